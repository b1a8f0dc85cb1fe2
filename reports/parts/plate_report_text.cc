#include "reports/parts/plate_report_text.h"

#include <cmath>

#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Text;

std::string Percent(double improvement) {
  if (!std::isfinite(improvement)) return "-";
  return Fixed(-improvement * 100.0, "%+.0f") + " %";
}

std::string OnOffRow(const std::string& what, const PlateOnOff& c) {
  return "| " + what + " | " + std::to_string(c.on.n) + " / " + std::to_string(c.off.n) + " | " +
         Fixed(c.off.s_um, "%.1f") + " → " + Fixed(c.on.s_um, "%.1f") + " | " +
         Percent(c.s_improvement) + " | " + Fixed(c.off.r_um, "%.1f") + " → " +
         Fixed(c.on.r_um, "%.1f") + " | " + Percent(c.r_improvement) + " | " +
         report_text::P(c.p_value) + " | " + (c.improves ? "yes" : "no") + " |\n";
}

std::string OptUm(const std::optional<double>& v) {
  return v ? Fixed(*v, "%.1f") : "-";
}

}  // namespace

std::string PlateReportMarkdown(const PlateReport& r, const PlantTime& time) {
  const PlateStatistics& st = r.stats;
  std::string md =
      "# Test plate " + Text(r.plate) + " on " + Text(r.machine) + "/" + Code(r.axis) + "\n\n";
  md += "Bored from " + Text(time.Format(st.first_bored_ms)) + " to " +
        Text(time.Format(st.last_bored_ms)) + ": " + std::to_string(r.holes.size()) + " holes in " +
        std::to_string(st.pairs.size()) +
        " pairs, one of each with the compensation on, one with it zeroed. Imported " +
        Text(time.Format(r.created_ms)) + " by " + Text(r.actor) + ".\n\n";
  const PlateOnOff& p = st.plate;
  md += "**S(" + Text(r.axis) + "DEV) " + Fixed(p.off.s_um, "%.1f") + " → " +
        Fixed(p.on.s_um, "%.1f") + " µm (" + Percent(p.s_improvement) + "), R " +
        Fixed(p.off.r_um, "%.1f") + " → " + Fixed(p.on.r_um, "%.1f") + " µm (" +
        Percent(p.r_improvement) + ").** ";
  md += p.improves ? "The compensated holes scatter less than chance explains (F-test, p " +
                         report_text::P(p.p_value) + ").\n\n"
                   : "No improvement beyond chance (F-test, p " + report_text::P(p.p_value) +
                         "): no claim that compensation helped on this plate.\n\n";
  if (st.pay_off_ms && r.pay_off_minutes) {
    md += "Compensation pays from pair " + std::to_string(st.pay_off_pair.value_or(0)) + " on, " +
          Text(time.Format(*st.pay_off_ms)) + ", " + Fixed(*r.pay_off_minutes, "%.0f") +
          " min after the first hole: from there every run of three pairs gains more than twice "
          "the compensated holes' scatter (2 S on).\n\n";
  } else {
    md +=
        "No pay-off time: no run of pairs to the plate's end where compensation keeps "
        "gaining more than twice the compensated holes' scatter (2 S on).\n\n";
  }
  if (r.holes_without_served > 0) {
    md += std::to_string(r.holes_without_served) +
          " hole(s) without a served compensation at their bore time (none logged in the day "
          "before).\n\n";
  }
  md += "## Per nominal level\n\n";
  md +=
      "| level | holes on / off | S off → on (µm) | S change | R off → on (µm) | R change | p | "
      "improves |\n|---|---|---|---|---|---|---|---|\n";
  md += OnOffRow("whole plate", p);
  for (const auto& l : st.levels)
    md += OnOffRow("Y " + Fixed(l.nominal_y_mm, "%.3f") + " mm", l.on_off);
  md +=
      "\n## Pairs in bore order\n\n| pair | bored | off (µm) | on (µm) | gain (µm) |\n"
      "|---|---|---|---|---|\n";
  for (const auto& pp : st.pairs) {
    md += "| " + std::to_string(pp.pair) + " | " + Text(time.Format(pp.first_bored_ms)) + " | " +
          Fixed(pp.off_um, "%.1f") + " | " + Fixed(pp.on_um, "%.1f") + " | " +
          Fixed(pp.gain_um, "%+.1f") + " |\n";
  }
  md +=
      "\n## Holes\n\n| hole | pair | compensation | nominal X, Y (mm) | dev X (µm) | dev Y (µm) | "
      "min | predicted drift (µm) | served offset (µm) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& h : r.holes) {
    md += "| " + Code(h.hole) + " | " + std::to_string(h.pair) + " | " +
          (h.compensated ? "on" : "off") + " | " + Fixed(h.nominal_x_mm, "%.3f") + ", " +
          Fixed(h.nominal_y_mm, "%.3f") + " | " + Fixed(h.dev_x_um, "%.1f") + " | " +
          Fixed(h.dev_y_um, "%.1f") + " | " + Fixed(h.minutes, "%.0f") + " | " +
          OptUm(h.predicted_drift_um) + " | " + OptUm(h.served_offset_um) + " |\n";
  }
  return md;
}

}  // namespace thermocomp
