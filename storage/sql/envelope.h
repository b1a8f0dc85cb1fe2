// Reading an hourly envelope (compensation_rollup, sample_rollup): each
// row holds an hour's lowest and highest point; a plot wants them as
// points in time order, inside the asked range, without repeats.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "storage/sql/connection.h"

namespace thermocomp {

// Steps `q`, whose columns are min_ts_ms, min, max_ts_ms, max, ordered by hour.
inline std::vector<std::pair<int64_t, double>> ReadEnvelope(SqlStatement& q, int64_t from_ms,
                                                            int64_t to_ms) {
  std::vector<std::pair<int64_t, double>> out;
  while (q.Step()) {
    std::pair<int64_t, double> lo{q.Int(0), q.Double(1)}, hi{q.Int(2), q.Double(3)};
    if (hi.first < lo.first) std::swap(lo, hi);
    for (const auto& p : {lo, hi}) {
      if (p.first < from_ms || p.first > to_ms) continue;
      if (out.empty() || out.back().first != p.first) out.push_back(p);
    }
  }
  return out;
}

}  // namespace thermocomp
