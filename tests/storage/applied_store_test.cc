// AppliedStore on SQLite and PostgreSQL: each axis keeps its newest kAppliedKeptPerAxis
// records, the oldest going as new ones come, and the newest and the
// history are read per axis, newest first.
#include "storage/storage.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "storage/applied_store.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class AppliedStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDir();
    storage_ = testing::OpenTestStorage(dir_, postgres_);
    ASSERT_TRUE(storage_);
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "T1", "", 0.2}};
    m.axes = {{0, "X", 0.0, {"T1"}, 0.03}, {0, "Y", 0.0, {"T1"}, 0.03}};
    const std::unique_ptr<Session> session = storage_->Open();
    ASSERT_TRUE(session->machines().Upsert(m, 0).ok());
    const MachineRecord stored = *session->machines().Find("m1");
    x_ = stored.axes[0].id;
    y_ = stored.axes[1].id;
  }
  void TearDown() override {
    storage_.reset();
    std::filesystem::remove_all(dir_);
  }
  static AppliedRecord Record(int64_t sequence) {
    AppliedRecord r;
    r.sequence = sequence;
    r.applied_at_ms = 1000 * sequence;
    r.offset_mm = -0.001 * static_cast<double>(sequence % 10);
    r.via = "opcua";
    r.actor = "token:cell-1";
    return r;
  }
  std::filesystem::path dir_;
  testing::TestPostgresDatabase postgres_;  // on PostgreSQL: dropped after storage_ closed it
  std::unique_ptr<Storage> storage_;
  int64_t x_ = 0, y_ = 0;
};

TEST_F(AppliedStoreTest, EachAxisKeepsItsNewestRecords) {
  const std::unique_ptr<Session> session = storage_->Open();
  AppliedStore& store = session->applied();
  EXPECT_FALSE(store.Newest(y_).has_value());
  ASSERT_TRUE(store.Append(x_, Record(1)).ok());
  {
    Transaction tx(*session);
    for (int64_t s = 1; s <= kAppliedKeptPerAxis + 5; ++s)
      ASSERT_TRUE(store.Append(y_, Record(s)).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }
  const std::optional<AppliedRecord> newest = store.Newest(y_);
  ASSERT_TRUE(newest.has_value());
  EXPECT_EQ(newest->sequence, kAppliedKeptPerAxis + 5);
  EXPECT_EQ(newest->applied_at_ms, 1000 * (kAppliedKeptPerAxis + 5));
  EXPECT_EQ(newest->via, "opcua");
  EXPECT_EQ(newest->actor, "token:cell-1");
  EXPECT_FALSE(newest->slope_um_per_m.has_value());
  const std::vector<AppliedRecord> all =
      store.History(y_, 2 * static_cast<int>(kAppliedKeptPerAxis));
  ASSERT_EQ(static_cast<int64_t>(all.size()), kAppliedKeptPerAxis);
  EXPECT_EQ(all.front().sequence, kAppliedKeptPerAxis + 5);
  EXPECT_EQ(all.back().sequence, 6);  // the five oldest went
  // The other axis keeps its own.
  ASSERT_EQ(store.History(x_, 10).size(), 1u);
  EXPECT_EQ(store.Newest(x_)->sequence, 1);
}

}  // namespace
}  // namespace thermocomp
