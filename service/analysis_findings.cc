#include "service/analysis_findings.h"

#include <cmath>
#include <cstdio>

#include "core/time_format.h"
#include "service/model_codec.h"

namespace thermocomp {
namespace {

// "Since the <event> on <date> (<axis> axis, ...): <statement>."
std::string EventStatement(const EventComparison& e, const std::string& axis,
                           const std::string& statement) {
  std::string out = "Since the ";
  out += e.event.kind;
  out += " on ";
  out += FormatRfc3339(e.event.ts_ms).substr(0, 10);
  out += " (";
  out += axis;
  out += " axis, declared model fitted on each side): ";
  out += statement;
  out += ".";
  return out;
}

std::string Fixed(const nlohmann::json& v, const char* format) {
  if (!v.is_number()) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v.get<double>());
  return buf;
}

std::string Um(const nlohmann::json& mm) {
  return mm.is_number() ? Fixed(mm.get<double>() * 1000.0, "%.2f") : "-";
}

// "-7.0 um/degC": a coefficient in mm per unit of its term, in um.
std::string UmPer(double mm, const std::string& unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%+.2f um/%s", mm * 1000.0, unit.c_str());
  return buf;
}

std::string Confidence(const nlohmann::json& g) {
  if (!g.is_object()) return "-";
  const nlohmann::json relative = g.value("relative", nlohmann::json());
  return (relative.is_number() ? Fixed(relative.get<double>() * 100.0, "%.1f") : "-") + " % (t " +
         Fixed(g.value("t", nlohmann::json()), "%.1f") + ", " +
         std::to_string(g.value("blocks", 0)) + " blocks)";
}

}  // namespace

nlohmann::json GainJson(const PairedGain& g) {
  return {{"gain_mm2", FiniteOrNull(g.gain)},
          {"se_mm2", FiniteOrNull(g.se)},
          {"t", FiniteOrNull(g.t)},
          {"relative", FiniteOrNull(g.relative)},
          {"blocks", g.blocks}};
}

void AddEffectFindings(const AddedEffect& e, nlohmann::json& effect) {
  effect["confidence"] = GainJson(e.confidence);
  nlohmann::json alternatives = nlohmann::json::array();
  for (const auto& a : e.alternatives) {
    alternatives.push_back({{"name", a.term.Name()}, {"confidence", GainJson(a.gain)}});
  }
  effect["alternatives"] = alternatives;
  if (!e.replaces.empty()) effect["replaces"] = e.replaces;
  if (!e.revises_declared.empty()) effect["revises_declared"] = e.revises_declared;
  if (!e.together_with.empty()) effect["together_with"] = e.together_with;
}

void AddFindings(const EffectSearchResult& r, const std::string& axis, nlohmann::json& report) {
  report["validation"] = {
      {"method", "blocked cross-validation (" + r.block_kind +
                     " blocks), paired block-to-block gains, forward-chained check of the "
                     "newest blocks"},
      {"block", r.block_kind},
      {"blocks", r.blocks},
      {"rmse_before_mm", FiniteOrNull(r.blocked_rmse_before_mm)},
      {"rmse_after_mm", FiniteOrNull(r.blocked_rmse_after_mm)}};
  nlohmann::json noise = nlohmann::json::object();
  for (const auto& [sensor, sigma] : r.sensor_noise_c) noise[sensor] = FiniteOrNull(sigma);
  report["sensor_noise_c"] = noise;
  nlohmann::json filters = nlohmann::json::array();
  for (const auto& f : r.filters) {
    filters.push_back({{"sensor", f.sensor},
                       {"noise_c", FiniteOrNull(f.noise_c)},
                       {"interval_min", FiniteOrNull(f.interval_min)},
                       {"current_alpha", FiniteOrNull(f.current_alpha)},
                       {"current_tau_min", FiniteOrNull(f.current_tau_min)},
                       {"recommended_alpha", FiniteOrNull(f.recommended_alpha)},
                       {"recommended_tau_min", FiniteOrNull(f.recommended_tau_min)},
                       {"expected_gain_mm2", FiniteOrNull(f.expected_gain_mm2)},
                       {"validated", GainJson(f.validated)},
                       {"applied", f.applied}});
  }
  report["filters"] = filters;
  nlohmann::json aside = nlohmann::json::array();
  for (const auto& s : r.set_aside) {
    aside.push_back({{"name", s.candidate.term.Name()},
                     {"reason", s.reason},
                     {"confidence", GainJson(s.candidate.gain)}});
  }
  report["set_aside"] = aside;
  nlohmann::json ambiguous = nlohmann::json::array();
  for (const auto& a : r.ambiguous) {
    ambiguous.push_back({{"name", a.term.Name()}, {"confidence", GainJson(a.gain)}});
  }
  report["ambiguous"] = ambiguous;
  nlohmann::json changes = nlohmann::json::array();
  for (const auto& c : r.coefficient_changes) {
    changes.push_back({{"term", c.term},
                       {"before", FiniteOrNull(c.before_mm)},
                       {"after", FiniteOrNull(c.after_mm)}});
  }
  report["coefficient_changes"] = changes;
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : r.event_comparisons) {
    nlohmann::json terms = nlohmann::json::array();
    std::string statement;
    for (size_t k = 0; k < e.terms.size(); ++k) {
      terms.push_back({{"name", e.terms[k]},
                       {"before", FiniteOrNull(e.before_mm[k])},
                       {"after", FiniteOrNull(e.after_mm[k])}});
      if (!std::isfinite(e.before_mm[k]) || !std::isfinite(e.after_mm[k])) continue;
      statement += (statement.empty() ? "" : "; ") + e.terms[k] + "'s sensitivity is " +
                   UmPer(e.after_mm[k], "degC") + " instead of " + UmPer(e.before_mm[k], "degC");
    }
    events.push_back({{"event", {{"ts", FormatRfc3339(e.event.ts_ms)}, {"kind", e.event.kind}}},
                      {"runs_before", e.runs_before},
                      {"runs_after", e.runs_after},
                      {"terms", terms},
                      {"rmse_before_mm", FiniteOrNull(e.rmse_before_mm)},
                      {"rmse_after_mm", FiniteOrNull(e.rmse_after_mm)},
                      {"statement", EventStatement(e, axis, statement)}});
  }
  report["event_comparisons"] = events;
}

std::string FindingsMarkdown(const nlohmann::json& report) {
  std::string md;
  if (report.contains("validation") && report["validation"].is_object()) {
    const auto& v = report["validation"];
    md += "## Validation\n\n" + v.value("method", "") + ": " +
          std::to_string(v.value("blocks", 0)) + " blocks; RMSE " +
          Um(v.value("rmse_before_mm", nlohmann::json())) + " -> " +
          Um(v.value("rmse_after_mm", nlohmann::json())) + " um.\n\n";
  }
  if (report.contains("effects")) {
    std::string rows;
    for (const auto& e : report["effects"]) {
      if (!e.contains("confidence")) continue;
      std::string alternatives;
      for (const auto& a : e["alternatives"]) {
        alternatives += (alternatives.empty() ? "" : ", ") + ("`" + a.value("name", "") + "`");
      }
      std::string notes;
      if (e.contains("replaces")) notes += "replaces `" + e.value("replaces", "") + "`; ";
      if (e.contains("revises_declared")) notes += e.value("revises_declared", "") + "; ";
      if (e.contains("together_with")) {
        notes += "qualified together with `" + e.value("together_with", "") + "`; ";
      }
      rows += "| `" + e.value("name", "") + "` | " + Confidence(e["confidence"]) + " | " +
              (alternatives.empty() ? "none" : alternatives) + " | " +
              (notes.empty() ? "-" : notes) + " |\n";
    }
    if (!rows.empty()) {
      md +=
          "## Confidence\n\nThe validated gain (share of the blocked cross-validation error "
          "removed, and its t over blocks):\n\n| effect | gain | equally good | notes |\n"
          "|---|---|---|---|\n" +
          rows + "\n";
    }
  }
  if (report.contains("coefficient_changes") && !report["coefficient_changes"].empty()) {
    md +=
        "## Declared coefficients (um per unit)\n\n| term | declared model | extended model |\n"
        "|---|---|---|\n";
    for (const auto& c : report["coefficient_changes"]) {
      md +=
          "| `" + c.value("term", "") + "` | " + Um(c["before"]) + " | " + Um(c["after"]) + " |\n";
    }
    md += "\n";
  }
  if (report.contains("filters") && !report["filters"].empty()) {
    md += "## Filters\n\n";
    for (const auto& f : report["filters"]) {
      md += "- `" + f.value("sensor", "") + "`: white noise " + Fixed(f["noise_c"], "%.3f") +
            " degC every " + Fixed(f["interval_min"], "%.2f") + " min; read through tau " +
            Fixed(f["recommended_tau_min"], "%.1f") + " min (ewma_alpha " +
            Fixed(f["recommended_alpha"], "%.3f") + ") instead of " +
            Fixed(f["current_tau_min"], "%.1f") + " min (" + Fixed(f["current_alpha"], "%.3f") +
            "): " + Confidence(f["validated"]) + (f.value("applied", false) ? ", applied" : "") +
            ".\n";
    }
    md += "\n";
  }
  if (report.contains("ambiguous") && !report["ambiguous"].empty()) {
    md +=
        "## Ambiguous\n\nEqually good explanations within the validation's uncertainty; "
        "none was added: ";
    std::string list;
    for (const auto& a : report["ambiguous"]) {
      list += (list.empty() ? "" : ", ") + ("`" + a.value("name", "") + "`");
    }
    md += list + ".\n\n";
  }
  if (report.contains("set_aside") && !report["set_aside"].empty()) {
    md += "## Set aside\n\n";
    for (const auto& s : report["set_aside"]) {
      md += "- `" + s.value("name", "") + "` (" + Confidence(s["confidence"]) +
            "): " + s.value("reason", "") + ".\n";
    }
    md += "\n";
  }
  if (report.contains("event_comparisons") && !report["event_comparisons"].empty()) {
    md += "## Events\n\n";
    for (const auto& e : report["event_comparisons"]) {
      md += "- " + e.value("statement", "") + " Runs " + std::to_string(e.value("runs_before", 0)) +
            " before, " + std::to_string(e.value("runs_after", 0)) + " after; RMSE " +
            Um(e["rmse_before_mm"]) + " / " + Um(e["rmse_after_mm"]) + " um.\n";
    }
    md += "\n";
  }
  return md;
}

}  // namespace thermocomp
