// Routes of models and effect analyses: fit, versions, activation,
// analyses and their reports.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "api/report_page.h"
#include "core/time_format.h"
#include "reports/analysis_report_codec.h"
#include "reports/analysis_report_text.h"
#include "reports/fit_report_codec.h"
#include "reports/fit_report_text.h"
#include "reports/json_fields.h"
#include "reports/outcome_codec.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

// A stored version's report, typed, with its status as it is now.
FitReport ModelReportOf(const json& j) {
  auto decoded = FitReportFromJson(j);
  FitReport r = decoded.ok() ? *decoded : FitReport{};
  r.version = j.value("version", 0);
  r.status = j.value("status", "");
  r.reason = j.value("reason", "");
  return r;
}

}  // namespace

void HttpServer::ModelRoutes() {
  auto& s = server_;
  const std::string& axis = kAxisPath;
  s.Post(axis + "/fit", [this](const Req& req, Res& res) {
    FitRequest fr;
    fr.actor = Actor(req);
    if (!req.body.empty()) {
      auto body = JsonObjectBody(req, res);
      if (!body) return;
      FieldErrors errors;
      JsonFields f(*body, errors);
      fr.inputs = f.Strings("inputs");
      fr.holdout_runs = f.Strings("holdout_runs");
      if (!errors.empty())
        return WriteProblem(res, Status::InvalidArgument("invalid fit request"), errors);
    }
    auto report = app_.fits().Fit(req.matches[1], req.matches[2], fr);
    if (!report.ok()) return WriteProblem(res, report.status());
    WriteJson(res, FitReportToJson(*report), 201);
  });
  s.Get(axis + "/models", [this](const Req& req, Res& res) {
    auto list = ListModels(app_, req.matches[1], req.matches[2]);
    if (!list.ok()) return WriteProblem(res, list.status());
    WriteJson(res, *list);
  });
  s.Get(axis + "/models/([0-9]{1,9})", [this](const Req& req, Res& res) {
    auto one = GetModel(app_, req.matches[1], req.matches[2], std::stoi(req.matches[3]));
    if (!one.ok()) return WriteProblem(res, one.status());
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, *one, AsIs,
        [&](const json& j) { return FitReportMarkdown(ModelReportOf(j), time); },
        [&](const json& j) { return FitReportHtml(ModelReportOf(j), time); });
  });
  s.Post(axis + "/models/([0-9]{1,9})/activate", [this](const Req& req, Res& res) {
    const int version = std::stoi(req.matches[3]);
    auto audit = app_.fits().Activate(req.matches[1], req.matches[2], version, Actor(req));
    if (!audit.ok()) return WriteProblem(res, audit.status());
    auto one = GetModel(app_, req.matches[1], req.matches[2], version);
    json out = one.ok() ? *one : json{{"version", version}};
    out["audit"] = {{"ts", FormatRfc3339(audit->ts_ms)},
                    {"actor", audit->actor},
                    {"action", audit->action},
                    {"machine", audit->machine},
                    {"detail", audit->detail}};
    WriteJson(res, out);
  });

  s.Post(axis + "/analysis", [this](const Req& req, Res& res) {
    AnalysisRequest ar;
    ar.actor = Actor(req);
    if (!req.body.empty()) {
      auto body = JsonObjectBody(req, res);
      if (!body) return;
      FieldErrors errors;
      JsonFields f(*body, errors);
      ar.inputs = f.Strings("inputs");
      ar.holdout_runs = f.Strings("holdout_runs");
      if (auto p = f.String("policy", JsonFields::kOptional, 16)) {
        if (*p != "off" && *p != "propose" && *p != "activate") {
          errors.push_back({0, "policy", "must be \"off\", \"propose\" or \"activate\""});
        } else {
          ar.policy = *p;
        }
      }
      if (!errors.empty()) {
        return WriteProblem(res, Status::InvalidArgument("invalid analysis request"), errors);
      }
    }
    auto report = app_.analyses().Analyze(req.matches[1], req.matches[2], ar);
    if (!report.ok()) return WriteProblem(res, report.status());
    WriteJson(res, AnalysisReportToJson(*report), 201);
  });
  s.Get(axis + "/analysis", [this](const Req& req, Res& res) {
    auto list = app_.analyses().List(req.matches[1], req.matches[2]);
    if (!list.ok()) return WriteProblem(res, list.status());
    WriteJson(res, AnalysesToJson(*list));
  });
  s.Get(axis + "/analysis/([0-9]{1,18})", [this](const Req& req, Res& res) {
    auto report = app_.analyses().Get(req.matches[1], req.matches[2], std::stoll(req.matches[3]));
    if (!report.ok()) return WriteProblem(res, report.status());
    // What its model did once applied, beside what the analysis predicted.
    auto with_outcome = [&](const AnalysisReport& r) {
      json j = AnalysisReportToJson(r);
      j["since_applied"] = nullptr;
      if (r.model) {
        auto v = app_.outcomes().SinceServed(req.matches[1], req.matches[2], r.model->version);
        if (v.ok()) j["since_applied"] = VersionOutcomeToJson(*v);
      }
      return j;
    };
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, *report, with_outcome,
        [&](const AnalysisReport& r) { return AnalysisMarkdown(r, time); },
        [&](const AnalysisReport& r) { return AnalysisHtml(r, time); });
  });
}

}  // namespace thermocomp::api
