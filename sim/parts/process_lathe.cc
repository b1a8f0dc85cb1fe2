#include "sim/parts/process_lathe.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/time_format.h"

namespace thermocomp {
namespace {

// Draws we define ourselves, the same on every standard library.
class Draw {
 public:
  explicit Draw(uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  }
  double Normal() {  // Box–Muller
    const double u = Uniform(1e-12, 1.0), v = Uniform(0.0, 1.0);
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * M_PI * v);
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace

double LatheTruthSizeErrorUm(double ap_mm, double f_mm_rev, double vc_m_min, double temperature_c) {
  const double a = ap_mm - 1.5, f = f_mm_rev - 0.2;
  return 3 * a + 2 * a * a + 30 * f + 150 * f * f - 0.02 * (vc_m_min - 200) + 20 * a * f +
         1.5 * (temperature_c - 25);
}

std::vector<SimProcessRecord> SimulateLathe(const SimLatheOptions& o) {
  Draw draw(o.seed);
  std::vector<SimProcessRecord> out;
  out.reserve(static_cast<size_t>(std::max(0, o.records)));
  for (int i = 0; i < o.records; ++i) {
    SimProcessRecord r;
    char part[32];
    std::snprintf(part, sizeof part, "P%04d", i / 2 + 1);
    r.part = part;
    r.feature = i % 2 == 0 ? "D1" : "D2";
    r.cut_ms = o.start_ms + int64_t{i} * 600000;
    const double ap = draw.Uniform(kLatheApMm[0], kLatheApMm[1]);
    const double f = draw.Uniform(kLatheFeedMmRev[0], kLatheFeedMmRev[1]);
    const double vc = draw.Uniform(kLatheVcMMin[0], kLatheVcMMin[1]);
    // The machine warms over a shift and cools between shifts: a slow
    // cycle, with a random spread so that settings and temperature do not
    // move together.
    const double phase = 2.0 * M_PI * static_cast<double>(i) / 48.0;
    const double temperature = std::clamp(25.0 + 4.0 * std::sin(phase) + draw.Uniform(-1.0, 1.0),
                                          kLatheTemperatureC[0], kLatheTemperatureC[1]);
    const double fp = draw.Uniform(50, 150);
    r.values = {{"ap_mm", ap},
                {"f_mm_rev", f},
                {"vc_m_min", vc},
                {"fp_n", fp},
                {"temperature_c", temperature}};
    if (o.nothing_to_find) {
      r.values["size_error_um"] = 5.0 + 2.0 * o.noise_um * draw.Normal();
      // Form errors are not negative: the noise folds at zero.
      r.values["cylindricity_um"] = std::fabs(3.0 + o.noise_um * draw.Normal());
      r.values["roundness_um"] = std::fabs(2.0 + o.noise_um * draw.Normal());
    } else {
      r.values["size_error_um"] =
          LatheTruthSizeErrorUm(ap, f, vc, temperature) + o.noise_um * draw.Normal();
      r.values["cylindricity_um"] =
          std::fabs(2 + 20 * f + 1.5 * (ap - 1.5) * (ap - 1.5) + 0.5 * o.noise_um * draw.Normal());
      r.values["roundness_um"] =
          std::fabs(1 + 0.5 * f * vc / 100 + 0.5 * o.noise_um * draw.Normal());
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::string LatheCsv(const std::vector<SimProcessRecord>& records) {
  static const char* kColumns[] = {
      "ap_mm",         "f_mm_rev",      "vc_m_min",        "fp_n",
      "temperature_c", "size_error_um", "cylindricity_um", "roundness_um"};
  std::string csv = "part,feature,cut_at";
  for (const char* c : kColumns) csv += std::string(",") + c;
  csv += "\n";
  for (const SimProcessRecord& r : records) {
    csv += r.part + "," + r.feature + "," + FormatRfc3339(r.cut_ms);
    for (const char* c : kColumns) {
      char buf[40];
      std::snprintf(buf, sizeof buf, ",%.6g", r.values.at(c));
      csv += buf;
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace thermocomp
