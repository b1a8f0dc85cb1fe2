#include "model/observations.h"

#include <numeric>

namespace thermocomp {

int Observations::ColumnIndex(const std::string& name) const {
  for (size_t j = 0; j < names.size(); ++j) {
    if (names[j] == name) return static_cast<int>(j);
  }
  return -1;
}

std::vector<int> Observations::AllRows() const {
  std::vector<int> rows(y.size());
  std::iota(rows.begin(), rows.end(), 0);
  return rows;
}

Observations Observations::Subset(const std::vector<int>& rows,
                                  const std::vector<std::string>& columns) const {
  Observations out;
  out.names = columns;
  out.x.resize(rows.size(), columns.size());
  out.y.resize(rows.size());
  std::vector<int> cols;
  cols.reserve(columns.size());
  for (const auto& c : columns) cols.push_back(ColumnIndex(c));
  for (size_t i = 0; i < rows.size(); ++i) {
    out.y(i) = y(rows[i]);
    for (size_t j = 0; j < cols.size(); ++j) out.x(i, j) = x(rows[i], cols[j]);
    out.group.push_back(group.empty() ? 0 : group[rows[i]]);
    if (!source.empty()) out.source.push_back(source[rows[i]]);
  }
  return out;
}

}  // namespace thermocomp
