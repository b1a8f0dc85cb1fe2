// The outbox on the line (SQLite) and the centre that applies it (SQLite
// here, PostgreSQL in the pg: run): rows as written, once, mapped to the
// centre's ids under the plant's names.
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "service/config.h"
#include "service/shipping/shipper.h"
#include "storage/sql/shipping/centre_store.h"
#include "storage/sql/shipping/shipped_tables.h"
#include "tests/shipping/shipping_util.h"
#include "tests/test_database.h"

namespace thermocomp {
namespace {

using testing::ExecOn;
using testing::ScalarOf;
using testing::TextOf;

// A line archive with a machine, its sensors, an axis, readings, an audit
// entry and a column check that closed its request.
constexpr const char* kLineRows =
    "INSERT INTO machines (id, name, created_ms, updated_ms) VALUES (1, 'm1', 1, 1);"
    "INSERT INTO sensors (id, machine_id, name, ewma_alpha) VALUES (1, 1, 'T1', 0.5),"
    " (2, 1, 'T2', 0.5);"
    "INSERT INTO axes (id, machine_id, name) VALUES (1, 1, 'Y');"
    "INSERT INTO samples (sensor_id, ts_ms, value, filtered) VALUES"
    " (1, 1700000000000, 0.1 + 0.2, 20.5), (2, 1700000000000, 21.25, 21.0),"
    " (1, 1700000060000, 1e-300, -1.5e-7);"
    "INSERT INTO audit (ts_ms, actor, action, machine, count) VALUES (5, 'op', 'put', 'm1', 1),"
    " (6, 'op', 'tokens', NULL, 0);"
    "INSERT INTO check_requests (id, machine_id, reason, created_ms, due_ms) VALUES"
    " (1, 1, 'weekly', 5, 9);"
    "INSERT INTO column_checks (id, machine_id, request_id, ts_ms, artifact, temperature_c,"
    " zero_x_mm, zero_y_mm, zero_z_mm, result_json) VALUES (1, 1, 1, 1700000000000, 'col-1',"
    " 20.1, 0.001, -0.002, 0.003, '{}');"
    "UPDATE check_requests SET check_id = 1, done_ms = 10 WHERE id = 1;";

class ShippingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::ShippingTempDir();
    auto line = SqliteStorage::OpenFile((dir_ / "line.db").string());
    ASSERT_TRUE(line.ok()) << line.status().ToString();
    line_ = std::move(line).value();
    with_line_ = testing::RunnerOf(line_.get());
  }
  void TearDown() override {
    line_.reset();
    std::filesystem::remove_all(dir_);
  }
  Status Enable(ShippingSwitch* outcome) {
    Status s;
    with_line_([&](SqlConnection& db) { s = EnableShipping(db, outcome); });
    return s;
  }
  std::vector<ShippedRow> ReadAll() {
    SqlOutbox outbox(with_line_);
    std::vector<ShippedRow> rows;
    EXPECT_TRUE(outbox.Read(0, 100000, &rows).ok());
    return rows;
  }

  std::filesystem::path dir_;
  std::unique_ptr<SqliteStorage> line_;
  WithSqlConnection with_line_;
};

TEST_F(ShippingTest, TheListsNameEveryColumnOfEachShippedTableInOrder) {
  for (const ShippedTable& t : ShippedTables()) {
    std::vector<std::string> columns;
    with_line_([&](SqlConnection& db) {
      SqlStatement st(db, "SELECT name FROM pragma_table_info('" + t.name + "') ORDER BY cid");
      while (st.Step()) columns.push_back(st.Text(0));
    });
    EXPECT_EQ(columns, t.columns) << t.name;
    EXPECT_EQ(t.has_id, !columns.empty() && columns[0] == "id") << t.name;
    EXPECT_LE(static_cast<int>(columns.size()), kOutboxColumns) << t.name;
  }
}

TEST_F(ShippingTest, SwitchingOnCopiesTheArchiveThenEveryWriteAsWritten) {
  ExecOn(with_line_, kLineRows);
  ShippingSwitch on;
  ASSERT_TRUE(Enable(&on).ok());
  EXPECT_TRUE(on.snapshot);
  // 1 machine, 2 sensors, 1 axis, 3 samples, 2 audit, 1 request (+1 again
  // for its forward reference), 1 check.
  EXPECT_EQ(on.snapshot_rows, 12);
  std::vector<ShippedRow> rows = ReadAll();
  ASSERT_EQ(rows.size(), 12u);
  EXPECT_EQ(rows.front().table, "machines");
  EXPECT_EQ(rows.back().table, "check_requests");
  for (size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i].seq, rows[i - 1].seq + 1);

  // Values keep their type and every bit.
  const ShippedRow& first_sample = rows[4];
  ASSERT_EQ(first_sample.table, "samples");
  ASSERT_EQ(first_sample.values[2].kind, ShippedValue::Kind::kReal);
  EXPECT_EQ(first_sample.values[2].d, 0.1 + 0.2);
  EXPECT_EQ(first_sample.values[1].kind, ShippedValue::Kind::kInt);
  EXPECT_EQ(first_sample.values[1].i, 1700000000000);
  const ShippedRow& tiny = rows[5];  // samples in key order: (1, t0), (1, t1), (2, t0)
  EXPECT_EQ(tiny.values[2].d, 1e-300);
  EXPECT_EQ(tiny.values[3].d, -1.5e-7);
  EXPECT_EQ(rows[10].table, "audit");
  EXPECT_EQ(rows[10].values[4].kind, ShippedValue::Kind::kNull);  // without a machine

  // Writes after: an insert, an update, a duplicate reading ignored.
  ExecOn(with_line_,
         "INSERT INTO samples (sensor_id, ts_ms, value, filtered) VALUES (2, 1700000060000, 22, "
         "21.5); UPDATE machines SET display_name = 'Mill 1' WHERE id = 1;"
         "INSERT OR IGNORE INTO samples (sensor_id, ts_ms, value, filtered) VALUES"
         " (2, 1700000060000, 99, 99)");
  rows = ReadAll();
  ASSERT_EQ(rows.size(), 14u);
  EXPECT_EQ(rows[12].table, "samples");
  EXPECT_EQ(rows[12].values[2].d, 22.0);
  EXPECT_EQ(rows[13].table, "machines");
  EXPECT_EQ(rows[13].values[2].text, "Mill 1");

  // A second start makes the triggers again and copies nothing.
  ShippingSwitch again;
  ASSERT_TRUE(Enable(&again).ok());
  EXPECT_FALSE(again.snapshot);
  EXPECT_EQ(ReadAll().size(), 14u);

  SqlOutbox outbox(with_line_);
  OutboxBacklog backlog;
  ASSERT_TRUE(outbox.Backlog(&backlog).ok());
  EXPECT_EQ(backlog.rows, 14);
  EXPECT_EQ(backlog.last_seq, rows.back().seq);
  EXPECT_GT(backlog.oldest_stored_ms, 1700000000000);
  ASSERT_TRUE(outbox.Acknowledge("north", rows[9].seq).ok());
  ASSERT_TRUE(outbox.Backlog(&backlog).ok());
  EXPECT_EQ(backlog.rows, 4);
  // The numbers go on after the acknowledged rows are gone.
  ASSERT_TRUE(outbox.Acknowledge("north", rows.back().seq).ok());
  ExecOn(with_line_, "INSERT INTO audit (ts_ms, actor, action) VALUES (7, 'op', 'x')");
  std::vector<ShippedRow> after;
  ASSERT_TRUE(outbox.Read(0, 10, &after).ok());
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].seq, rows.back().seq + 1);

  // Switched off: the triggers go, the outbox is emptied.
  ShippingSwitch off;
  with_line_([&](SqlConnection& db) { ASSERT_TRUE(DisableShipping(db, &off).ok()); });
  EXPECT_EQ(off.dropped_rows, 1);
  ExecOn(with_line_, "INSERT INTO audit (ts_ms, actor, action) VALUES (8, 'op', 'y')");
  EXPECT_EQ(ScalarOf(with_line_, "SELECT COUNT(*) FROM outbox"), 0);
  EXPECT_EQ(ScalarOf(with_line_, "SELECT COUNT(*) FROM sqlite_master WHERE type = 'trigger'"), 0);
}

class CentreTest : public ShippingTest {
 protected:
  void SetUp() override {
    ShippingTest::SetUp();
    std::filesystem::create_directories(dir_ / "centre");
    centre_storage_ = testing::OpenTestStorage(dir_ / "centre", postgres_);
    ASSERT_NE(centre_storage_, nullptr);
    with_centre_ = testing::RunnerOf(centre_storage_.get());
  }
  void TearDown() override {
    centre_storage_.reset();
    ShippingTest::TearDown();
  }
  int64_t Centre(const std::string& sql) { return ScalarOf(with_centre_, sql); }

  testing::TestPostgresDatabase postgres_;
  std::unique_ptr<Storage> centre_storage_;
  WithSqlConnection with_centre_;
};

TEST_F(CentreTest, AppliesEachRowOnceUnderThePlantsNames) {
  ExecOn(with_line_, kLineRows);
  ShippingSwitch on;
  ASSERT_TRUE(Enable(&on).ok());
  std::vector<ShippedRow> rows = ReadAll();
  SqlCentre centre(with_centre_);
  int64_t applied = 0;
  ASSERT_TRUE(centre.Applied("north", &applied).ok());
  EXPECT_EQ(applied, 0);
  Status s = centre.Apply("north", rows, &applied);
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(applied, rows.back().seq);

  EXPECT_EQ(TextOf(with_centre_, "SELECT name FROM machines"), "north.m1");
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples"), 3);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples s JOIN sensors n ON n.id = s.sensor_id JOIN"
                   " machines m ON m.id = n.machine_id WHERE m.name = 'north.m1'"),
            3);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples WHERE value = CAST(0.1 AS DOUBLE PRECISION) +"
                   " CAST(0.2 AS DOUBLE PRECISION)"),
            1);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit WHERE machine = 'north.m1'"), 1);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit WHERE machine IS NULL"), 1);
  // The request's forward reference, shipped again at the end, is resolved.
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM check_requests r JOIN column_checks c ON c.id ="
                   " r.check_id AND c.request_id = r.id"),
            1);

  // The same batch again (acknowledgement lost): nothing changes.
  int64_t again = 0;
  ASSERT_TRUE(centre.Apply("north", rows, &again).ok());
  EXPECT_EQ(again, applied);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit"), 2);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM check_requests"), 1);

  // A later update lands on the same row.
  SqlOutbox outbox(with_line_);
  ASSERT_TRUE(outbox.Acknowledge("north", applied).ok());
  ExecOn(with_line_,
         "UPDATE machines SET display_name = 'Mill 1' WHERE id = 1;"
         "INSERT INTO audit (ts_ms, actor, action, machine) VALUES (9, 'op', 'x', 'm1')");
  std::vector<ShippedRow> more;
  ASSERT_TRUE(outbox.Read(applied, 100, &more).ok());
  ASSERT_EQ(more.size(), 2u);
  ASSERT_TRUE(centre.Apply("north", more, &applied).ok());
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM machines"), 1);
  EXPECT_EQ(TextOf(with_centre_, "SELECT display_name FROM machines"), "Mill 1");
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit"), 3);

  // Another plant's m1 is a machine of its own; its ids do not mix with north's.
  SqlCentre south(with_centre_);
  ASSERT_TRUE(south.Apply("south", rows, &again).ok());
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM machines"), 2);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples s JOIN sensors n ON n.id = s.sensor_id JOIN"
                   " machines m ON m.id = n.machine_id WHERE m.name = 'south.m1'"),
            3);
  ASSERT_TRUE(centre.Applied("north", &again).ok());
  EXPECT_EQ(again, applied);
}

TEST_F(CentreTest, KeyedRowsTakeTheirLastImageAndTextComesThroughExactly) {
  ExecOn(with_line_, kLineRows);
  ShippingSwitch on;
  ASSERT_TRUE(Enable(&on).ok());
  const std::string json =
      R"({"screw": "a \"quoted\" name", "path": "C:\\lead\\screw", "n": [1, 2]})";
  with_line_([&](SqlConnection& db) {
    SqlStatement st(db,
                    "INSERT INTO feed_axis_configs (axis_id, config_json, updated_ms) VALUES"
                    " (1, ?1, 5)");
    st.Bind(1, std::string_view(json));
    ASSERT_TRUE(st.Run().ok());
  });
  // A reading written, then its filtered value replayed twice, in one batch.
  ExecOn(with_line_,
         "INSERT INTO samples (sensor_id, ts_ms, value, filtered) VALUES (2, 1700000120000, 23,"
         " 22); UPDATE samples SET filtered = 22.5 WHERE sensor_id = 2 AND ts_ms = 1700000120000;"
         "UPDATE samples SET filtered = 22.75 WHERE sensor_id = 2 AND ts_ms = 1700000120000;"
         "INSERT INTO axes (id, machine_id, name) VALUES (2, 1, 'X');"
         "INSERT INTO compensation_log (axis_id, ts_ms, offset_mm, predicted_drift_mm, valid,"
         " clamped, model_version) VALUES (2, 1700000120000, -0.0125, 0.0125, 1, 0, NULL)");
  SqlCentre centre(with_centre_);
  int64_t applied = 0;
  const Status s = centre.Apply("north", ReadAll(), &applied);
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(TextOf(with_centre_, "SELECT config_json FROM feed_axis_configs"), json);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples"), 4);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples WHERE ts_ms = 1700000120000 AND filtered ="
                   " 22.75"),
            1);
  // The served value of an axis that came in the same batch, after the
  // axis: the order that matters is kept.
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM compensation_log c JOIN axes a ON a.id = c.axis_id"
                   " WHERE a.name = 'X' AND c.model_version IS NULL AND c.offset_mm = -0.0125"),
            1);
}

TEST_F(CentreTest, ACentreThatLostRowsOrAnotherArchiveOfThePlantIsRefusedForGood) {
  ExecOn(with_line_, kLineRows);
  ShippingSwitch on;
  ASSERT_TRUE(Enable(&on).ok());
  SqlOutbox outbox(with_line_);
  ShippingBoard board;
  Shipper::Options options;
  options.plant = "north";
  const Shipper::Connect connect = [this]() -> StatusOr<std::unique_ptr<thermocomp::Centre>> {
    return std::unique_ptr<thermocomp::Centre>(std::make_unique<SqlCentre>(with_centre_));
  };
  auto ship = [&](int64_t* n) {
    Shipper shipper(outbox, connect, board, options);  // a fresh start each time
    return shipper.ShipBatch(n);
  };
  int64_t n = 0;
  ASSERT_TRUE(ship(&n).ok());
  EXPECT_EQ(n, 12);
  const std::string progress = "SELECT seq FROM ship_progress WHERE plant = 'north'";
  EXPECT_EQ(ScalarOf(with_line_, progress), Centre(progress));

  // The centre goes back (a failover to a standby that was behind): the
  // rows it lost are gone from the outbox, so shipping stops, loudly.
  ExecOn(with_centre_, "UPDATE ship_progress SET seq = seq - 5");
  ExecOn(with_line_, "INSERT INTO audit (ts_ms, actor, action) VALUES (7, 'op', 'x')");
  Status s = ship(&n);
  EXPECT_EQ(s.code(), Status::Code::kFailedPrecondition) << s.ToString();
  EXPECT_NE(s.message().find("lost rows"), std::string::npos) << s.message();
  EXPECT_NE(board.Render().find("thermocomp_shipping_refused 1"), std::string::npos);
  // Put right at the centre, it stays refused until switched off and on.
  ExecOn(with_centre_, "UPDATE ship_progress SET seq = seq + 5");
  s = ship(&n);
  EXPECT_NE(s.message().find("was refused"), std::string::npos) << s.message();
  ShippingSwitch off;
  with_line_([&](SqlConnection& db) { ASSERT_TRUE(DisableShipping(db, &off).ok()); });
  ASSERT_TRUE(Enable(&on).ok());
  ASSERT_TRUE(ship(&n).ok());
  EXPECT_EQ(n, 13);  // the archive again, met on ids and keys
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit"), 3);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM machines"), 1);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples"), 3);

  // Another archive under the same plant name, however many rows it
  // writes afterwards.
  auto other = SqliteStorage::OpenFile((dir_ / "other.db").string());
  ASSERT_TRUE(other.ok());
  WithSqlConnection with_other = testing::RunnerOf(other->get());
  ExecOn(with_other, kLineRows);
  with_other([&](SqlConnection& db) { ASSERT_TRUE(EnableShipping(db, &on).ok()); });
  SqlOutbox other_outbox(with_other);
  auto ship_other = [&](int64_t* shipped) {
    Shipper shipper(other_outbox, connect, board, options);
    return shipper.ShipBatch(shipped);
  };
  s = ship_other(&n);
  EXPECT_NE(s.message().find("another archive"), std::string::npos) << s.message();
  for (int i = 0; i < 40; ++i) {
    ExecOn(with_other, "INSERT INTO audit (ts_ms, actor, action) VALUES (" + std::to_string(i) +
                           ", 'op', 'y')");
  }
  s = ship_other(&n);
  EXPECT_NE(s.message().find("was refused"), std::string::npos) << s.message();
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM audit"), 3);
}

TEST_F(CentreTest, ABatchThatFailsLeavesTheCentreAsItWas) {
  ExecOn(with_line_, kLineRows);
  ShippingSwitch on;
  ASSERT_TRUE(Enable(&on).ok());
  std::vector<ShippedRow> rows = ReadAll();
  // A reading of a sensor the centre has never been sent: refused whole.
  std::vector<ShippedRow> broken(rows.begin(), rows.begin() + 6);
  broken.erase(broken.begin() + 1, broken.begin() + 3);  // without the sensors
  SqlCentre centre(with_centre_);
  int64_t applied = 0;
  Status s = centre.Apply("north", broken, &applied);
  EXPECT_EQ(s.code(), Status::Code::kFailedPrecondition) << s.ToString();
  EXPECT_NE(s.message().find("sensors"), std::string::npos) << s.message();
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM machines"), 0);
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM ship_ids"), 0);
  ASSERT_TRUE(centre.Applied("north", &applied).ok());
  EXPECT_EQ(applied, 0);
  // The whole outbox then goes through.
  ASSERT_TRUE(centre.Apply("north", rows, &applied).ok());
  EXPECT_EQ(Centre("SELECT COUNT(*) FROM samples"), 3);
}

TEST_F(ShippingTest, TheCentreKeysAreCheckedWhenTheConfigurationLoads) {
  auto load = [&](const std::string& text) {
    std::ofstream((dir_ / "c.toml").string()) << text;
    auto c = LoadConfig((dir_ / "c.toml").string());
    return c.ok() ? std::string("accepted") : c.status().message();
  };
  const std::string url = "[centre]\nurl = \"postgresql://u@127.0.0.1:5432/centre\"\n";
  EXPECT_EQ(load(url + "plant = \"north\"\nbatch_rows = 100\n"), "accepted");
  EXPECT_NE(load(url).find("centre.plant"), std::string::npos);
  EXPECT_NE(load(url + "plant = \"north.a\"\n").find("centre.plant"), std::string::npos);
  EXPECT_NE(load(url + "plant = \"a-name-longer-than-16\"\n").find("centre.plant"),
            std::string::npos);
  EXPECT_NE(load("[centre]\nurl = \"http://centre\"\nplant = \"n\"\n").find("centre.url"),
            std::string::npos);
  EXPECT_NE(load(url + "plant = \"n\"\n[server]\nread_only = true\n").find("read-only"),
            std::string::npos);
  EXPECT_NE(load(url + "plant = \"n\"\nbatch_rows = 0\n").find("centre.batch_rows"),
            std::string::npos);
}

}  // namespace
}  // namespace thermocomp
