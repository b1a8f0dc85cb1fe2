// The thermocomp command line refuses bad options with a message and exit 1.
#include <sys/wait.h>

#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "core/time_units.h"

namespace thermocomp {
namespace {

// Runs the binary with `args`; returns exit status and combined output.
std::pair<int, std::string> RunThermocomp(const std::string& args) {
  std::string out;
  // Appended, not a chain of operator+: GCC 12 reports a false
  // -Warray-bounds inside such a chain when it inlines it (GCC PR 105651).
  std::string command(THERMOCOMP_BINARY);
  command.append(" ").append(args).append(" 2>&1");
  FILE* p = popen(command.c_str(), "r");
  char buf[512];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? pclose(p) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// The JSON document among a command's output and its log lines.
nlohmann::json JsonIn(const std::string& out) {
  const size_t first = out.find('{'), last = out.rfind('}');
  if (first == std::string::npos || last == std::string::npos) return nullptr;
  return nlohmann::json::parse(out.substr(first, last - first + 1), nullptr, false);
}

TEST(CliTest, NonNumericOptionIsAClearError) {
  auto [code, out] = RunThermocomp("simulate --days ten --out /tmp/thermocomp-cli-never");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("an option that takes a number got something else"), std::string::npos) << out;
}

TEST(CliTest, OutOfRangeNumberIsAClearError) {
  auto [code, out] = RunThermocomp("simulate --live --speed 1e999");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("out of range"), std::string::npos) << out;
}

TEST(CliTest, AHiddenEffectNamesAKnownEffectAndAMachine) {
  auto [code, out] = RunThermocomp("simulate --hidden lag@ --out /tmp/thermocomp-cli-never");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("--hidden: 'lag@' names no machine after '@'"), std::string::npos) << out;
  std::tie(code, out) = RunThermocomp("demo --db /tmp/thermocomp-cli-never.db --hidden leg@sim-2");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("--hidden: unknown effect 'leg'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists("/tmp/thermocomp-cli-never.db"));
}

TEST(CliTest, ASensorFaultNamesAKindAKnownSensorAndAMachine) {
  const std::pair<const char*, const char*> cases[] = {
      {"Tco", "is not KIND:SENSOR[@MACHINE]"},
      {"leak:Tco", "unknown kind 'leak'"},
      {"drift:Tfoo", "unknown sensor 'Tfoo'"},
      {"lost_contact:Tenv", "Tenv is the shop air a loose sensor reads"},
      {"step:Tco@", "names no machine after '@'"},
      {"drift@m1:Tco", "is not KIND:SENSOR[@MACHINE]"},
      {"step:Tco,drift:Tco@m1", "Tco fails twice on m1"}};
  for (const auto& [fault, said] : cases) {
    auto [code, out] =
        RunThermocomp(std::string("simulate --db /tmp/thermocomp-cli-never.db --fault ") + fault);
    EXPECT_EQ(code, 1) << fault;
    EXPECT_NE(out.find(said), std::string::npos) << out;
  }
  EXPECT_FALSE(std::filesystem::exists("/tmp/thermocomp-cli-never.db"));
}

// `simulate --end` fixes when the history ends (the same recording at any
// time of day); it must be a time, and a live simulation has none.
TEST(CliTest, ASimulatedHistoryEndsAtTheGivenTime) {
  const std::string dir = "/tmp/thermocomp-cli-end-" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  ASSERT_EQ(RunThermocomp("simulate --machines m1 --days 2 --end 2026-03-04T12:00:00Z --out " + dir)
                .first,
            0);
  FILE* f = std::fopen((dir + "/m1_temperatures.csv").c_str(), "r");
  ASSERT_NE(f, nullptr);
  char line[256];
  std::string first, last;
  while (std::fgets(line, sizeof line, f)) {
    if (first.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) first = line;
    last = line;
  }
  std::fclose(f);
  // From midnight two days before the end's day, minute by minute, to the end.
  EXPECT_EQ(first.substr(0, 24), "2026-03-02T00:01:00.000Z") << first;
  EXPECT_EQ(last.substr(0, 24), "2026-03-04T12:00:00.000Z") << last;
  std::filesystem::remove_all(dir);

  auto [code, out] =
      RunThermocomp("simulate --db /tmp/thermocomp-cli-never.db --create --end yesterday");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("--end: not an RFC 3339 time ('yesterday')"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists("/tmp/thermocomp-cli-never.db"));
  // Times ingest would refuse are refused before the database is made.
  const std::pair<const char*, const char*> refused[] = {
      {"2999-01-01T00:00:00Z", "--end: in the future"},
      {"2000-01-03T00:00:00Z", "--end: the history would begin before 2000-01-01"}};
  for (const auto& [end, said] : refused) {
    std::tie(code, out) = RunThermocomp(
        std::string("simulate --db /tmp/thermocomp-cli-never.db --create --days 14 --end ") + end);
    EXPECT_EQ(code, 1) << end;
    EXPECT_NE(out.find(said), std::string::npos) << out;
    EXPECT_FALSE(std::filesystem::exists("/tmp/thermocomp-cli-never.db")) << end;
  }
  std::tie(code, out) = RunThermocomp("simulate --live --end 2026-03-04T12:00:00Z");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("--end: a live simulation runs from now on"), std::string::npos) << out;
}

// A fault given to `simulate` is in the readings the database keeps: the
// analysis names the sensor, its kind and its onset, two thirds in.
TEST(CliTest, ASimulatedSensorFaultIsNamedByTheAnalysis) {
  const std::string dir = "/tmp/thermocomp-cli-fault-" + std::to_string(getpid());
  const std::string db = dir + "/t.db";
  // Midnight UTC 12 days before today (read on both sides of the command,
  // which may straddle a midnight), then 8 days in.
  const auto onset = [] { return FormatRfc3339((NowUnixMs() / kDayMs - 12 + 8) * kDayMs); };
  const std::string onset_before = onset();
  ASSERT_EQ(RunThermocomp("simulate --db " + db +
                          " --create --machines m1,m2 --days 12 --fault step:Tco@m2")
                .first,
            0);
  auto [code, out] = RunThermocomp("analyze --db " + db + " --machine m2 --axis Y --format json");
  ASSERT_EQ(code, 0) << out;
  const auto report = JsonIn(out);
  ASSERT_EQ(report["sensor_faults"].size(), 1u) << out;
  EXPECT_EQ(report["sensor_faults"][0]["sensor"], "Tco");
  EXPECT_EQ(report["sensor_faults"][0]["kind"], "step");
  const std::string found = report["sensor_faults"][0]["onset"];
  EXPECT_TRUE(found == onset_before || found == onset()) << found;
  std::tie(code, out) =
      RunThermocomp("analyze --db " + db + " --machine m1 --axis Y --format json");
  ASSERT_EQ(code, 0) << out;
  EXPECT_TRUE(JsonIn(out)["sensor_faults"].empty()) << out;
  std::filesystem::remove_all(dir);
}

TEST(CliTest, UnknownCommandIsAUsageError) {
  auto [code, out] = RunThermocomp("frobnicate");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("unknown command 'frobnicate'"), std::string::npos) << out;
}

TEST(CliTest, UnknownOptionsAndStrayArgumentsAreUsageErrors) {
  auto [code, out] = RunThermocomp("serve --halp");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("unknown option --halp"), std::string::npos) << out;
  std::tie(code, out) = RunThermocomp("fit --machine m1 extra");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("unexpected argument 'extra'"), std::string::npos) << out;
  std::tie(code, out) = RunThermocomp("fit --machine");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("--machine needs a value"), std::string::npos) << out;
  // --help explains the command and starts nothing.
  std::tie(code, out) = RunThermocomp("serve --help");
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("--listen"), std::string::npos) << out;
}

TEST(CliTest, AMistypedDatabasePathCreatesNothing) {
  const std::string dir = "/tmp/thermocomp-cli-typo-" + std::to_string(getpid());
  const std::string db = " --db " + dir + "/nonexist.db";
  const std::string backup = "backup " + dir + "/copy.db";
  for (const std::string& cmd : {backup + db, "fit --machine m1" + db, "analyze --machine m1" + db,
                                 "import --machine m1 --temperatures /dev/null" + db}) {
    auto [code, out] = RunThermocomp(cmd);
    EXPECT_EQ(code, 1) << cmd;
    EXPECT_NE(out.find("does not exist"), std::string::npos) << cmd << ": " << out;
    EXPECT_NE(access(dir.c_str(), F_OK), 0) << cmd << " created " << dir;
  }
  // With --create it is made, directory and all.
  auto [code, out] =
      RunThermocomp("simulate --db " + dir + "/new.db --create --machines m1 --days 1");
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(access((dir + "/new.db").c_str(), F_OK), 0);
  std::system(("rm -rf " + dir).c_str());
}

TEST(CliTest, AnalyzeAndPositioningImportWorkOnADatabase) {
  const std::string dir = "/tmp/thermocomp-cli-" + std::to_string(getpid());
  const std::string db = dir + "/t.db";
  ASSERT_EQ(
      RunThermocomp("simulate --db " + db + " --create --machines m1 --days 6 --hidden position")
          .first,
      0);
  auto [code, out] =
      RunThermocomp("analyze --db " + db + " --machine m1 --axis Y --format markdown");
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("# Effect analysis"), std::string::npos) << out;
  EXPECT_NE(out.find("pos(Y)*Tcb"), std::string::npos) << out;
  {
    FILE* f = fopen((dir + "/laser.csv").c_str(), "w");
    ASSERT_TRUE(f);
    fputs(
        "target_mm,run,direction,deviation_um\n0,1,+,1\n1000,1,+,-1\n1000,2,-,2\n0,2,-,0\n"
        "0,3,+,3\n1000,3,+,-1\n1000,4,-,4\n0,4,-,2\n",
        f);
    fclose(f);
  }
  std::tie(code, out) = RunThermocomp("import --db " + db + " --machine m1 --positioning " + dir +
                                      "/laser.csv --axis Y --ts 2026-03-10T08:00:00Z");
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("A 7.66 um, E 4.00 um, R 6.83 um, B 4.00 um"), std::string::npos) << out;
  std::tie(code, out) = RunThermocomp("import --db " + db + " --machine m1 --positioning " + dir +
                                      "/laser.csv --axis Y");
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("--ts"), std::string::npos) << out;

  // Continuous displacement goes in as it is: 15-s samples, runs by gaps.
  {
    FILE* f = fopen((dir + "/displacement.csv").c_str(), "w");
    ASSERT_TRUE(f);
    fputs("ts,dev_Y\n", f);
    for (int i = 0; i < 240; ++i)
      fprintf(f, "%lld,%.6f\n", 1772352000000LL + i * 15000LL, i * 1e-5);
    for (int i = 0; i < 240; ++i)
      fprintf(f, "%lld,%.6f\n", 1772438400000LL + i * 15000LL, i * 1e-5);
    fclose(f);
  }
  std::tie(code, out) = RunThermocomp("import --db " + db + " --machine m1 --displacements " + dir +
                                      "/displacement.csv");
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("displacements: 480 accepted, 0 duplicates"), std::string::npos) << out;
  std::tie(code, out) = RunThermocomp("import --db " + db + " --machine m1 --displacements " + dir +
                                      "/displacement.csv --run-gap-min 0");
  EXPECT_EQ(code, 1) << out;
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace thermocomp
