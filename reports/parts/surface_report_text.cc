#include "reports/parts/surface_report_text.h"

#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Text;

std::string Mm(double v) {
  return Fixed(v, "%+.3f");
}

std::string Flag(const SurfaceIteration& it) {
  if (!it.allowance_not_uniform) return "—";
  std::string out;
  for (const std::string& f : it.flags) out += (out.empty() ? "" : "; ") + Text(f);
  return "**allowance not uniform**: " + out;
}

}  // namespace

std::string SurfacePartMarkdown(const SurfacePartReport& r, const PlantTime& time) {
  std::string md = "# Surface " + Code(r.part) + " on " + Text(r.machine) + "\n\n";
  md += std::to_string(r.nominal.size()) + (r.nominal.size() == 1 ? " point" : " points") +
        ". Each deviation d is taken along the normal of the original nominal point, in "
        "every iteration; the program for the next part is the mirror of what is left: "
        "corrected(k+1) = corrected(k) − d(k)·n (corrected(0) = nominal).\n\n";
  if (r.iterations.empty()) return md + "No measurement yet.\n";
  md +=
      "| iteration | measured | by | input | points | max − mm | max + mm | mean abs(d) mm | "
      "RMS mm | flag |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SurfaceIteration& it : r.iterations) {
    md += "| " + std::to_string(it.iteration) + " | " + time.Format(it.measured_ms) + " | " +
          Text(it.actor) + " | " + Text(it.input) + " | " + std::to_string(it.stats.points) +
          " | " + Mm(it.stats.max_negative_mm) + " | " + Mm(it.stats.max_positive_mm) + " | " +
          Fixed(it.stats.mean_abs_mm, "%.3f") + " | " + Fixed(it.stats.rms_mm, "%.3f") + " | " +
          Flag(it) + " |\n";
  }
  md += "\n## Before → after\n\n";
  bool any = false;
  for (const SurfaceIteration& it : r.iterations) {
    if (!it.before) continue;
    any = true;
    md += "- Iteration " + std::to_string(it.iteration) + " (part from the program corrected on " +
          "iteration " + std::to_string(it.iteration - 1) + "): " + Mm(it.before->max_negative_mm) +
          "/" + Mm(it.before->max_positive_mm) + "/" + Fixed(it.before->mean_abs_mm, "%.3f") +
          " mm → " + Mm(it.stats.max_negative_mm) + "/" + Mm(it.stats.max_positive_mm) + "/" +
          Fixed(it.stats.mean_abs_mm, "%.3f") + " mm (max −/max +/mean abs(d))";
    if (it.before->mean_abs_mm > 0) {
      md += ", mean abs(d) " +
            Fixed(100 * (it.stats.mean_abs_mm / it.before->mean_abs_mm - 1), "%+.0f") + " %";
    }
    if (it.repeat) {
      md += "; " + std::to_string(it.repeat->not_repeating) + " points (" +
            Fixed(100 * it.repeat->share, "%.0f") + " %) did not repeat";
    }
    md += ".\n";
  }
  if (!any) md += "One measurement so far: the next part is made from the corrected program.\n";
  md +=
      "\n## The allowance flag\n\nAn iteration is flagged when the stock before finishing "
      "(allowance_mm) spreads by more than " +
      Fixed(100 * kAllowanceSpreadShare, "%.0f") +
      " % of its mean, or, from iteration 1 on, when more than " +
      Fixed(100 * kNotRepeatingShare, "%.0f") +
      " % of the points changed by more than the correction predicted (more than " +
      Fixed(kRepeatToleranceMm, "%.3f") +
      " mm or half the shift made there): the mirror assumes the error repeats, which holds "
      "only for a uniform allowance.\n";
  return md;
}

}  // namespace thermocomp
