// The thermocomp command line refuses bad options with a message and exit 1.
#include <sys/wait.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

// Runs the binary with `args`; returns exit status and combined output.
std::pair<int, std::string> RunThermocomp(const std::string& args) {
  std::string out;
  FILE* p = popen((std::string(THERMOCOMP_BINARY) + " " + args + " 2>&1").c_str(), "r");
  char buf[512];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? pclose(p) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
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

TEST(CliTest, UnknownCommandIsAUsageError) {
  auto [code, out] = RunThermocomp("frobnicate");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("unknown command 'frobnicate'"), std::string::npos) << out;
}

TEST(CliTest, AnalyzeAndPositioningImportWorkOnADatabase) {
  const std::string dir = "/tmp/thermocomp-cli-" + std::to_string(getpid());
  const std::string db = dir + "/t.db";
  ASSERT_EQ(
      RunThermocomp("simulate --db " + db + " --machines m1 --days 6 --hidden position").first, 0);
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
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace thermocomp
