// What the PostgreSQL backend adds beneath the shared stores: SQLite's
// placeholders rewritten, values that come back exactly as bound, the id of
// an insert, one partition of the readings per month, and a database that
// would sort names differently refused. The rewrite is checked everywhere;
// the rest on the server the test run starts (tests/test_database.h).
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <gtest/gtest.h>

#include "storage/postgresql/pg_storage.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

TEST(PlaceholdersTest, SqliteNumbersBecomeDenseDollarNumbers) {
  std::vector<int> index;
  EXPECT_EQ(RewritePlaceholders("SELECT ? , ?", &index), "SELECT $1 , $2");
  EXPECT_EQ(index, (std::vector<int>{0, 1, 2}));
  // ?N reused; unused numbers (?2, ?3 when a filter is absent) are no slot.
  EXPECT_EQ(RewritePlaceholders("id < ?1 AND ts >= ?4 AND x = ?4 LIMIT ?6", &index),
            "id < $1 AND ts >= $2 AND x = $2 LIMIT $3");
  EXPECT_EQ(index, (std::vector<int>{0, 1, 0, 0, 2, 0, 3}));
  // A bare ? after ?N is one more than the largest so far, as in SQLite.
  RewritePlaceholders("?3, ?", &index);
  EXPECT_EQ(index[4], 2);
  // Quoted text and comments keep their question marks.
  EXPECT_EQ(RewritePlaceholders("SELECT '?', \"a?\" -- why?\n, ?", &index),
            "SELECT '?', \"a?\" -- why?\n, $1");
}

class PostgresqlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::OnPostgresql()) GTEST_SKIP() << "needs the test run's PostgreSQL";
    ASSERT_NO_FATAL_FAILURE(postgres_.Create());
    auto storage = PgStorage::Open(postgres_.url());
    ASSERT_TRUE(storage.ok()) << storage.status().ToString();
    storage_ = std::move(storage).value();
  }
  testing::TestPostgresDatabase postgres_;
  std::unique_ptr<PgStorage> storage_;
};

TEST_F(PostgresqlTest, ValuesComeBackExactly) {
  storage_->WithConnection([](SqlConnection& db) {
    ASSERT_TRUE(db.Exec("CREATE TABLE v(i BIGINT, d DOUBLE PRECISION, t TEXT)").ok());
    const double values[] = {0.1, 1.0 / 3.0, -2.5e-300, 1.7976931348623157e308,
                             std::numeric_limits<double>::denorm_min()};
    for (double d : values) {
      SqlStatement ins(db, "INSERT INTO v VALUES (?, ?, ?)");
      ins.Bind(1, int64_t{-9007199254740993}).Bind(2, d).Bind(3, std::string("ä'?\\"));
      ASSERT_TRUE(ins.Run().ok()) << ins.status().ToString();
    }
    SqlStatement q(db, "SELECT i, d, t FROM v");
    for (double d : values) {
      ASSERT_TRUE(q.Step()) << q.status().ToString();
      EXPECT_EQ(q.Int(0), -9007199254740993);
      EXPECT_EQ(q.Double(1), d);  // bit for bit, not nearly
      EXPECT_EQ(q.Text(2), "ä'?\\");
    }
  });
}

TEST_F(PostgresqlTest, InsertIdsAndChangedRowsAsOnSqlite) {
  storage_->WithConnection([](SqlConnection& db) {
    SqlStatement ins(db, "INSERT INTO machines(name, created_ms, updated_ms) VALUES (?, 0, 0)");
    ins.Bind(1, std::string("a"));
    ASSERT_TRUE(ins.Run().ok());
    const int64_t first = db.LastInsertId();
    ins.Reset();
    ins.Bind(1, std::string("b"));
    ASSERT_TRUE(ins.Run().ok());
    EXPECT_EQ(db.LastInsertId(), first + 1);
    SqlStatement up(db, "UPDATE machines SET display_name = 'x'");
    ASSERT_TRUE(up.Run().ok());
    EXPECT_EQ(db.Changes(), 2);
    // A duplicate name is a Conflict, as SQLite's constraint error is.
    ins.Reset();
    ins.Bind(1, std::string("a"));
    EXPECT_EQ(ins.Run().code(), Status::Code::kConflict);
  });
}

TEST_F(PostgresqlTest, ReadingsGoToTheirMonthsPartition) {
  storage_->WithConnection([](SqlConnection& db) {
    // 2019-02-28T23:59:59.999Z and 2019-03-01T00:00:00Z: two months.
    for (int64_t ts : {int64_t{1551398399999}, int64_t{1551398400000}}) {
      ASSERT_TRUE(db.PrepareReadingsAt(ts).ok());
    }
    SqlStatement q(db,
                   "SELECT c.relname, pg_get_expr(c.relpartbound, c.oid) FROM pg_inherits i"
                   " JOIN pg_class c ON c.oid = i.inhrelid JOIN pg_class p ON p.oid = i.inhparent"
                   " WHERE p.relname = 'samples' AND c.relname LIKE 'samples_2019%'"
                   " ORDER BY c.relname");
    ASSERT_TRUE(q.Step());
    EXPECT_EQ(q.Text(0), "samples_201902");
    EXPECT_EQ(q.Text(1), "FOR VALUES FROM ('1548979200000') TO ('1551398400000')");
    ASSERT_TRUE(q.Step());
    EXPECT_EQ(q.Text(0), "samples_201903");
    EXPECT_FALSE(q.Step());
  });
}

// A transaction whose connection is lost is never finished on a new one:
// the statements after the loss fail, the commit fails, nothing of it is
// stored, and the next transaction connects again.
TEST_F(PostgresqlTest, ATransactionThatLosesItsConnectionLeavesNothing) {
  int64_t pid = 0;
  storage_->WithConnection([&](SqlConnection& db) {
    SqlStatement q(db, "SELECT pg_backend_pid()");
    ASSERT_TRUE(q.Step());
    pid = q.Int(0);
  });
  auto admin = PgConnection::Connect(postgres_.url());
  ASSERT_TRUE(admin.ok());
  MachineRecord m;
  m.name = "a";
  m.sensors = {{0, "T1", "", 0.2}};
  m.axes = {{0, "Y", 0.0, {"T1"}, 0.03}};
  {
    const std::unique_ptr<Session> session = storage_->Open();
    Transaction t(*session);
    ASSERT_TRUE(t.status().ok());
    ASSERT_TRUE(session->machines().Upsert(m, 0).ok());
    const std::string id = std::to_string(pid);
    ASSERT_TRUE((*admin)->Exec("SELECT pg_terminate_backend(" + id + ")").ok());
    // Termination is a signal: wait (up to 60 s) until the backend is gone.
    for (int i = 0; i < 600; ++i) {
      bool alive = true;
      (*admin)->Lock();
      {
        SqlStatement q(**admin, "SELECT 1 FROM pg_stat_activity WHERE pid = " + id);
        alive = q.Step();
      }
      (*admin)->Unlock();
      if (!alive) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    m.name = "b";
    EXPECT_FALSE(session->machines().Upsert(m, 0).ok());
    EXPECT_FALSE(t.Commit().ok());
  }
  const std::unique_ptr<Session> session = storage_->Open();
  EXPECT_FALSE(session->machines().Find("a").has_value());
  EXPECT_FALSE(session->machines().Find("b").has_value());
  {
    Transaction t(*session);
    ASSERT_TRUE(t.status().ok()) << t.status().ToString();
    m.name = "c";
    ASSERT_TRUE(session->machines().Upsert(m, 0).ok());
    ASSERT_TRUE(t.Commit().ok());
  }
  EXPECT_TRUE(session->machines().Find("c").has_value());
}

TEST_F(PostgresqlTest, ADatabaseSortingByLanguageIsRefused) {
  auto admin = PgConnection::Connect(postgres_.url());
  ASSERT_TRUE(admin.ok());
  const std::string name =
      "tc_locale_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed());
  ASSERT_TRUE(
      (*admin)
          ->Exec("CREATE DATABASE " + name +
                 " TEMPLATE template0 ENCODING 'UTF8' LOCALE_PROVIDER icu ICU_LOCALE 'de-DE'"
                 " LC_COLLATE 'C' LC_CTYPE 'C'")
          .ok());
  const std::string url = postgres_.url().substr(0, postgres_.url().rfind('/') + 1) + name;
  auto refused = PgStorage::Open(url);
  EXPECT_EQ(refused.status().code(), Status::Code::kFailedPrecondition);
  EXPECT_NE(refused.status().message().find("LC_COLLATE 'C'"), std::string::npos);
  (*admin)->Exec("DROP DATABASE " + name);
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

// The server restarted or failed over under a running thermocomp: its
// connection is gone. A request either finds out between transactions and
// connects again, or finds out in its transaction and is answered
// Unavailable (503 with Retry-After) with nothing of it stored; the next
// one is stored. Never another error, never a restart of thermocomp.
class PostgresqlLostConnectionTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    if (!testing::OnPostgresql()) GTEST_SKIP() << "needs the test run's PostgreSQL";
    AppFixture::SetUp();
  }
  void CutConnections() {
    auto admin = PgConnection::Connect(postgres_.url());
    ASSERT_TRUE(admin.ok());
    ASSERT_TRUE((*admin)
                    ->Exec("SELECT pg_terminate_backend(pid) FROM pg_stat_activity"
                           " WHERE datname = current_database() AND pid <> pg_backend_pid()")
                    .ok());
  }
};

TEST_F(PostgresqlLostConnectionTest, TheNextRequestConnectsAgain) {
  ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", nullptr).ok());
  auto sample = [&](int minute) {
    return std::vector<TemperatureInput>{{"Tcb", testing::kT0 + minute * 60000LL, 21.0}};
  };
  ASSERT_TRUE(app_->ingest().AddTemperatures("m1", sample(0), "test").status.ok());
  int stored = 1;
  for (int cut = 0; cut < 5; ++cut) {
    ASSERT_NO_FATAL_FAILURE(CutConnections());
    for (int attempt = 0;; ++attempt) {
      ASSERT_LT(attempt, 2) << "a second request after the cut still failed";
      const Status s =
          app_->ingest().AddTemperatures("m1", sample(10 * cut + attempt + 1), "test").status;
      if (s.ok()) {
        ++stored;
        break;
      }
      EXPECT_EQ(s.code(), Status::Code::kUnavailable) << s.ToString();
      EXPECT_NE(s.message().find("retry"), std::string::npos) << s.message();
    }
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), stored);
}

}  // namespace
}  // namespace thermocomp
