#include "reports/analysis_report_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Join;
using report_text::P;
using report_text::Text;
using report_text::Um;

// Units as a person reads them: the API and the model's sentences spell
// °C "degC" and µm "um" (a whole word, so "sum" or "maximum" stay).
std::string Readable(std::string text) {
  for (size_t at = text.find("degC"); at != std::string::npos; at = text.find("degC", at)) {
    text.replace(at, 4, "°C");
  }
  const auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; };
  for (size_t at = text.find("um"); at != std::string::npos; at = text.find("um", at + 1)) {
    const bool alone =
        (at == 0 || !letter(text[at - 1])) && (at + 2 == text.size() || !letter(text[at + 2]));
    if (alone) text.replace(at, 2, "µm");
  }
  return text;
}

std::string Confidence(const PairedGain& g) {
  return Fixed(g.relative * 100.0, "%.1f") + " % (t " + Fixed(g.t, "%.1f") + ", " +
         std::to_string(g.blocks) + " blocks)";
}

std::string EffectsMarkdown(const AnalysisReport& r) {
  if (r.effects.empty()) {
    return "**No effect passed**: no candidate explained the residual better than chance "
           "(Bonferroni-corrected F-test) and by a gain beyond its uncertainty in "
           "cross-validation over whole days.\n\n";
  }
  std::string md =
      "## Effects added\n\n| # | effect | coefficient | p (adj.) | CV RMSE µm |\n"
      "|---|---|---|---|---|\n";
  int i = 0;
  for (const auto& e : r.effects) {
    md += "| " + std::to_string(++i) + " | " + Code(e.term.Name()) + " | " +
          Fixed(e.coefficient_mm * 1000.0, "%.4g") + " µm/" + Text(Readable(e.term.Unit())) +
          " | " + P(e.p_adjusted) + " | " + Um(e.cv_rmse_before_mm) + " -> " +
          Um(e.cv_rmse_after_mm) + " |\n";
  }
  md += "\n";
  i = 0;
  for (const auto& e : r.effects)
    md += std::to_string(++i) + ". " + Text(Readable(e.interpretation)) + "\n";
  md += "\n";
  if (!r.superseded.empty()) {
    md += "Superseded (no longer significant once an effect was in):\n\n";
    for (const auto& name : r.superseded) {
      auto why = r.superseded_reasons.find(name);
      md += "- `" + Text(name) + "`" +
            (why == r.superseded_reasons.end() ? "" : ": " + Text(Readable(why->second))) + "\n";
    }
    md += "\n";
  }
  return md;
}

std::string ClosestMarkdown(const AnalysisReport& r) {
  if (r.closest.empty()) return "";
  std::string list;
  for (const auto& c : r.closest) {
    const double t = c.confidence ? c.confidence->t : kNotComputed;
    list += (list.empty() ? "" : ", ") + (Code(c.name) + " " + Um(c.cv_rmse_mm) + ", " +
                                          P(c.p_adjusted) + ", t " + Fixed(t, "%.1f"));
  }
  return "Closest candidates that did not pass (CV RMSE with it, µm; adjusted p; t of its "
         "validated gain, which must reach the configured min_t as Student's t over the blocks, "
         "unless it removes 30 % of the error in all days but one): " +
         list + ".\n\n";
}

std::string ConfidenceMarkdown(const AnalysisReport& r) {
  if (!r.validation || r.effects.empty()) return "";
  std::string md =
      "## Confidence\n\nThe validated gain (share of the blocked cross-validation error "
      "removed, and its t over blocks; the blocks in which it predicted better):\n\n"
      "| effect | gain | blocks won | equally good | notes |\n|---|---|---|---|---|\n";
  for (const auto& e : r.effects) {
    std::string alternatives;
    for (const auto& a : e.alternatives) {
      alternatives += (alternatives.empty() ? "" : ", ") + Code(a.name);
    }
    std::string notes;
    if (!e.replaces.empty()) notes += "replaces " + Code(e.replaces) + "; ";
    if (!e.revises_declared.empty()) notes += Text(Readable(e.revises_declared)) + "; ";
    if (!e.together_with.empty())
      notes += "qualified together with " + Code(e.together_with) + "; ";
    const std::string won = BlocksWon(e.confidence, *r.validation);
    md += "| " + Code(e.term.Name()) + " | " + Confidence(e.confidence) + " | " +
          (won.empty() ? "-" : Text(won)) + " | " + (alternatives.empty() ? "none" : alternatives) +
          " | " + (notes.empty() ? "-" : notes) + " |\n";
  }
  return md + "\n";
}

std::string FindingsMarkdown(const AnalysisReport& r) {
  std::string md;
  if (r.validation) {
    const BlockedValidation& v = *r.validation;
    md += "## Validation\n\n" + Text(ValidationMethod(v.block)) + ": " + std::to_string(v.blocks) +
          " blocks; RMSE " + Um(v.rmse_before_mm) + " -> " + Um(v.rmse_after_mm) + " µm.\n\n";
  }
  md += ConfidenceMarkdown(r);
  if (!r.coefficient_changes.empty()) {
    md +=
        "## Declared coefficients (µm per unit)\n\n| term | declared model | extended model |\n"
        "|---|---|---|\n";
    for (const auto& c : r.coefficient_changes) {
      md += "| " + Code(c.term) + " | " + Um(c.before_mm) + " | " + Um(c.after_mm) + " |\n";
    }
    md += "\n";
  }
  if (!r.filters.empty()) {
    md += "## Filters\n\n";
    for (const auto& f : r.filters) {
      md += "- " + Code(f.sensor) + ": white noise " + Fixed(f.noise_c, "%.3f") + " °C every " +
            Fixed(f.interval_min, "%.2f") + " min; read through tau " +
            Fixed(f.recommended_tau_min, "%.1f") + " min (ewma_alpha " +
            Fixed(f.recommended_alpha, "%.3f") + ") instead of " +
            Fixed(f.current_tau_min, "%.1f") + " min (" + Fixed(f.current_alpha, "%.3f") +
            "): " + Confidence(f.validated) + (f.applied ? ", applied" : "") + ".\n";
    }
    md += "\n";
  }
  if (!r.ambiguous.empty()) {
    std::string list;
    for (const auto& a : r.ambiguous) list += (list.empty() ? "" : ", ") + Code(a.name);
    md +=
        "## Ambiguous\n\nEqually good explanations within the validation's uncertainty; "
        "none was added: " +
        list + ".\n\n";
  }
  if (!r.set_aside.empty()) {
    md += "## Set aside\n\n";
    for (const auto& s : r.set_aside) {
      md += "- " + Code(s.name) + " (" + Confidence(s.confidence) +
            "): " + Text(Readable(s.reason)) + ".\n";
    }
    md += "\n";
  }
  if (!r.event_comparisons.empty()) {
    md += "## Events\n\n";
    for (const auto& e : r.event_comparisons) {
      md += "- " + Text(Readable(EventStatement(e, r.context.axis))) + " Runs " +
            std::to_string(e.runs_before) + " before, " + std::to_string(e.runs_after) +
            " after; RMSE " + Um(e.rmse_before_mm) + " / " + Um(e.rmse_after_mm) + " µm.\n";
    }
    md += "\n";
  }
  return md;
}

// A run that reads a faulty sensor past its onset says so: its error is
// partly the fault's.
std::string HeldOutRow(std::string run, const HeldOutRunError& e) {
  if (!e.faulty_sensors.empty())
    run += " (reads " + Text(Join(e.faulty_sensors)) + " past its fault's onset)";
  return "| " + run + " | " + std::to_string(e.n) + " | " + Um(e.mae_before_mm) + " | " +
         Um(e.mae_after_mm) + " | " + Um(e.rmse_before_mm) + " | " + Um(e.rmse_after_mm) + " | " +
         Um(e.max_before_mm) + " | " + Um(e.max_after_mm) + " |\n";
}

// Per held-out run, so one run the model fails on is not averaged away.
std::string HeldOutMarkdown(const AnalysisReport& r) {
  if (!r.holdout_errors) return "";
  std::string md =
      "## Held-out runs (µm)\n\nRuns the search never saw: the error of the declared model "
      "(before) and of the extended one (after) at their probe points.\n\n"
      "| run | points | MAE before | MAE after | RMSE before | RMSE after | " +
      Text("max |error|") + " before | " + Text("max |error|") +
      " after |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& e : r.holdout_errors->runs) md += HeldOutRow(Text(e.run), e);
  return md + HeldOutRow("all held-out runs", r.holdout_errors->total) + "\n";
}

// What the sensor check could not look for: over too short a training
// window only steps ("" when it looked for every kind, or is not known).
std::string SensorCheckSentence(const AnalysisReport& r) {
  if (!r.sensor_check) return "";
  const auto& kinds = r.sensor_check->kinds;
  if (std::find(kinds.begin(), kinds.end(), "drift") != kinds.end()) return "";
  return "Only steps were looked for: drifts and lost contacts are looked for once the training "
         "runs span " +
         Fixed(r.sensor_check->slow_min_days, "%.0f") + " days (these span " +
         Fixed(r.sensor_check->training_days, "%.1f") + " days).";
}

// A faulty sensor is reported for a person to check, apart from the effects.
std::string SensorsMarkdown(const AnalysisReport& r, const PlantTime& time) {
  const std::string partial = SensorCheckSentence(r);
  if (r.sensor_faults.empty()) {
    return partial.empty() ? "" : "## Sensors to check\n\nNone found. " + partial + "\n\n";
  }
  std::string md =
      "## Sensors to check\n\nThese declared sensors read differently from their neighbours "
      "from the onset on: a sensor to check, not a thermal effect. Their readings from the "
      "onset on were left out of the search (unless that would have taken too large a share "
      "of the training points, or the onset lies in the held-out runs: points left out 0; or, "
      "for a lost contact, once it has settled: below); a held-out run that reads them past "
      "the onset is marked.\n\n" +
      (partial.empty() ? std::string() : partial + "\n\n") +
      "| sensor | kind | since | departure °C | drift it caused µm | points left out | why |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& f : r.sensor_faults) {
    std::string kind = f.kind;
    std::replace(kind.begin(), kind.end(), '_', ' ');  // lost_contact -> lost contact
    md += "| " + Code(f.sensor) + " | " + Text(kind) + " | " + time.Format(f.onset_ms) + " | " +
          Fixed(f.size_c, "%+.2f") + " | " + Um(f.effect_mm) + " | " +
          std::to_string(f.points_left_out) + " | " + Text(Readable(f.reason)) + " |\n";
  }
  md += "\n";
  for (const auto& f : r.sensor_faults) {
    if (!f.accommodated) continue;
    md += "Its contact lost, " + Code(f.sensor) + " reads a fixed share of the air (" +
          Code(f.air) + ") once the loss has settled (" + time.Format(f.settled_ms) +
          "): the runs from then on are kept, fitted with " + Code(f.sensor) + " and " +
          Code(f.air) + " each read with a coefficient of its own (the terms " +
          Code("change(" + f.sensor + ",sensor_fault …)") + " and " +
          Code("change(" + f.air + ",sensor_fault …)") +
          "), and the extended model serves them so; on the held-out runs the declared model "
          "reads " +
          Code(f.sensor) +
          " as if it were sound. Once the sensor is mounted again, "
          "serve the model version from before the fault (activate it) until an analysis of "
          "the days since is done.\n\n";
  }
  return md;
}

std::string ErrorsMarkdown(const AnalysisReport& r) {
  std::string md =
      "## Error before and after (µm)\n\n| | declared model | extended model |\n|---|---|---|\n";
  md += "| training RMSE | " + Um(r.train_rmse_before_mm) + " | " + Um(r.train_rmse_after_mm) +
        " |\n";
  if (r.validation) {
    md += "| blocked cross-validation RMSE | " + Um(r.validation->rmse_before_mm) + " | " +
          Um(r.validation->rmse_after_mm) + " |\n";
  }
  md += "| leave-one-run-out RMSE | " + Um(r.cv_rmse_before_mm) + " | " + Um(r.cv_rmse_after_mm) +
        " |\n";
  md += "| held-out RMSE | " + Um(r.holdout_rmse_before_mm) + " | " + Um(r.holdout_rmse_after_mm) +
        " |\n";
  if (r.holdout_errors) {
    const HeldOutRunError& t = r.holdout_errors->total;
    md += "| held-out MAE | " + Um(t.mae_before_mm) + " | " + Um(t.mae_after_mm) + " |\n";
    md += "| held-out " + Text("max |error|") + " | " + Um(t.max_before_mm) + " | " +
          Um(t.max_after_mm) + " |\n";
  }
  md += "\n";
  md += HeldOutMarkdown(r);
  md += "## Residual structure\n\n| | before | after |\n|---|---|---|\n";
  const ResidualStructure& b = r.structure_before;
  const ResidualStructure& a = r.structure_after;
  md += "| lag1_autocorrelation | " + Fixed(b.lag1_autocorrelation, "%.3f") + " | " +
        Fixed(a.lag1_autocorrelation, "%.3f") + " |\n";
  md += "| between_run_share | " + Fixed(b.between_run_share, "%.3f") + " | " +
        Fixed(a.between_run_share, "%.3f") + " |\n";
  md += "| durbin_watson | " + Fixed(b.durbin_watson, "%.3f") + " | " +
        Fixed(a.durbin_watson, "%.3f") + " |\n";
  return md;
}

}  // namespace

std::string AnalysisMarkdown(const AnalysisReport& r, const PlantTime& time) {
  const AnalysisContext& c = r.context;
  std::string md = "# Effect analysis " + std::to_string(r.id) + ": " + Text(c.machine) + " axis " +
                   Text(c.axis) + "\n\n";
  md += "Created " + time.Format(c.created_ms) + " (" + Text(c.trigger) +
        "). Declared inputs: " + Join(c.declared_inputs) +
        ". Held-out runs, never seen by the search: " + Join(c.holdout_runs) + ". " +
        std::to_string(r.candidates) + " candidate effects, " + std::to_string(r.training_runs) +
        " training runs, " + std::to_string(r.n) + " probe points.\n\n";
  md += SensorsMarkdown(r, time);
  md += EffectsMarkdown(r);
  md += ClosestMarkdown(r);
  md += FindingsMarkdown(r);
  md += ErrorsMarkdown(r);
  if (r.model) {
    md += "\n## Model\n\nVersion " + std::to_string(r.model->version) + ": " +
          Text(r.model->status) + ". " + Text(r.model->reason) + ".\n";
  }
  return md;
}

std::string AnalysisErrorChartSvg(const AnalysisReport& r) {
  // Bars of the error measures, before (grey) and after (blue).
  struct Measure {
    const char* label;
    double before, after;
  };
  const double blocked_before = r.validation ? r.validation->rmse_before_mm : kNotComputed;
  const double blocked_after = r.validation ? r.validation->rmse_after_mm : kNotComputed;
  const Measure measures[4] = {{"training", r.train_rmse_before_mm, r.train_rmse_after_mm},
                               {"blocked CV", blocked_before, blocked_after},
                               {"run-out CV", r.cv_rmse_before_mm, r.cv_rmse_after_mm},
                               {"held-out", r.holdout_rmse_before_mm, r.holdout_rmse_after_mm}};
  double top = 1e-9;
  for (const auto& m : measures) {
    for (double v : {m.before, m.after}) {
      if (std::isfinite(v)) top = std::max(top, v);
    }
  }
  std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg' width='440' height='170' role='img' "
      "aria-label='RMSE before and after, µm'>";
  for (int i = 0; i < 4; ++i) {
    const int y = 6 + i * 40;
    svg += "<text x='0' y='" + std::to_string(y + 14) + "' font-size='12'>" + measures[i].label +
           "</text>";
    for (int s = 0; s < 2; ++s) {
      const double v = s == 0 ? measures[i].before : measures[i].after;
      const int w = static_cast<int>(250.0 * (std::isfinite(v) ? v : 0.0) / top);
      svg += "<rect x='110' y='" + std::to_string(y + s * 14) + "' width='" + std::to_string(w) +
             "' height='12' fill='" + (s == 0 ? "#999" : "#2a6ebb") + "'/><text x='" +
             std::to_string(115 + w) + "' y='" + std::to_string(y + s * 14 + 10) +
             "' font-size='10'>" + Um(v) + " µm</text>";
    }
  }
  return svg + "</svg>";
}

}  // namespace thermocomp
