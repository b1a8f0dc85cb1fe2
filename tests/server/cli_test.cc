// The thermocomp command line refuses bad options with a message and exit 1.
#include <sys/wait.h>

#include <cstdio>
#include <string>

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

}  // namespace
}  // namespace thermocomp
