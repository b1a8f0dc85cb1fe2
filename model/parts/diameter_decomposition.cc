#include "model/parts/diameter_decomposition.h"

#include <cstdlib>

#include "model/parts/diameter_decimal.h"

namespace thermocomp {

DiameterComponents Decompose(const FourDiameters& d) {
  // A diameter difference in nm is the radial component in half-nm.
  DiameterComponents c;
  c.f_half_nm = d.w_nm - d.des_nm;
  c.th_half_nm = d.c_nm - d.w_nm;
  c.g_half_nm = d.pp_nm - d.c_nm;
  c.tot_half_nm = d.pp_nm - d.des_nm;
  return c;
}

std::optional<double> ThermalShare(const DiameterComponents& c) {
  const int64_t sum = std::llabs(c.f_half_nm) + std::llabs(c.th_half_nm) + std::llabs(c.g_half_nm);
  if (sum == 0) return std::nullopt;
  return static_cast<double>(std::llabs(c.th_half_nm)) / static_cast<double>(sum);
}

ComponentSummary Summarize(const std::vector<DiameterComponents>& parts) {
  ComponentSummary s;
  s.count = static_cast<int64_t>(parts.size());
  if (parts.empty()) return s;
  // Sums as integers (exact): 10^6 parts of 1 mm are 2·10^12 half-nm.
  int64_t f = 0, th = 0, g = 0, tot = 0, abs_f = 0, abs_th = 0, abs_g = 0;
  for (const DiameterComponents& c : parts) {
    f += c.f_half_nm;
    th += c.th_half_nm;
    g += c.g_half_nm;
    tot += c.tot_half_nm;
    abs_f += std::llabs(c.f_half_nm);
    abs_th += std::llabs(c.th_half_nm);
    abs_g += std::llabs(c.g_half_nm);
  }
  const auto n = static_cast<double>(s.count);
  s.mean_f_um = HalfNmToUm(f) / n;
  s.mean_th_um = HalfNmToUm(th) / n;
  s.mean_g_um = HalfNmToUm(g) / n;
  s.mean_tot_um = HalfNmToUm(tot) / n;
  s.mean_abs_th_um = HalfNmToUm(abs_th) / n;
  const int64_t all = abs_f + abs_th + abs_g;
  if (all > 0) s.thermal_share = static_cast<double>(abs_th) / static_cast<double>(all);
  return s;
}

ShareTrend ShareOverTime(const std::vector<int64_t>& ts_ms,
                         const std::vector<std::optional<double>>& shares) {
  ShareTrend t;
  constexpr double kPeriodMs = 30.0 * 86400000.0;
  double mean_x = 0, mean_y = 0;
  int64_t n = 0;
  const int64_t origin = ts_ms.empty() ? 0 : ts_ms.front();
  for (size_t i = 0; i < ts_ms.size() && i < shares.size(); ++i) {
    if (!shares[i]) continue;
    ++n;
    const double x = static_cast<double>(ts_ms[i] - origin) / kPeriodMs;
    mean_x += (x - mean_x) / static_cast<double>(n);
    mean_y += (*shares[i] - mean_y) / static_cast<double>(n);
  }
  t.parts = n;
  if (n < 3) return t;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < ts_ms.size() && i < shares.size(); ++i) {
    if (!shares[i]) continue;
    const double dx = static_cast<double>(ts_ms[i] - origin) / kPeriodMs - mean_x;
    sxx += dx * dx;
    sxy += dx * (*shares[i] - mean_y);
  }
  if (sxx > 0) t.slope_per_30_days = sxy / sxx;
  return t;
}

}  // namespace thermocomp
