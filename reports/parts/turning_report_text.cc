#include "reports/parts/turning_report_text.h"

#include "model/parts/diameter_decimal.h"
#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Text;

std::string Share(const std::optional<double>& s) {
  return s ? Fixed(*s, "%.2f") : std::string("—");
}

std::string Change(const CompensationChange& c, const PlantTime& time) {
  const std::string how =
      c.action == "fit" || c.action == "feed-fit" ? "fitted and served" : "activated";
  return time.Format(c.ts_ms) + ": axis " + Text(c.axis) + " " + Text(c.kind) + " model v" +
         std::to_string(c.version) + " " + how;
}

std::string SummaryRow(const std::string& label, const ComponentSummary& s) {
  return "| " + label + " | " + std::to_string(s.count) + " | " + Fixed(s.mean_f_um, "%+.1f") +
         " | " + Fixed(s.mean_th_um, "%+.1f") + " | " + Fixed(s.mean_g_um, "%+.1f") + " | " +
         Fixed(s.mean_tot_um, "%+.1f") + " | " + Fixed(s.mean_abs_th_um, "%.1f") + " | " +
         Share(s.thermal_share) + " |\n";
}

constexpr const char* kSummaryHead =
    "| parts | count | mean δf µm | mean δth µm | mean δg µm | mean δtot µm | mean \\|δth\\| µm | "
    "thermal share |\n|---|---|---|---|---|---|---|---|\n";

std::string Feature(const TurnedFeatureReport& f, const PlantTime& time) {
  const std::optional<CompensationChange>& change = f.change;
  std::string md = "## Feature " + Code(f.feature) + "\n\n";
  md += std::to_string(f.all.count) + " parts cut from " + time.Format(f.first_ms) + " to " +
        time.Format(f.last_ms) + ".\n\n";
  const TurnedPart& p = f.latest;
  md += "Latest part " + Code(p.part) + ", cut " + time.Format(p.cut_ms) + " (mm):\n\n";
  md +=
      "| D_des | D_w | D_c | D_pp | δf | δth | δg | δtot | thermal share |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  md += "| " + FormatNmAsMm(p.d.des_nm) + " | " + FormatNmAsMm(p.d.w_nm) + " | " +
        FormatNmAsMm(p.d.c_nm) + " | " + FormatNmAsMm(p.d.pp_nm) + " | " +
        FormatHalfNmAsMm(p.c.f_half_nm, true) + " | " + FormatHalfNmAsMm(p.c.th_half_nm, true) +
        " | " + FormatHalfNmAsMm(p.c.g_half_nm, true) + " | " +
        FormatHalfNmAsMm(p.c.tot_half_nm, true) + " | " + Share(ThermalShare(p.c)) + " |\n\n";
  md += kSummaryHead;
  md += SummaryRow("all", f.all);
  if (f.before && change) md += SummaryRow("before the change", *f.before);
  if (f.after && change) md += SummaryRow("after the change", *f.after);
  md += "\n";
  if (change && f.before && f.after) {
    md += "Before/after: " + Change(*change, time) + "; thermal share " +
          Share(f.before->thermal_share) + " before, " + Share(f.after->thermal_share) +
          " after.\n\n";
  }
  md += "Thermal share over time: ";
  md += f.trend.slope_per_30_days
            ? Fixed(*f.trend.slope_per_30_days, "%+.3f") + " per 30 days over " +
                  std::to_string(f.trend.parts) + " parts"
            : std::string("too few parts for a trend");
  md += ".\n\n";
  if (!f.weeks.empty()) {
    md +=
        "| week from | parts | mean δth µm | mean \\|δth\\| µm | thermal share |\n"
        "|---|---|---|---|---|\n";
    for (const TurnedPeriod& w : f.weeks) {
      md += "| " + time.Format(w.start_ms) + " | " + std::to_string(w.summary.count) + " | " +
            Fixed(w.summary.mean_th_um, "%+.1f") + " | " + Fixed(w.summary.mean_abs_th_um, "%.1f") +
            " | " + Share(w.summary.thermal_share) + " |\n";
    }
    md += "\n";
  }
  return md;
}

}  // namespace

std::string TurningReportMarkdown(const TurningReport& r, const PlantTime& time) {
  std::string md = "# Turned parts " + Text(r.machine) + "\n\n";
  md += "Created " + time.Format(r.created_ms) + ". Parts cut from " + time.Format(r.from_ms) +
        " to " + time.Format(r.to_ms) + ": " + std::to_string(r.parts) + " in " +
        std::to_string(r.features.size()) + " features.\n\n";
  md +=
      "Per part: δf = (D_w − D_des)/2 (force), δth = (D_c − D_w)/2 (thermal), "
      "δg = (D_pp − D_c)/2 (geometric and other), δtot = (D_pp − D_des)/2, their sum; "
      "thermal share |δth| / (|δf| + |δth| + |δg|), of a group Σ|δth| / Σ(|δf| + |δth| + "
      "|δg|). Parts in mm as measured, means in µm.\n\n";
  md += "Compensation changes on this machine: ";
  if (r.changes.empty()) {
    md += "none archived.\n\n";
  } else {
    md += "\n\n";
    for (const CompensationChange& c : r.changes) md += "- " + Change(c, time) + "\n";
    md += "\n";
  }
  md +=
      "Before/after per feature: the latest change with parts of the feature on both "
      "sides.\n\n";
  if (r.features.empty()) md += "No turned parts in this period.\n";
  for (const TurnedFeatureReport& f : r.features) md += Feature(f, time);
  return md;
}

}  // namespace thermocomp
