#include "model/positioning_check.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {
namespace {

struct MeanSd {
  double mean = 0, sd = 0;
};

// Mean and sample standard deviation (divisor n - 1) of column i.
MeanSd Column(const std::vector<const PositioningRun*>& runs, size_t i) {
  MeanSd r;
  const double n = static_cast<double>(runs.size());
  for (const auto* run : runs) r.mean += run->deviations_um[i];
  r.mean /= n;
  double ss = 0;
  for (const auto* run : runs)
    ss += (run->deviations_um[i] - r.mean) * (run->deviations_um[i] - r.mean);
  r.sd = std::sqrt(ss / (n - 1.0));
  return r;
}

}  // namespace

Status ValidatePositioning(const PositioningData& d) {
  if (d.targets_mm.size() < 2) return Status::InvalidArgument("targets_mm: at least 2 targets");
  for (size_t i = 0; i < d.targets_mm.size(); ++i) {
    if (!std::isfinite(d.targets_mm[i])) return Status::InvalidArgument("targets_mm: not finite");
    if (i > 0 && !(d.targets_mm[i] > d.targets_mm[i - 1])) {
      return Status::InvalidArgument("targets_mm: must be strictly increasing (target " +
                                     std::to_string(i) + ")");
    }
  }
  int up = 0, down = 0;
  for (size_t r = 0; r < d.runs.size(); ++r) {
    const auto& run = d.runs[r];
    if (run.direction != 1 && run.direction != -1) {
      return Status::InvalidArgument("runs[" + std::to_string(r) + "].direction: + or -");
    }
    (run.direction > 0 ? up : down)++;
    if (run.deviations_um.size() != d.targets_mm.size()) {
      return Status::InvalidArgument("runs[" + std::to_string(r) + "].deviations_um: " +
                                     std::to_string(run.deviations_um.size()) + " values for " +
                                     std::to_string(d.targets_mm.size()) + " targets");
    }
    for (double v : run.deviations_um) {
      if (!std::isfinite(v)) {
        return Status::InvalidArgument("runs[" + std::to_string(r) + "].deviations_um: not finite");
      }
    }
  }
  if (up < 2 || down < 2) {
    return Status::InvalidArgument("runs: at least 2 runs in each direction (got " +
                                   std::to_string(up) + " up, " + std::to_string(down) + " down)");
  }
  return Status::Ok();
}

StatusOr<PositioningEvaluation> EvaluatePositioning(const PositioningData& d,
                                                    const UncertaintyInputs& inputs) {
  if (Status s = ValidatePositioning(d); !s.ok()) return s;
  std::vector<const PositioningRun*> up, down;
  for (const auto& run : d.runs) (run.direction > 0 ? up : down).push_back(&run);
  PositioningEvaluation out;
  Iso230Result& iso = out.iso;
  iso.runs_per_direction = static_cast<int>(std::min(up.size(), down.size()));
  double max_up_hi = -HUGE_VAL, min_up_lo = HUGE_VAL, max_dn_hi = -HUGE_VAL, min_dn_lo = HUGE_VAL;
  double max_up = -HUGE_VAL, min_up = HUGE_VAL, max_dn = -HUGE_VAL, min_dn = HUGE_VAL;
  double max_mean = -HUGE_VAL, min_mean = HUGE_VAL, sum_b = 0;
  double p_hi = -HUGE_VAL, p_lo = HUGE_VAL, sum_u = 0;
  for (size_t i = 0; i < d.targets_mm.size(); ++i) {
    const MeanSd a = Column(up, i), b = Column(down, i);
    PositionStats p;
    p.target_mm = d.targets_mm[i];
    p.mean_up_um = a.mean;
    p.mean_down_um = b.mean;
    p.mean_um = (a.mean + b.mean) / 2.0;
    p.s_up_um = a.sd;
    p.s_down_um = b.sd;
    p.reversal_um = a.mean - b.mean;
    p.r_up_um = 4.0 * a.sd;
    p.r_down_um = 4.0 * b.sd;
    p.r_um = std::max({2.0 * a.sd + 2.0 * b.sd + std::fabs(p.reversal_um), p.r_up_um, p.r_down_um});
    p.u_um = b.mean - a.mean;
    p.ps_um = 6.0 * (a.sd + b.sd) / 2.0;
    iso.positions.push_back(p);

    iso.B_um = std::max(iso.B_um, std::fabs(p.reversal_um));
    sum_b += p.reversal_um;
    iso.R_up_um = std::max(iso.R_up_um, p.r_up_um);
    iso.R_down_um = std::max(iso.R_down_um, p.r_down_um);
    iso.R_um = std::max(iso.R_um, p.r_um);
    max_up = std::max(max_up, a.mean);
    min_up = std::min(min_up, a.mean);
    max_dn = std::max(max_dn, b.mean);
    min_dn = std::min(min_dn, b.mean);
    max_mean = std::max(max_mean, p.mean_um);
    min_mean = std::min(min_mean, p.mean_um);
    max_up_hi = std::max(max_up_hi, a.mean + 2.0 * a.sd);
    min_up_lo = std::min(min_up_lo, a.mean - 2.0 * a.sd);
    max_dn_hi = std::max(max_dn_hi, b.mean + 2.0 * b.sd);
    min_dn_lo = std::min(min_dn_lo, b.mean - 2.0 * b.sd);
    // VDI 3441: P spans mean +- (|U| + Ps) / 2.
    p_hi = std::max(p_hi, p.mean_um + (std::fabs(p.u_um) + p.ps_um) / 2.0);
    p_lo = std::min(p_lo, p.mean_um - (std::fabs(p.u_um) + p.ps_um) / 2.0);
    sum_u += std::fabs(p.u_um);
    out.vdi.U_max_um = std::max(out.vdi.U_max_um, std::fabs(p.u_um));
    out.vdi.Ps_max_um = std::max(out.vdi.Ps_max_um, p.ps_um);
  }
  const double m = static_cast<double>(d.targets_mm.size());
  iso.B_mean_um = sum_b / m;
  iso.E_up_um = max_up - min_up;
  iso.E_down_um = max_dn - min_dn;
  iso.E_um = std::max(max_up, max_dn) - std::min(min_up, min_dn);
  iso.M_um = max_mean - min_mean;
  iso.A_up_um = max_up_hi - min_up_lo;
  iso.A_down_um = max_dn_hi - min_dn_lo;
  iso.A_um = std::max(max_up_hi, max_dn_hi) - std::min(min_up_lo, min_dn_lo);
  out.vdi.Pa_um = iso.M_um;
  out.vdi.P_um = p_hi - p_lo;
  out.vdi.U_mean_um = sum_u / m;

  // Expanded uncertainties (k = 2); L in m, results in um.
  PositioningUncertainty& U = out.uncertainty;
  U.stated = inputs.stated;
  U.length_m = (d.targets_mm.back() - d.targets_mm.front()) / 1000.0;
  const double L = U.length_m;
  U.device_um = 0.6 * inputs.device_um_per_m * L;
  U.misalignment_um = L > 0 ? 0.3 * inputs.misalignment_mm * inputs.misalignment_mm / L : 0.0;
  U.machine_m_um = 0.6 * inputs.alpha_um_per_m_c * L * inputs.temperature_range_c;
  U.machine_e_um = 0.6 * inputs.delta_t_c * L * inputs.alpha_range_um_per_m_c;
  U.eve_um = 0.6 * inputs.e_ve_um;
  const double components = U.device_um * U.device_um + U.misalignment_um * U.misalignment_um +
                            U.machine_m_um * U.machine_m_um + U.machine_e_um * U.machine_e_um;
  U.R_up_down_um = 2.0 * U.eve_um;
  U.B_um = 0.9 * U.eve_um;
  U.R_um = 2.2 * U.eve_um;
  U.E_um = std::sqrt(components + U.eve_um * U.eve_um / 5.0);
  U.M_um = std::sqrt(components + U.eve_um * U.eve_um / 10.0);
  U.A_um = std::sqrt(U.E_um * U.E_um + U.R_up_down_um * U.R_up_down_um);
  return out;
}

}  // namespace thermocomp
