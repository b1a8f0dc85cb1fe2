// The thermocomp subcommands: serve, import, fit, analyze, simulate, demo, backup,
// restore.
// Each returns a process exit code (0 ok, 1 failed, 2 usage).
#pragma once

#include <string>
#include <vector>

namespace thermocomp {

std::string Usage();
int RunCommand(const std::string& name, const std::vector<std::string>& raw);

}  // namespace thermocomp
