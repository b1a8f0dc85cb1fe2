// The scheduled backups on a real directory with a manual clock: one file
// per period under its UTC name, the newest `keep` kept, other files never
// touched, an existing name never overwritten, a restart not backing up
// before it is due.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/clock.h"
#include "service/operations/backup_schedule.h"
#include "storage/sqlite/sqlite_storage.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

namespace fs = std::filesystem;

constexpr int64_t kHour = 3600 * 1000;
// 2026-11-25T06:00:00Z
constexpr int64_t kStart = 1795586400000;

std::string ReadFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void Write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

int64_t Machines(const fs::path& db) {
  auto opened = Database::Open(db.string(), {.create = false});
  if (!opened.ok()) return -1;
  Statement q((*opened)->handle(), "SELECT COUNT(*) FROM machines");
  return q.Step() ? q.Int(0) : -1;
}

class BackupScheduleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDir();
    backups_ = dir_ / "backups";
    fs::create_directories(backups_);
    auto storage = SqliteStorage::OpenFile((dir_ / "thermocomp.db").string());
    ASSERT_TRUE(storage.ok()) << storage.status().ToString();
    storage_ = std::move(storage).value();
    storage_->WithConnection([](Database& db) {
      ASSERT_TRUE(
          db.Exec("INSERT INTO machines(name, created_ms, updated_ms) VALUES ('m1', 1, 1)").ok());
    });
  }
  void TearDown() override {
    storage_.reset();
    fs::remove_all(dir_);
  }
  BackupSchedule::Options Options(int keep) const {
    return {backups_.string(), /*every_h=*/24, keep, /*retry_after_ms=*/10 * 60 * 1000};
  }

  fs::path dir_, backups_;
  std::unique_ptr<SqliteStorage> storage_;
  ManualClock clock_{kStart};
};

TEST_F(BackupScheduleTest, NamesAreUtcTimesAndOnlyThePatternIsOwn) {
  EXPECT_EQ(BackupSchedule::FileName(kStart), "thermocomp-20261125T060000Z.db");
  EXPECT_EQ(BackupSchedule::TimeOfName("thermocomp-20261125T060000Z.db"), kStart / 1000);
  for (const char* other :
       {"thermocomp-20261125T060000Z.db.bak", "thermocomp-latest.db",
        "thermocomp-20261399T000000Z.db", "xthermocomp-20261125T060000Z.db",
        "thermocomp-20261125T060000Z.db-wal", ".thermocomp-20261125T060000Z.db.partial-abc123"}) {
    EXPECT_FALSE(BackupSchedule::TimeOfName(other).has_value()) << other;
  }
}

TEST_F(BackupScheduleTest, KeepsTheNewestAndLeavesOtherFilesAlone) {
  const std::map<std::string, std::string> foreign = {
      {"notes.txt", "the operator's notes"},
      {"thermocomp-latest.db", "a copy someone made by hand"},
      {"thermocomp-20200101T000000Z.db.bak", "renamed away by hand"}};
  for (const auto& [name, text] : foreign) Write(backups_ / name, text);
  fs::create_directories(backups_ / "thermocomp-20200102T000000Z.db");  // a directory, not a file

  BackupSchedule schedule(*storage_, clock_, Options(3));
  std::vector<std::string> expected;
  for (int day = 0; day < 6; ++day) {
    ASSERT_TRUE(schedule.Due()) << "day " << day;
    ASSERT_TRUE(schedule.Tick().ok()) << "day " << day;
    expected.push_back(BackupSchedule::FileName(clock_.NowMs()));
    // Not again within the period.
    clock_.Advance(23 * kHour);
    EXPECT_FALSE(schedule.Due());
    EXPECT_TRUE(schedule.Tick().ok());
    clock_.Advance(kHour);
  }
  const std::vector<std::string> newest(expected.end() - 3, expected.end());
  EXPECT_EQ(schedule.OwnFiles(), newest);
  for (const auto& name : newest) {
    EXPECT_EQ(Machines(backups_ / name), 1) << name;  // a complete database
  }
  for (const auto& [name, text] : foreign) EXPECT_EQ(ReadFile(backups_ / name), text) << name;
  EXPECT_TRUE(fs::is_directory(backups_ / "thermocomp-20200102T000000Z.db"));
  // Nothing half-written left behind.
  for (const auto& entry : fs::directory_iterator(backups_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
}

TEST_F(BackupScheduleTest, AnExistingNameIsNeverOverwritten) {
  BackupSchedule schedule(*storage_, clock_, Options(7));
  ASSERT_TRUE(schedule.Tick().ok());
  clock_.Advance(24 * kHour);
  const fs::path taken = backups_ / BackupSchedule::FileName(clock_.NowMs());
  Write(taken, "not a backup, but it has the name");
  const Status s = schedule.Tick();
  EXPECT_EQ(s.code(), Status::Code::kConflict) << s.ToString();
  EXPECT_EQ(ReadFile(taken), "not a backup, but it has the name");
  // Retried after the pause, under the time's new name.
  clock_.Advance(5 * 60 * 1000);
  EXPECT_FALSE(schedule.Due());
  clock_.Advance(5 * 60 * 1000);
  ASSERT_TRUE(schedule.Tick().ok());
  EXPECT_EQ(Machines(backups_ / BackupSchedule::FileName(clock_.NowMs())), 1);
  EXPECT_EQ(ReadFile(taken), "not a backup, but it has the name");
}

TEST_F(BackupScheduleTest, ARestartWaitsForTheNewestBackupToAge) {
  {
    BackupSchedule first(*storage_, clock_, Options(7));
    ASSERT_TRUE(first.Tick().ok());
  }
  clock_.Advance(10 * kHour);
  BackupSchedule second(*storage_, clock_, Options(7));
  EXPECT_FALSE(second.Due());
  ASSERT_TRUE(second.Tick().ok());
  EXPECT_EQ(second.OwnFiles().size(), 1U);
  clock_.Advance(14 * kHour);
  EXPECT_TRUE(second.Due());
  ASSERT_TRUE(second.Tick().ok());
  EXPECT_EQ(second.OwnFiles().size(), 2U);
}

TEST_F(BackupScheduleTest, AFailureIsReportedAndTheThreadGoesOn) {
  BackupSchedule::Options o = Options(7);
  o.dir = (dir_ / "missing").string();
  BackupSchedule schedule(*storage_, clock_, o);
  EXPECT_FALSE(schedule.Tick().ok());
  // On its thread: ticks and stops without taking the process down.
  schedule.Start(std::chrono::milliseconds(5));
  schedule.Stop();
  fs::create_directories(dir_ / "missing");
  clock_.Advance(11 * 60 * 1000);
  EXPECT_TRUE(schedule.Tick().ok());
  EXPECT_EQ(schedule.OwnFiles().size(), 1U);
}

}  // namespace
}  // namespace thermocomp
