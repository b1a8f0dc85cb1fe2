// Plate statistics (docs/model.md §15.1): a test plate bored with hole
// pairs, one hole of each pair with the compensation active, the other with
// it zeroed, and each hole's deviation measured on a CMM. Compared per
// plate and per nominal level (holes of one nominal Y, a row):
//   S = sample standard deviation (n - 1) of the deviations,
//   R = max - min of the deviations,
//   improvement = 1 - on/off (of S and of R),
// an F-test of S_off^2 / S_on^2 (one-sided, 1 %) that says whether the
// improvement is more than the scatter of two equal spreads would give,
// and the pay-off time: from which pair on compensation keeps paying.
// Pure values: no I/O, no clock.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/status.h"

namespace thermocomp {

// One measured hole, as the statistics need it.
struct PlateHoleValue {
  int pair = 0;
  double nominal_y_mm = 0;
  double dev_um = 0;  // the compared axis' deviation, µm
  bool compensated = false;
  int64_t bored_ms = 0;
};

// S and R of one set of deviations; NaN where there are too few (S needs
// two values, R one).
struct PlateSpread {
  int n = 0;
  double mean_um = 0;
  double s_um = 0;
  double r_um = 0;
};

struct PlateOnOff {
  PlateSpread on, off;
  double s_improvement = 0;  // 1 - S_on/S_off; NaN when S_off is 0 or unknown
  double r_improvement = 0;  // 1 - R_on/R_off; likewise
  double p_value = 0;        // of S_off^2/S_on^2 under equal spreads; NaN if unknown
  bool improves = false;     // p_value < kPlateSignificance
};

struct PlateLevel {
  double nominal_y_mm = 0;
  PlateOnOff on_off;
};

// One pair in bore order with its gain |dev_off| - |dev_on|.
struct PlatePair {
  int pair = 0;
  int64_t first_bored_ms = 0;  // the earlier of its two holes
  double on_um = 0, off_um = 0;
  double gain_um = 0;
};

struct PlateStatistics {
  PlateOnOff plate;
  std::vector<PlateLevel> levels;  // ascending nominal Y
  std::vector<PlatePair> pairs;    // in bore order
  int64_t first_bored_ms = 0, last_bored_ms = 0;
  // The pay-off (see PayOffPair): the pair and its first bore time.
  std::optional<int> pay_off_pair;
  std::optional<int64_t> pay_off_ms;
};

// A plate of pure noise claims an improvement this often.
inline constexpr double kPlateSignificance = 0.01;
// The pay-off threshold in units of S_on: a window of three pairs whose
// holes are noise alone gains more than 2 S_on about once in 30 000.
inline constexpr double kPayOffThresholdInSOn = 2.0;
// Consecutive pairs the pay-off rule averages over.
inline constexpr int kPayOffWindowPairs = 3;
// Nominal Y values closer than this are one level (a row of holes).
inline constexpr double kPlateLevelToleranceMm = 0.001;

// Sample standard deviation (n - 1); NaN for fewer than two values.
double SampleStdDev(const std::vector<double>& values);
// max - min; NaN for none.
double SpreadRange(const std::vector<double>& values);
PlateSpread SpreadOf(const std::vector<double>& values);
PlateOnOff CompareOnOff(const std::vector<double>& on_um, const std::vector<double>& off_um);

// The earliest pair k (index into `pairs`, bore order) such that every
// window of kPayOffWindowPairs consecutive pairs starting at k or later has
// a mean gain above `threshold_um` (ComputePlateStatistics: 2 S_on, twice
// the scatter compensation leaves), with at least one such window; nullopt
// if none.
std::optional<size_t> PayOffPair(const std::vector<PlatePair>& pairs, double threshold_um);

// The statistics of a plate. Every pair must hold exactly one compensated
// and one uncompensated hole (InvalidArgument otherwise; the service checks
// first and names the row).
StatusOr<PlateStatistics> ComputePlateStatistics(const std::vector<PlateHoleValue>& holes);

}  // namespace thermocomp
