#include "service/analysis_report.h"

#include <cstdio>

#include "core/time_format.h"
#include "service/analysis_findings.h"
#include "service/model_codec.h"

namespace thermocomp {
namespace {

nlohmann::json Structure(const ResidualStructure& s) {
  return {{"lag1_autocorrelation", s.lag1_autocorrelation},
          {"between_run_share", s.between_run_share},
          {"durbin_watson", s.durbin_watson}};
}

std::string Um(const nlohmann::json& mm) {
  if (!mm.is_number()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", mm.get<double>() * 1000.0);
  return buf;
}

std::string Num(const nlohmann::json& v, const char* format = "%.3g") {
  if (!v.is_number()) return "-";
  if (v.get<double>() == 0.0 && format[2] == '2') return "< 1e-300";  // p underflowed
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v.get<double>());
  return buf;
}

std::string Join(const nlohmann::json& list) {
  std::string out;
  for (const auto& s : list) out += (out.empty() ? "" : ", ") + s.get<std::string>();
  return out.empty() ? "none" : out;
}

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

nlohmann::json AnalysisReportJson(const EffectSearchResult& r, const AnalysisContext& c) {
  nlohmann::json effects = nlohmann::json::array();
  for (const auto& e : r.effects) {
    nlohmann::json j = EffectTermToJson(e.term);
    j["coefficient"] = e.coefficient_mm;
    j["p"] = FiniteOrNull(e.p);
    j["p_adjusted"] = FiniteOrNull(e.p_adjusted);
    j["candidates_tried"] = e.candidates_tried;
    j["cv_rmse_before_mm"] = FiniteOrNull(e.cv_rmse_before_mm);
    j["cv_rmse_after_mm"] = FiniteOrNull(e.cv_rmse_after_mm);
    j["residual_correlation"] = FiniteOrNull(e.residual_correlation);
    TermContext context{c.axis, 0.0};
    if (e.term.kind == EffectKind::kEventSensor) {
      if (const TermStats* base = r.after.Find(EffectTerm::Sensor(e.term.source).Name())) {
        context.base_coefficient_mm = base->estimate;
      }
    }
    j["interpretation"] = e.term.Interpretation(e.coefficient_mm, context);
    AddEffectFindings(e, j);
    j["revised"] = e.revised;
    nlohmann::json runners = nlohmann::json::array();
    for (const auto& s : e.runners_up) {
      runners.push_back({{"name", s.term.Name()},
                         {"cv_rmse_mm", FiniteOrNull(s.cv_rmse)},
                         {"p_adjusted", FiniteOrNull(s.p_adjusted)}});
    }
    j["runners_up"] = runners;
    effects.push_back(j);
  }
  nlohmann::json closest = nlohmann::json::array();
  for (const auto& s : r.closest) {
    closest.push_back({{"name", s.term.Name()},
                       {"cv_rmse_mm", FiniteOrNull(s.cv_rmse)},
                       {"p_adjusted", FiniteOrNull(s.p_adjusted)},
                       {"confidence", GainJson(s.gain)}});
  }
  nlohmann::json superseded = nlohmann::json::array();
  for (const auto& t : r.superseded) superseded.push_back(t.Name());
  nlohmann::json terms = nlohmann::json::array();
  nlohmann::json coefficients = nlohmann::json::object();
  for (const auto& t : r.after.terms) coefficients[t.name] = t.estimate;
  for (const auto& t : r.terms) terms.push_back(EffectTermToJson(t));
  nlohmann::json report = {
      {"machine", c.machine},
      {"axis", c.axis},
      {"created_at", FormatRfc3339(c.created_ms)},
      {"trigger", c.trigger},
      {"declared_inputs", c.declared_inputs},
      {"holdout_runs", c.holdout_runs},
      {"training_runs", r.training_runs},
      {"n", r.training_n},
      {"holdout_n", r.holdout_n},
      {"candidates", r.candidates},
      {"not_evaluable", r.not_evaluable},
      {"effects", effects},
      {"superseded", superseded},
      {"closest_candidates", closest},
      {"terms", terms},
      {"coefficients", coefficients},
      {"rmse_before_mm", r.holdout_n ? FiniteOrNull(r.holdout_rmse_before_mm) : nullptr},
      {"rmse_after_mm", r.holdout_n ? FiniteOrNull(r.holdout_rmse_after_mm) : nullptr},
      {"validation_r2_before", r.holdout_n ? FiniteOrNull(r.holdout_r2_before) : nullptr},
      {"validation_r2_after", r.holdout_n ? FiniteOrNull(r.holdout_r2_after) : nullptr},
      {"cv_rmse_before_mm", FiniteOrNull(r.cv_before.rmse)},
      {"cv_rmse_after_mm", FiniteOrNull(r.cv_after.rmse)},
      {"train_rmse_before_mm", FiniteOrNull(r.before.rmse)},
      {"train_rmse_after_mm", FiniteOrNull(r.after.rmse)},
      {"r2_before", FiniteOrNull(r.before.r2)},
      {"r2_after", FiniteOrNull(r.after.r2)},
      {"adj_r2_after", FiniteOrNull(r.after.adj_r2)},
      {"residual_structure",
       {{"before", Structure(r.structure_before)}, {"after", Structure(r.structure_after)}}},
  };
  AddFindings(r, c.axis, report);
  return report;
}

std::string AnalysisMarkdown(const nlohmann::json& report) {
  std::string md = "# Effect analysis " + std::to_string(report.value("id", 0)) + ": " +
                   report.value("machine", "") + " axis " + report.value("axis", "") + "\n\n";
  md += "Created " + report.value("created_at", "") + " (" + report.value("trigger", "") +
        "). Declared " + "inputs: " + Join(report["declared_inputs"]) +
        ". Held-out runs, never seen by the search: " + Join(report["holdout_runs"]) + ". " +
        std::to_string(report.value("candidates", 0)) + " candidate effects, " +
        std::to_string(report.value("training_runs", 0)) + " training runs, " +
        std::to_string(report.value("n", 0)) + " probe points.\n\n";
  const auto& effects = report["effects"];
  if (effects.empty()) {
    md +=
        "**No effect passed**: no candidate explained the residual better than chance "
        "(Bonferroni-corrected F-test) and by a gain beyond its uncertainty in cross-validation "
        "over whole days.\n\n";
  } else {
    md +=
        "## Effects added\n\n| # | effect | coefficient | p (adj.) | CV RMSE um |\n"
        "|---|---|---|---|---|\n";
    int i = 0;
    for (const auto& e : effects) {
      md += "| " + std::to_string(++i) + " | `" + e.value("name", "") + "` | " +
            Num(e["coefficient"], "%.4g") + " mm/" + e.value("unit", "") + " | " +
            Num(e["p_adjusted"], "%.2g") + " | " + Um(e["cv_rmse_before_mm"]) + " -> " +
            Um(e["cv_rmse_after_mm"]) + " |\n";
    }
    md += "\n";
    i = 0;
    for (const auto& e : effects) {
      md += std::to_string(++i) + ". " + e.value("interpretation", "") + "\n";
    }
    md += "\n";
    if (!report["superseded"].empty()) {
      md += "Superseded (no longer significant once an effect was in): " +
            Join(report["superseded"]) + ".\n\n";
    }
  }
  if (report.contains("closest_candidates") && !report["closest_candidates"].empty()) {
    md +=
        "Closest candidates that did not pass (CV RMSE with it, um; adjusted p; t of its "
        "validated gain, which must reach the configured min_t): ";
    std::string list;
    for (const auto& c : report["closest_candidates"]) {
      const nlohmann::json t = c.contains("confidence")
                                   ? c["confidence"].value("t", nlohmann::json())
                                   : nlohmann::json();
      list += (list.empty() ? "" : ", ") +
              ("`" + c.value("name", "") + "` " + Um(c["cv_rmse_mm"]) + ", " +
               Num(c["p_adjusted"], "%.2g") + ", t " + Num(t, "%.1f"));
    }
    md += list + ".\n\n";
  }
  md += FindingsMarkdown(report);
  md += "## Error before and after (um)\n\n| | declared model | extended model |\n|---|---|---|\n";
  md += "| training RMSE | " + Um(report["train_rmse_before_mm"]) + " | " +
        Um(report["train_rmse_after_mm"]) + " |\n";
  if (report.contains("validation") && report["validation"].is_object()) {
    const nlohmann::json& v = report["validation"];
    md += "| blocked cross-validation RMSE | " + Um(v.value("rmse_before_mm", nlohmann::json())) +
          " | " + Um(v.value("rmse_after_mm", nlohmann::json())) + " |\n";
  }
  md += "| leave-one-run-out RMSE | " + Um(report["cv_rmse_before_mm"]) + " | " +
        Um(report["cv_rmse_after_mm"]) + " |\n";
  md += "| held-out RMSE | " + Um(report["rmse_before_mm"]) + " | " + Um(report["rmse_after_mm"]) +
        " |\n\n";
  md += "## Residual structure\n\n| | before | after |\n|---|---|---|\n";
  const auto& rs = report["residual_structure"];
  for (const char* k : {"lag1_autocorrelation", "between_run_share", "durbin_watson"}) {
    md += std::string("| ") + k + " | " + Num(rs["before"][k], "%.3f") + " | " +
          Num(rs["after"][k], "%.3f") + " |\n";
  }
  if (report.contains("model") && report["model"].is_object()) {
    md += "\n## Model\n\nVersion " + std::to_string(report["model"].value("version", 0)) + ": " +
          report["model"].value("status", "") + ". " + report["model"].value("reason", "") + ".\n";
  }
  return md;
}

std::string AnalysisHtml(const nlohmann::json& report) {
  // Bars of the three error measures, before (grey) and after (blue).
  std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' width='420' height='130'>";
  const char* keys[3][3] = {{"training", "train_rmse_before_mm", "train_rmse_after_mm"},
                            {"cross-validation", "cv_rmse_before_mm", "cv_rmse_after_mm"},
                            {"held-out", "rmse_before_mm", "rmse_after_mm"}};
  double top = 1e-9;
  for (auto& k : keys) {
    for (int s = 1; s < 3; ++s) {
      if (report[k[s]].is_number()) top = std::max(top, report[k[s]].get<double>());
    }
  }
  for (int i = 0; i < 3; ++i) {
    const int y = 10 + i * 40;
    svg +=
        "<text x='0' y='" + std::to_string(y + 14) + "' font-size='12'>" + keys[i][0] + "</text>";
    for (int s = 1; s < 3; ++s) {
      const double v = report[keys[i][s]].is_number() ? report[keys[i][s]].get<double>() : 0.0;
      const int w = static_cast<int>(250.0 * v / top);
      svg += "<rect x='110' y='" + std::to_string(y + (s - 1) * 14) + "' width='" +
             std::to_string(w) + "' height='12' fill='" + (s == 1 ? "#999" : "#2a6ebb") +
             "'/><text x='" + std::to_string(115 + w) + "' y='" +
             std::to_string(y + (s - 1) * 14 + 10) + "' font-size='10'>" + Um(report[keys[i][s]]) +
             " um</text>";
    }
  }
  svg += "</svg>";
  std::string md = AnalysisMarkdown(report);
  return "<!doctype html><html><head><meta charset='utf-8'><title>Effect analysis</title>"
         "</head><body><pre>" +
         Escape(md) + "</pre><p>RMSE before (grey) and after (blue):</p>" + svg +
         "</body></html>\n";
}

}  // namespace thermocomp
