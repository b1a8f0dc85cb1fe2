// The database lock is held by a Session and nowhere else: a store works
// only inside its session, a second session waits for the first, and a
// write is one transaction on a session.
#include "storage/storage.h"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDir();
    storage_ = testing::OpenTestStorage(dir_, postgres_);
    ASSERT_TRUE(storage_);
  }
  void TearDown() override {
    storage_.reset();
    std::filesystem::remove_all(dir_);
  }
  static MachineRecord Machine(const std::string& name) {
    MachineRecord m;
    m.name = name;
    m.sensors = {{0, "T1", "", 0.2}};
    m.axes = {{0, "Y", 0.0, {"T1"}, 0.03}};
    return m;
  }
  std::filesystem::path dir_;
  testing::TestPostgresDatabase postgres_;  // on PostgreSQL: dropped after storage_ closed it
  std::unique_ptr<Storage> storage_;
};

TEST_F(SessionTest, AStoreWorksOnlyWhileItsSessionHoldsTheLock) {
  std::unique_ptr<Session> session = storage_->Open();
  MachineStore& machines = session->machines();
  ASSERT_TRUE(machines.Upsert(Machine("m1"), 0).ok());
  ASSERT_EQ(machines.List().size(), 1u);

  session->Pause();
  // Used without the lock, the store refuses instead of racing others.
  EXPECT_FALSE(machines.Upsert(Machine("m2"), 0).ok());
  EXPECT_TRUE(machines.List().empty());

  session->Resume();
  EXPECT_EQ(machines.List().size(), 1u);
}

TEST_F(SessionTest, ASecondSessionWaitsUntilTheFirstEnds) {
  std::unique_ptr<Session> first = storage_->Open();
  std::atomic<bool> opened{false};
  std::thread other([&] {
    std::unique_ptr<Session> second = storage_->Open();
    opened = true;
    // The first session's write is visible: it committed before letting go.
    EXPECT_EQ(second->machines().List().size(), 1u);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(opened.load());
  ASSERT_TRUE(first->machines().Upsert(Machine("m1"), 0).ok());
  first.reset();
  other.join();
  EXPECT_TRUE(opened.load());
}

TEST_F(SessionTest, ATransactionNotCommittedLeavesNothing) {
  std::unique_ptr<Session> session = storage_->Open();
  {
    Transaction tx(*session);
    ASSERT_TRUE(tx.status().ok());
    ASSERT_TRUE(session->machines().Upsert(Machine("m1"), 0).ok());
  }
  EXPECT_TRUE(session->machines().List().empty());
  {
    Transaction tx(*session);
    ASSERT_TRUE(session->machines().Upsert(Machine("m1"), 0).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }
  EXPECT_EQ(session->machines().List().size(), 1u);
}

}  // namespace
}  // namespace thermocomp
