// Tests use the repository's loopback DDS configuration, whatever the
// environment says.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace thermocomp::testing {

// A DDS domain of this test process's own, so tests running in parallel
// (or any other DDS process on the machine) never match each other.
inline uint32_t TestDomain() {
  return 1 + static_cast<uint32_t>(getpid()) % 200;
}

inline void UseRepoDdsConfig() {
  setenv("CYCLONEDDS_URI",
         ("file://" + std::string(THERMOCOMP_SOURCE_DIR) + "/deploy/cyclonedds.xml").c_str(), 1);
}

}  // namespace thermocomp::testing
