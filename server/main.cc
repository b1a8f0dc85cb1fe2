// thermocomp: one binary, several subcommands (see Usage()).
#include <cstdio>
#include <string>
#include <vector>

#include "server/commands.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::fputs(thermocomp::Usage().c_str(), stdout);
    return args.empty() ? 2 : 0;
  }
  return thermocomp::RunCommand(args[0], {args.begin() + 1, args.end()});
}
