#include "model/parts/plate_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <boost/math/distributions/fisher_f.hpp>

namespace thermocomp {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// P(F >= f) for F(d1, d2): how likely an S_off^2/S_on^2 this large is when
// both holes' spreads are the same.
double UpperTail(double f, int d1, int d2) {
  if (!std::isfinite(f) || d1 < 1 || d2 < 1) return kNaN;
  if (f <= 0) return 1.0;
  const boost::math::fisher_f_distribution<double> dist(d1, d2);
  return boost::math::cdf(boost::math::complement(dist, f));
}

double Improvement(double on, double off) {
  if (!std::isfinite(on) || !std::isfinite(off) || off <= 0) return kNaN;
  return 1.0 - on / off;
}

}  // namespace

double SampleStdDev(const std::vector<double>& values) {
  if (values.size() < 2) return kNaN;
  double mean = 0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  double ss = 0;
  for (double v : values) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(values.size() - 1));
}

double SpreadRange(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return *hi - *lo;
}

PlateSpread SpreadOf(const std::vector<double>& values) {
  PlateSpread s;
  s.n = static_cast<int>(values.size());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean_um = values.empty() ? kNaN : sum / static_cast<double>(values.size());
  s.s_um = SampleStdDev(values);
  s.r_um = SpreadRange(values);
  return s;
}

PlateOnOff CompareOnOff(const std::vector<double>& on_um, const std::vector<double>& off_um) {
  PlateOnOff c;
  c.on = SpreadOf(on_um);
  c.off = SpreadOf(off_um);
  c.s_improvement = Improvement(c.on.s_um, c.off.s_um);
  c.r_improvement = Improvement(c.on.r_um, c.off.r_um);
  if (std::isfinite(c.on.s_um) && std::isfinite(c.off.s_um)) {
    const double var_on = c.on.s_um * c.on.s_um;
    const double var_off = c.off.s_um * c.off.s_um;
    // Both zero: nothing to compare; only the on side zero: as improved
    // as a spread can be.
    c.p_value = var_on > 0 ? UpperTail(var_off / var_on, c.off.n - 1, c.on.n - 1)
                           : (var_off > 0 ? 0.0 : kNaN);
  } else {
    c.p_value = kNaN;
  }
  c.improves = std::isfinite(c.p_value) && c.p_value < kPlateSignificance;
  return c;
}

std::optional<size_t> PayOffPair(const std::vector<PlatePair>& pairs, double threshold_um) {
  const size_t w = kPayOffWindowPairs;
  if (pairs.size() < w || !std::isfinite(threshold_um)) return std::nullopt;
  // Walk back from the last window; the answer is the start of the longest
  // run of passing windows that reaches the end.
  std::optional<size_t> first;
  for (size_t start = pairs.size() - w + 1; start-- > 0;) {
    double gain = 0;
    for (size_t i = start; i < start + w; ++i) gain += pairs[i].gain_um;
    if (gain / static_cast<double>(w) <= threshold_um) break;
    first = start;
  }
  return first;
}

StatusOr<PlateStatistics> ComputePlateStatistics(const std::vector<PlateHoleValue>& holes) {
  if (holes.empty()) return Status::InvalidArgument("a plate needs holes");
  PlateStatistics out;
  struct PairHoles {
    const PlateHoleValue* on = nullptr;
    const PlateHoleValue* off = nullptr;
  };
  std::map<int, PairHoles> by_pair;
  std::vector<double> on, off;
  on.reserve(holes.size());
  off.reserve(holes.size());
  // Levels keyed by nominal Y; values within the tolerance share a key.
  std::map<double, std::pair<std::vector<double>, std::vector<double>>> levels;
  out.first_bored_ms = holes.front().bored_ms;
  out.last_bored_ms = holes.front().bored_ms;
  for (const auto& h : holes) {
    if (!std::isfinite(h.dev_um) || !std::isfinite(h.nominal_y_mm)) {
      return Status::InvalidArgument("pair " + std::to_string(h.pair) + ": a value is not finite");
    }
    PairHoles& p = by_pair[h.pair];
    const PlateHoleValue*& slot = h.compensated ? p.on : p.off;
    if (slot) {
      return Status::InvalidArgument("pair " + std::to_string(h.pair) + " has two " +
                                     (h.compensated ? "on" : "off") + " holes");
    }
    slot = &h;
    (h.compensated ? on : off).push_back(h.dev_um);
    auto level = levels.lower_bound(h.nominal_y_mm - kPlateLevelToleranceMm);
    if (level == levels.end() || level->first > h.nominal_y_mm + kPlateLevelToleranceMm) {
      level =
          levels
              .emplace(h.nominal_y_mm, std::make_pair(std::vector<double>{}, std::vector<double>{}))
              .first;
    }
    (h.compensated ? level->second.first : level->second.second).push_back(h.dev_um);
    out.first_bored_ms = std::min(out.first_bored_ms, h.bored_ms);
    out.last_bored_ms = std::max(out.last_bored_ms, h.bored_ms);
  }
  out.pairs.reserve(by_pair.size());
  for (const auto& [pair, p] : by_pair) {
    if (!p.on || !p.off) {
      return Status::InvalidArgument("pair " + std::to_string(pair) + " lacks an " +
                                     (p.on ? "off" : "on") + " hole");
    }
    PlatePair pp;
    pp.pair = pair;
    pp.first_bored_ms = std::min(p.on->bored_ms, p.off->bored_ms);
    pp.on_um = p.on->dev_um;
    pp.off_um = p.off->dev_um;
    pp.gain_um = std::abs(pp.off_um) - std::abs(pp.on_um);
    out.pairs.push_back(pp);
  }
  std::stable_sort(out.pairs.begin(), out.pairs.end(), [](const PlatePair& a, const PlatePair& b) {
    return a.first_bored_ms != b.first_bored_ms ? a.first_bored_ms < b.first_bored_ms
                                                : a.pair < b.pair;
  });
  out.plate = CompareOnOff(on, off);
  out.levels.reserve(levels.size());
  for (const auto& [y, values] : levels) {
    out.levels.push_back({y, CompareOnOff(values.first, values.second)});
  }
  if (auto k = PayOffPair(out.pairs, kPayOffThresholdInSOn * out.plate.on.s_um)) {
    out.pay_off_pair = out.pairs[*k].pair;
    out.pay_off_ms = out.pairs[*k].first_bored_ms;
  }
  return out;
}

}  // namespace thermocomp
