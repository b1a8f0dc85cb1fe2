// Tests use the repository's loopback DDS configuration, whatever the
// environment says.
#pragma once

#include <cstdlib>
#include <string>

namespace thermocomp::testing {

inline void UseRepoDdsConfig() {
  setenv("CYCLONEDDS_URI",
         ("file://" + std::string(THERMOCOMP_SOURCE_DIR) + "/deploy/cyclonedds.xml").c_str(), 1);
}

}  // namespace thermocomp::testing
