// The cells of one CSV line as the part-test parsers read them: split at
// every comma (no quoting: names and numbers only), each cell without
// surrounding blanks and a trailing CR.
#pragma once

#include <string_view>
#include <vector>

namespace thermocomp::api {

inline std::string_view TrimCell(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

inline std::vector<std::string_view> CsvCells(std::string_view line) {
  std::vector<std::string_view> cells;
  size_t c = 0;
  while (true) {
    const size_t comma = line.find(',', c);
    cells.push_back(TrimCell(line.substr(c, comma == std::string_view::npos ? comma : comma - c)));
    if (comma == std::string_view::npos) return cells;
    c = comma + 1;
  }
}

}  // namespace thermocomp::api
