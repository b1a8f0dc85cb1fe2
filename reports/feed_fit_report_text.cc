#include "reports/feed_fit_report_text.h"

#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Text;

std::string Ids(const std::vector<int64_t>& ids) {
  std::string out;
  for (int64_t id : ids) out += (out.empty() ? "" : ", ") + std::to_string(id);
  return out.empty() ? "none" : out;
}

std::string Parameters(const FeedTypeParameters& p) {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (p.alpha_um_per_m_k) {
    add("α " + Fixed(*p.alpha_um_per_m_k, "%.3f") + " ± " + Fixed(p.alpha_se.value_or(0), "%.3f") +
        " µm/(m·K)");
  }
  if (p.stiffness_ratio) {
    add("a " + Fixed(*p.stiffness_ratio, "%.4f") + " ± " +
        Fixed(p.stiffness_ratio_se.value_or(0), "%.4f"));
  }
  if (p.hidden_units) {
    add(std::to_string(*p.hidden_units) + " units, " + std::to_string(p.weights.value_or(0)) +
        " weights, " + Fixed(p.effective_parameters.value_or(0), "%.1f") + " effective");
  }
  if (p.coefficients) add(std::to_string(*p.coefficients) + " coefficients");
  return out.empty() ? "—" : out;
}

std::string HeldOutTable(const FeedHeldOut& h, const PlantTime& time) {
  std::string md =
      "| check | time | max before | RMS before | max after | RMS after | removed | fallback | "
      "invalid |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const FeedCheckScore& s : h.checks) {
    md += "| " + std::to_string(s.check_id) + " | " + time.Format(s.ts_ms) + " | " +
          Fixed(s.max_before_um, "%.2f") + " | " + Fixed(s.rms_before_um, "%.2f") + " | " +
          Fixed(s.max_after_um, "%.2f") + " | " + Fixed(s.rms_after_um, "%.2f") + " | " +
          Fixed(100 * s.reduction, "%.0f") + " % | " + std::to_string(s.fallback_targets) + " | " +
          std::to_string(s.invalid_targets) + " |\n";
  }
  return md + "\nOver the held-out checks: max " + Fixed(h.max_before_um, "%.2f") + " → " +
         Fixed(h.max_after_um, "%.2f") + " µm (" + Fixed(100 * h.reduction, "%.0f") +
         " % removed), RMS after " + Fixed(h.rms_after_um, "%.2f") + " µm.\n\n";
}

}  // namespace

std::string FeedFitReportMarkdown(const FeedFitReport& r, const PlantTime& time) {
  std::string md = "# Feed-axis fit " + Text(r.machine) + " axis " + Text(r.axis) + "\n\n";
  md += "**" + std::string(r.accepted ? "Accepted" : "Not accepted") + "**: " + Text(r.decision) +
        ". Served version after the fit: " +
        (r.active_version ? std::to_string(r.active_version) : std::string("none")) + ". Created " +
        time.Format(r.created_ms) + " by " + Text(r.actor) + " (" + Text(r.trigger) + ").\n\n";
  md += "## Checks\n\nReference (cold): " + std::to_string(r.reference_check_id) +
        ". Training: " + Ids(r.training_check_ids) + ". Held out: " + Ids(r.held_out_check_ids) +
        ".\n\n";
  if (!r.skipped.empty()) {
    md += "| skipped check | why |\n|---|---|\n";
    for (const FeedSkippedCheck& s : r.skipped) {
      md += "| " + std::to_string(s.check_id) + " | " + Text(s.why) + " |\n";
    }
    md += "\n";
  }
  md +=
      "## Types\n\n| type | version | status | parameters | training RMSE | held-out max "
      "before → after |\n|---|---|---|---|---|---|\n";
  for (const FeedTypeResult& t : r.types) {
    if (!t.fitted) {
      md += "| " + Code(t.type) + " | — | not fitted | " + Text(t.error) + " | | |\n";
      continue;
    }
    md += "| " + Code(t.type) + " | " + std::to_string(t.version) + " | " + Text(t.status) + " | " +
          Parameters(t.parameters) + " | " + Fixed(t.training_rmse_um, "%.2f") + " µm | " +
          Fixed(t.held_out.max_before_um, "%.2f") + " → " + Fixed(t.held_out.max_after_um, "%.2f") +
          " µm |\n";
  }
  md += "\n";
  for (const FeedTypeResult& t : r.types) {
    if (!t.fitted) continue;
    md +=
        "### " + Code(t.type) + "\n\n" + Text(t.reason) + ".\n\n" + HeldOutTable(t.held_out, time);
  }
  md += "## Champion\n\n";
  if (!r.champion) {
    md += "No model was active.\n\n";
  } else {
    md += "Version " + std::to_string(r.champion->version) + " (" + Code(r.champion->type) + ")";
    if (r.champion->held_out) {
      md += " on the same held-out checks:\n\n" + HeldOutTable(*r.champion->held_out, time);
    } else {
      md += ": " + Text(r.champion->note) + ".\n\n";
    }
  }
  md += "## Sensors\n\n";
  if (!r.sensors.interpolation_bound.empty()) {
    md += "| held-out check | interpolation bound |\n|---|---|\n";
    for (const auto& b : r.sensors.interpolation_bound) {
      md += "| " + std::to_string(b.check_id) + " | " +
            (b.bound_um ? Fixed(*b.bound_um, "%.2f") + " µm" : std::string("not known")) + " |\n";
    }
    md += "\n";
  }
  if (r.sensors.dropped.empty()) {
    md += "Every configured sensor was used.\n";
  } else {
    md += "| dropped sensor | kind | why |\n|---|---|---|\n";
    for (const FeedDroppedSensor& d : r.sensors.dropped) {
      md +=
          "| " + Code(d.name) + " | " + (d.screw ? "screw" : "body") + " | " + Text(d.why) + " |\n";
    }
    md += "\n" + Text(r.sensors.cost) + ".\n";
  }
  return md;
}

}  // namespace thermocomp
