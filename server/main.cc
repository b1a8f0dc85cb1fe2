// thermocomp: one binary, several subcommands (see Usage()).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/version.h"
#include "server/commands.h"
#include "storage/sqlite/migrator.h"

namespace {

// "thermocomp 0.1.0 (git 4a29387)" and the newest database schema this
// program migrates to, so a plant can tell which build and schema it runs.
int PrintVersion() {
  std::printf("thermocomp %s", thermocomp::build::kVersion);
  if (*thermocomp::build::kGitDescribe) std::printf(" (git %s)", thermocomp::build::kGitDescribe);
  int schema = 0;
  for (const auto& m : thermocomp::EmbeddedMigrations()) schema = std::max(schema, m.version);
  std::printf("\ndatabase schema %d\n", schema);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::fputs(thermocomp::Usage().c_str(), stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version" || args[0] == "version") return PrintVersion();
  return thermocomp::RunCommand(args[0], {args.begin() + 1, args.end()});
}
