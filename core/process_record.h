// A process record: one turned feature, where it was cut, the settings and
// logged signals it was cut with and the errors measured on it
// (docs/api.md, "Part-error models"). A record of the archive that the
// parsers, the part-model service and the store share, so it lives here.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace thermocomp {

// The numeric columns of a process record, in table order; the first three
// are required, the rest may be absent (not logged, not measured).
inline const std::vector<std::string>& ProcessRecordFields() {
  static const std::vector<std::string> fields = {
      "ap_mm",       "f_mm_rev",        "vc_m_min",      "fc_n",          "ff_n",
      "fp_n",        "displacement_um", "temperature_c", "size_error_um", "cylindricity_um",
      "roundness_um"};
  return fields;
}

struct ProcessRecordRow {
  int64_t id = 0;
  std::string part, feature;
  int64_t cut_ms = 0;
  std::map<std::string, double> values;  // ProcessRecordFields() present
};

}  // namespace thermocomp
