// Helpers shared by the tests: paths of checked-in data and the reference
// values computed by R (tests/reference/fms_reference.R).
#pragma once

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "model/observations.h"

namespace thermocomp::testing {

// Built with AddressSanitizer (the sanitizer build): memory is shadowed and
// freed blocks are held in quarantine, so peak-memory bounds do not apply.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif
#else
inline constexpr bool kUnderSanitizer = false;
#endif

inline std::string SourcePath(const std::string& rel) {
  return std::string(THERMOCOMP_SOURCE_DIR) + "/" + rel;
}

// key -> value of tests/reference/fms_reference.txt ("key value" lines).
inline std::map<std::string, std::string> LoadReference() {
  std::map<std::string, std::string> out;
  std::ifstream in(SourcePath("tests/reference/fms_reference.txt"));
  std::string key, value;
  while (in >> key >> value) out[key] = value;
  return out;
}

// The study data set as Observations of the Y axis (or X with column 11).
inline Observations LoadStudy(bool y_axis = true) {
  std::ifstream in(SourcePath("deploy/demo/fms_datum_drift.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  std::vector<double> ys;
  std::vector<int> groups;
  std::map<std::string, int> run_index;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (cells.size() != 12) continue;
    std::vector<double> x;
    for (int c = 2; c < 10; ++c) x.push_back(std::stod(cells[c]));
    rows.push_back(x);
    ys.push_back(std::stod(cells[y_axis ? 10 : 11]));
    groups.push_back(run_index.emplace(cells[1], static_cast<int>(run_index.size())).first->second);
  }
  Observations obs;
  obs.names = {"dT_co", "dT_cl", "dT_x1", "dT_x2", "dT_env", "dT_y1", "dT_y2", "dT_z"};
  obs.x.resize(rows.size(), 8);
  obs.y.resize(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    for (int j = 0; j < 8; ++j) obs.x(i, j) = rows[i][j];
    obs.y(i) = ys[i];
  }
  obs.group = groups;
  return obs;
}

}  // namespace thermocomp::testing
