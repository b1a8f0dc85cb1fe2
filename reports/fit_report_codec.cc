#include "reports/fit_report_codec.h"

#include <cmath>

#include "core/time_format.h"
#include "reports/json_read.h"
#include "reports/model_codec.h"

namespace thermocomp {
namespace {

using json_read::ArrayAt;
using json_read::NumberOr;
using json_read::ObjectAt;
using json_read::ValueOr;
using nlohmann::json;

json ErrorsToJson(const HeldOutErrors& e, bool computed) {
  return {{"rmse_mm", computed ? FiniteOrNull(e.rmse_mm) : nullptr},
          {"r2", computed ? FiniteOrNull(e.r2) : nullptr}};
}

HeldOutErrors ErrorsFromJson(const json& j, const char* count_key) {
  return {ValueOr<int>(j, count_key, 0), NumberOr(j, "rmse_mm"), NumberOr(j, "r2")};
}

json ResidualsToJson(const FitResiduals& r) {
  json largest = json::array();
  for (const auto& l : r.largest) {
    largest.push_back(
        {{"run", l.run}, {"k", l.k}, {"ts", FormatRfc3339(l.ts_ms)}, {"value", l.value}});
  }
  json out = {{"standardized_max_abs", r.standardized_max_abs},
              {"standardized_over_2", r.standardized_over_2},
              {"largest", largest}};
  if (const auto& c = r.checks) {
    out["skewness"] = c->skewness;
    out["excess_kurtosis"] = c->excess_kurtosis;
    out["normal"] = c->normal;
    out["goldfeld_quandt"] = {{"f", FiniteOrNull(c->goldfeld_quandt)},
                              {"p", FiniteOrNull(c->goldfeld_quandt_p)},
                              {"df", {c->gq_df1, c->gq_df2}}};
    out["homoscedastic"] = c->homoscedastic;
  }
  return out;
}

FitResiduals ResidualsFromJson(const json& j) {
  FitResiduals r;
  r.standardized_max_abs = NumberOr(j, "standardized_max_abs", 0);
  r.standardized_over_2 = ValueOr<int64_t>(j, "standardized_over_2", 0);
  for (const auto& l : ArrayAt(j, "largest")) {
    const auto ts = ParseRfc3339(l.value("ts", ""));
    r.largest.push_back(
        {l.value("run", ""), l.value("k", 0), ts.value_or(0), NumberOr(l, "value", 0)});
  }
  if (j.contains("skewness")) {
    ResidualChecks c;
    c.skewness = NumberOr(j, "skewness");
    c.excess_kurtosis = NumberOr(j, "excess_kurtosis");
    c.normal = j.value("normal", true);
    c.homoscedastic = j.value("homoscedastic", true);
    const json& gq = ObjectAt(j, "goldfeld_quandt");
    c.goldfeld_quandt = NumberOr(gq, "f");
    c.goldfeld_quandt_p = NumberOr(gq, "p");
    const json& df = ArrayAt(gq, "df");
    if (df.size() == 2) {
      c.gq_df1 = df[0].get<int>();
      c.gq_df2 = df[1].get<int>();
    }
    r.checks = c;
  }
  return r;
}

}  // namespace

json FitReportToJson(const FitReport& r) {
  const DriftModel& m = r.model;
  const LinearFit& fit = r.fit;
  json coefficients = {{"intercept", m.intercept}};
  json ranges = json::object();
  for (size_t j = 0; j < m.inputs.size(); ++j) {
    coefficients[m.inputs[j]] = m.coefficients[j];
    ranges[m.inputs[j]] = {{"min", m.trained[j].min}, {"max", m.trained[j].max}};
  }
  json removed_terms = json::array();
  for (const auto& t : r.removed_terms) {
    removed_terms.push_back({{"term", t.name},
                             {"reason", t.reason},
                             {"p", FiniteOrNull(t.p)},
                             {"vif", FiniteOrNull(t.vif)}});
  }
  json cv = ErrorsToJson(r.cross_validation, true);
  cv["method"] = "leave-one-run-out";
  cv["folds"] = r.cross_validation.n;
  json validation = ErrorsToJson(r.validation, r.validation.n > 0);
  validation["runs"] = r.validation_runs;
  validation["n"] = r.validation.n;
  json out = {
      {"machine", r.machine},
      {"axis", r.axis},
      {"status", r.status},
      {"reason", r.reason},
      {"trigger", r.trigger},
      {"created_at", FormatRfc3339(r.created_ms)},
      {"declared_inputs", r.declared_inputs},
      {"inputs", m.inputs},
      {"coefficients", coefficients},
      {"unit", "mm per degC of temperature change since the run's datum"},
      {"n", fit.n},
      {"r2", fit.r2},
      {"adj_r2", fit.adj_r2},
      {"rmse_mm", fit.rmse},
      {"sigma_mm", fit.sigma},
      {"f", FiniteOrNull(fit.f)},
      {"f_p", FiniteOrNull(fit.f_p)},
      {"durbin_watson", fit.durbin_watson},
      {"terms", FitTermsJson(fit)},
      {"residuals", ResidualsToJson(r.residuals)},
      {"removed_terms", removed_terms},
      {"removed_outliers", r.removed_outliers},
      {"outlier_steps", r.outlier_steps},
      {"skipped",
       {{"gross_errors", r.skipped_gross_errors},
        {"no_datum", r.skipped_no_datum},
        {"compensated_unserved", r.skipped_unserved}}},
      {"training_runs", r.training_runs},
      {"training_range", ranges},
      {"cross_validation", cv},
      {"validation", validation},
      {"acceptance", {{"passed", r.accepted}, {"reasons", r.acceptance_reasons}}},
  };
  if (const auto& c = r.compared_with) {
    const bool compared = std::isfinite(c->active_rmse_mm);
    out["compared_with"] = {
        {"version", c->version},
        {"validation_rmse_mm", compared ? FiniteOrNull(c->active_rmse_mm) : nullptr},
        {"candidate_rmse_mm", compared ? FiniteOrNull(c->candidate_rmse_mm) : nullptr}};
  }
  if (r.version) out["version"] = *r.version;
  return out;
}

StatusOr<FitReport> FitReportFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("fit report: not a JSON object");
  try {
    FitReport r;
    r.machine = j.value("machine", "");
    r.axis = j.value("axis", "");
    r.status = j.value("status", "");
    r.reason = j.value("reason", "");
    r.trigger = j.value("trigger", "");
    r.created_ms = ParseRfc3339(j.value("created_at", "")).value_or(0);
    if (j.contains("version") && j["version"].is_number_integer()) r.version = j["version"];
    r.declared_inputs = j.value("declared_inputs", std::vector<std::string>{});

    DriftModel& m = r.model;
    m.inputs = j.value("inputs", std::vector<std::string>{});
    const json& coefficients = ObjectAt(j, "coefficients");
    const json& ranges = ObjectAt(j, "training_range");
    m.intercept = NumberOr(coefficients, "intercept", 0);
    for (const auto& name : m.inputs) {
      m.coefficients.push_back(NumberOr(coefficients, name.c_str(), 0));
      const json& range = ObjectAt(ranges, name.c_str());
      m.trained.push_back({NumberOr(range, "min", 0), NumberOr(range, "max", 0)});
    }

    LinearFit& fit = r.fit;
    fit.n = j.value("n", 0);
    fit.r2 = NumberOr(j, "r2");
    fit.adj_r2 = NumberOr(j, "adj_r2");
    fit.rmse = NumberOr(j, "rmse_mm");
    fit.sigma = NumberOr(j, "sigma_mm");
    fit.f = NumberOr(j, "f");
    fit.f_p = NumberOr(j, "f_p");
    fit.durbin_watson = NumberOr(j, "durbin_watson");
    for (const auto& [name, t] : ObjectAt(j, "terms").items()) {
      fit.terms.push_back({name, NumberOr(t, "estimate", 0), NumberOr(t, "std_error"),
                           NumberOr(t, "t"), NumberOr(t, "p"), NumberOr(t, "vif")});
    }
    fit.k = static_cast<int>(m.inputs.size());

    r.residuals = ResidualsFromJson(ObjectAt(j, "residuals"));
    for (const auto& t : ArrayAt(j, "removed_terms")) {
      r.removed_terms.push_back(
          {t.value("term", ""), t.value("reason", ""), NumberOr(t, "p"), NumberOr(t, "vif")});
    }
    r.removed_outliers = j.value("removed_outliers", int64_t{0});
    r.outlier_steps = j.value("outlier_steps", 0);
    const json& skipped = ObjectAt(j, "skipped");
    r.skipped_gross_errors = skipped.value("gross_errors", 0);
    r.skipped_no_datum = skipped.value("no_datum", 0);
    r.skipped_unserved = skipped.value("compensated_unserved", 0);  // absent before 0008
    r.training_runs = j.value("training_runs", 0);
    r.cross_validation = ErrorsFromJson(ObjectAt(j, "cross_validation"), "folds");
    const json& validation = ObjectAt(j, "validation");
    r.validation = ErrorsFromJson(validation, "n");
    r.validation_runs = validation.value("runs", std::vector<std::string>{});
    const json& acceptance = ObjectAt(j, "acceptance");
    r.accepted = acceptance.value("passed", false);
    r.acceptance_reasons = acceptance.value("reasons", std::vector<std::string>{});
    if (j.contains("compared_with") && j["compared_with"].is_object()) {
      const json& c = j["compared_with"];
      r.compared_with = ActiveComparison{c.value("version", 0), NumberOr(c, "validation_rmse_mm"),
                                         NumberOr(c, "candidate_rmse_mm")};
    }
    return r;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("fit report: ") + e.what());
  }
}

}  // namespace thermocomp
