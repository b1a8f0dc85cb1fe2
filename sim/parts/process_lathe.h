// A simulated lathe for part-error models from the process (docs/model.md
// §15): turned features cut at random settings of depth of cut ap (mm),
// feed f (mm/rev) and cutting speed vc (m/min) while the machine warms and
// cools, each with a measured size error whose truth is known:
//
//   size_error_um = 3 (ap − 1.5) + 2 (ap − 1.5)² + 30 (f − 0.2) + 150 (f − 0.2)²
//                   − 0.02 (vc − 200) + 20 (ap − 1.5)(f − 0.2)
//                   + 1.5 (temperature_c − 25) + noise (σ = noise_um)
//   cylindricity_um = |2 + 20 f + 1.5 (ap − 1.5)² + noise (σ = noise_um / 2)|
//   roundness_um    = |1 + 0.5 f · vc / 100 + noise (σ = noise_um / 2)|
//
// The passive force fp_n is logged but has no effect on either: a ranking
// must drop it. With nothing_to_find the errors are noise about a constant
// (size 5 µm, σ = 2 noise_um; the form errors folded at zero), whatever the inputs: no model may
// claim to predict them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace thermocomp {

struct SimProcessRecord {
  std::string part, feature;
  int64_t cut_ms = 0;
  std::map<std::string, double> values;  // the inputs and the measured errors
};

struct SimLatheOptions {
  uint64_t seed = 1;
  int records = 200;
  int64_t start_ms = 0;  // the first cut; one every 10 minutes
  double noise_um = 1.0;
  bool nothing_to_find = false;
};

// The ranges the settings are drawn from (the guard's tests go outside).
inline constexpr double kLatheApMm[2] = {0.5, 2.5};
inline constexpr double kLatheFeedMmRev[2] = {0.05, 0.35};
inline constexpr double kLatheVcMMin[2] = {120, 280};
inline constexpr double kLatheTemperatureC[2] = {20, 30};

// The noise-free size error at a setting.
double LatheTruthSizeErrorUm(double ap_mm, double f_mm_rev, double vc_m_min, double temperature_c);

std::vector<SimProcessRecord> SimulateLathe(const SimLatheOptions& options);

// The records as the process-records CSV (docs/api.md): part, feature,
// cut_at, ap_mm, f_mm_rev, vc_m_min, fp_n, temperature_c, size_error_um,
// cylindricity_um, roundness_um.
std::string LatheCsv(const std::vector<SimProcessRecord>& records);

}  // namespace thermocomp
