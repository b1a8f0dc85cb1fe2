// Feed-axis routes (docs/api.md, "Feed axes"): an axis' ball-screw
// configuration, its feed-axis models (list, one, activation) and their
// refit. Parse, call FeedAxisService or FeedFitService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/problem.h"
#include "core/time_format.h"
#include "reports/feed_fit_report_codec.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

// Stored JSON as JSON (null if it does not parse: it was written by us).
json Parsed(const std::string& text) {
  json j = json::parse(text, nullptr, false);
  return j.is_discarded() ? json() : j;
}

// The held-out summary of this version from the report of the fit that
// made it: the type's scores on the checks it was not fitted on.
json HeldOutSummary(const FeedModelRecord& m, const json& report) {
  if (!report.is_object() || !report.contains("types") || !report["types"].is_array()) {
    return nullptr;
  }
  for (const json& t : report["types"]) {
    if (!t.is_object() || t.value("type", "") != m.type || t.value("version", 0) != m.version ||
        !t.contains("held_out") || !t["held_out"].is_object()) {
      continue;
    }
    const json& h = t["held_out"];
    json out = json::object();
    for (const char* key : {"max_before_um", "max_after_um", "rms_after_um", "reduction"}) {
      if (h.contains(key)) out[key] = h[key];
    }
    out["checks"] = h.contains("checks") && h["checks"].is_array() ? h["checks"].size() : 0;
    return out;
  }
  return nullptr;
}

json ModelSummary(const FeedModelRecord& m) {
  return {{"version", m.version},
          {"type", m.type},
          {"status", m.status},
          {"reason", m.reason},
          {"created_at", FormatRfc3339(m.created_ms)},
          {"held_out", HeldOutSummary(m, Parsed(m.report_json))}};
}

json ModelInFull(const FeedModelRecord& m) {
  json j = ModelSummary(m);
  j["model"] = Parsed(m.model_json);
  j["report"] = Parsed(m.report_json);
  return j;
}

}  // namespace

void HttpServer::FeedAxisRoutes() {
  // The guarded server's own Get and Post (api/guarded_server.h), as in
  // api/check_routes.cc: its writes release the anonymous worker share,
  // get a compressed body inflated, and count under their route names.
  GuardedServer& s = server_;
  const std::string& axis = kAxisPath;

  s.Put(axis + "/screw", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    auto created =
        app_.feed_axes().PutConfig(req.matches[1], req.matches[2], *body, Actor(req), &errors);
    if (!created.ok()) return WriteProblem(res, created.status(), errors);
    auto config = app_.feed_axes().Config(req.matches[1], req.matches[2]);
    if (!config.ok()) return WriteProblem(res, config.status());
    WriteJson(res, FeedAxisConfigToJson(*config), *created ? 201 : 200);
  });
  s.Get(axis + "/screw", [this](const Req& req, Res& res) {
    auto config = app_.feed_axes().Config(req.matches[1], req.matches[2]);
    if (!config.ok()) return WriteProblem(res, config.status());
    WriteJson(res, FeedAxisConfigToJson(*config));
  });

  s.Post(axis + "/feed-models/fit", [this](const Req& req, Res& res) {
    auto report = app_.feed_fit().Fit(req.matches[1], req.matches[2], Actor(req));
    if (!report.ok()) return WriteProblem(res, report.status());
    WriteJson(res, FeedFitReportToJson(*report), 201);
  });
  s.Get(axis + "/feed-models", [this](const Req& req, Res& res) {
    auto list = app_.feed_axes().Models(req.matches[1], req.matches[2]);
    if (!list.ok()) return WriteProblem(res, list.status());
    json models = json::array();
    for (const FeedModelRecord& m : *list) models.push_back(ModelSummary(m));
    WriteJson(res, {{"machine", req.matches[1].str()},
                    {"axis", req.matches[2].str()},
                    {"models", std::move(models)}});
  });
  s.Get(axis + "/feed-models/([0-9]{1,9})", [this](const Req& req, Res& res) {
    auto one = app_.feed_axes().Model(req.matches[1], req.matches[2], std::stoi(req.matches[3]));
    if (!one.ok()) return WriteProblem(res, one.status());
    WriteJson(res, ModelInFull(*one));
  });
  s.Post(axis + "/feed-models/([0-9]{1,9})/activate", [this](const Req& req, Res& res) {
    const int version = std::stoi(req.matches[3]);
    auto audit = app_.feed_axes().Activate(req.matches[1], req.matches[2], version, Actor(req));
    if (!audit.ok()) return WriteProblem(res, audit.status());
    auto one = app_.feed_axes().Model(req.matches[1], req.matches[2], version);
    json out = one.ok() ? ModelSummary(*one) : json{{"version", version}};
    out["audit"] = {{"ts", FormatRfc3339(audit->ts_ms)},
                    {"actor", audit->actor},
                    {"action", audit->action},
                    {"machine", audit->machine},
                    {"detail", audit->detail}};
    WriteJson(res, out);
  });
}

}  // namespace thermocomp::api
