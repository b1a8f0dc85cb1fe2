// The four-diameter decomposition of a turned feature (docs/model.md §15):
// D_des the drawing, D_w on the machine right after the cut, D_c on the
// machine after cooling, D_pp off the machine. Radially,
//   δf   = (D_w  − D_des)/2   force and deflection,
//   δth  = (D_c  − D_w)/2     thermal,
//   δg   = (D_pp − D_c)/2     geometric and other,
//   δtot = (D_pp − D_des)/2 = δf + δth + δg.
// Diameters are whole nm and components whole half-nm, so the sum is exact
// (model/parts/diameter_decimal.h). Pure values, no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace thermocomp {

struct FourDiameters {
  int64_t des_nm = 0, w_nm = 0, c_nm = 0, pp_nm = 0;
};

struct DiameterComponents {
  int64_t f_half_nm = 0, th_half_nm = 0, g_half_nm = 0, tot_half_nm = 0;
};

DiameterComponents Decompose(const FourDiameters& d);

// The thermal share of a feature's error: |δth| / (|δf| + |δth| + |δg|), in
// [0, 1]; nullopt when all three are zero (a perfect part has no share).
// Magnitudes, not signs: a thermal +10 µm and a force −10 µm that cancel in
// δtot are still half thermal, and that half is what compensation removes.
std::optional<double> ThermalShare(const DiameterComponents& c);

// A group of parts (a feature's history, a week, before or after a
// compensation change): means in µm and the share of the group as a ratio
// of sums, Σ|δth| / Σ(|δf| + |δth| + |δg|), so a nearly perfect part does
// not weigh as much as a bad one. Shares nullopt when undefined.
struct ComponentSummary {
  int64_t count = 0;
  double mean_f_um = 0, mean_th_um = 0, mean_g_um = 0, mean_tot_um = 0;
  double mean_abs_th_um = 0;
  std::optional<double> thermal_share;
};
ComponentSummary Summarize(const std::vector<DiameterComponents>& parts);

// How the per-part thermal share moves over time: the least-squares slope
// of share against time, per 30 days, over the parts that have a share
// (nullopt with fewer than 3 such parts or all at one time).
struct ShareTrend {
  int64_t parts = 0;  // parts with a share
  std::optional<double> slope_per_30_days;
};
ShareTrend ShareOverTime(const std::vector<int64_t>& ts_ms,
                         const std::vector<std::optional<double>>& shares);

}  // namespace thermocomp
