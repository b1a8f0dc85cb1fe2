// Routes of column checks (artifacts, requests, results) and positioning
// checks (evaluation, reports, pitch tables): parse, call CheckService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include "api/check_reports.h"
#include "api/http_util.h"
#include "api/ingest_parsers.h"
#include "core/time_format.h"
#include "reports/check_report_codec.h"
#include "reports/json_fields.h"

namespace thermocomp::api {
using nlohmann::json;

void HttpServer::CheckRoutes() {
  // The guarded server's own Get and Post: a route registered on httplib::Server
  // directly would skip the worker share's release, the inflation of a
  // compressed body and the route's name in the metrics and the log.
  GuardedServer& s = server_;
  const std::string m = "/api/v1/machines/([A-Za-z0-9_.-]{1,64})";

  s.Put("/api/v1/artifacts/([A-Za-z0-9_.-]{1,64})", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    auto created = app_.checks().PutArtifact(req.matches[1], *body, Actor(req), &errors);
    if (!created.ok()) return WriteProblem(res, created.status(), errors);
    WriteJson(res, {{"artifact", req.matches[1].str()}, {"points", (*body)["points"].size()}},
              *created ? 201 : 200);
  });

  s.Get("/api/v1/artifacts/([A-Za-z0-9_.-]{1,64})", [this](const Req& req, Res& res) {
    auto definition = app_.checks().Artifact(req.matches[1]);
    if (!definition.ok()) return WriteProblem(res, definition.status());
    WriteJson(res, *definition);
  });

  s.Post(m + "/column-checks/requests", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    JsonFields f(*body, errors);
    const std::string reason = f.String("reason").value_or("");
    if (errors.empty() && reason.empty()) errors.push_back({0, "reason", "must not be empty"});
    std::optional<int64_t> due = f.Timestamp("due", JsonFields::kOptional);
    if (!errors.empty()) return WriteProblem(res, 400, "invalid check request", errors);
    const int64_t due_ms =
        due.value_or(app_.clock().NowMs() + int64_t{app_.config().check_due_after_h} * 3600000);
    auto id = app_.checks().RequestCheck(req.matches[1], reason, due_ms, Actor(req));
    if (!id.ok()) return WriteProblem(res, id.status());
    WriteJson(res, {{"id", *id}, {"state", "pending"}, {"due", FormatRfc3339(due_ms)}}, 201);
  });
  s.Get(m + "/column-checks/requests", [this](const Req& req, Res& res) {
    const std::string state = req.get_param_value("state");
    if (!state.empty() && state != "pending" && state != "overdue" && state != "done") {
      return WriteProblem(res, 400, "state: must be pending, overdue or done",
                          {{0, "state", "unknown state '" + state + "'"}});
    }
    auto list = app_.checks().Requests(req.matches[1], state);
    if (!list.ok()) return WriteProblem(res, list.status());
    json out = json::array();
    for (const auto& r : *list) out.push_back(RequestToJson(r));
    WriteJson(res, {{"requests", out}});
  });

  // The id segment takes any text, so that one that is not an id is
  // answered 400 naming it rather than 404 as an unknown path.
  s.Post(m + "/column-checks/requests/([^/]{1,64})/acknowledge", [this](const Req& req, Res& res) {
    const std::string id_text = req.matches[2];
    const bool digits =
        id_text.size() <= 18 && id_text.find_first_not_of("0123456789") == std::string::npos;
    if (!digits) {
      return WriteProblem(res, 400, "invalid acknowledgement",
                          {{0, "id", "must be the integer id of a request"}});
    }
    const std::string actor = Actor(req);
    // Who acknowledges: the body's name, else the caller's token name
    // (none without tokens, where the actor is only an address).
    std::optional<std::string> by;
    if (const std::string token = "token:"; actor.rfind(token, 0) == 0) {
      by = actor.substr(token.size());
    }
    FieldErrors errors;
    if (!req.body.empty()) {
      auto body = JsonObjectBody(req, res);
      if (!body) return;
      JsonFields f(*body, errors);
      if (auto named = f.String("by", JsonFields::kOptional)) by = *named;
      if (!errors.empty()) return WriteProblem(res, 400, "invalid acknowledgement", errors);
    }
    auto view = app_.checks().Acknowledge(req.matches[1], std::stoll(id_text), by, actor, &errors);
    if (!view.ok()) return WriteProblem(res, view.status(), errors);
    WriteJson(res, RequestToJson(*view));
  });

  s.Post(m + "/column-checks", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    auto input = ColumnCheckFromJson(*body, errors);
    if (!input) return WriteProblem(res, 400, "invalid column check", errors);
    bool created = false;
    auto result = app_.checks().AddColumnCheck(req.matches[1], *input, Actor(req), &created);
    if (!result.ok()) return WriteProblem(res, result.status());
    WriteJson(res, ColumnCheckReportToJson(*result), created ? 201 : 200);
  });
  s.Get(m + "/column-checks", [this](const Req& req, Res& res) {
    auto history = app_.checks().ColumnChecks(req.matches[1]);
    if (!history.ok()) return WriteProblem(res, history.status());
    WriteJson(res, ColumnCheckHistoryToJson(*history));
  });

  s.Get(m + "/column-checks/([0-9]{1,18})", [this](const Req& req, Res& res) {
    auto report = app_.checks().ColumnCheck(req.matches[1], std::stoll(req.matches[2]));
    if (!report.ok()) return WriteProblem(res, report.status());
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, ColumnCheckReportToJson(*report), AsIs,
        [&](const json& j) { return ColumnCheckMarkdown(j, time); },
        [&](const json& j) { return ColumnCheckHtml(j, time); });
  });

  s.Post(m + "/positioning-checks", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    FieldErrors errors;
    std::optional<PositioningInput> input;
    if (IsCsv(req)) {
      // Laser-software export; what the CSV does not carry comes as parameters.
      input.emplace();
      PositioningFromQuery(req.params, *input, errors);
      PositioningFromCsv(req.body, input->data, errors);
    } else {
      if (!req.params.empty()) {
        return WriteProblem(res, 400, "query parameters are for text/csv uploads",
                            {{0, req.params.begin()->first, "give it in the JSON body"}});
      }
      Status status;
      auto body = ParseJsonBody(req.body, errors, &status);
      if (!body) return WriteProblem(res, status, errors);
      input = PositioningFromJson(*body, errors);
    }
    if (!errors.empty() || !input)
      return WriteProblem(res, 400, "invalid positioning check", errors);
    if (Status v = ValidatePositioning(input->data); !v.ok()) {
      const std::string& msg = v.message();
      return WriteProblem(res, 422, msg, {{0, msg.substr(0, msg.find(':')), msg}});
    }
    bool created = false;
    auto result = app_.checks().AddPositioningCheck(req.matches[1], *input, Actor(req), &created);
    if (!result.ok()) return WriteProblem(res, result.status());
    WriteJson(res, PositioningCheckReportToJson(*result), created ? 201 : 200);
  });
  s.Get(m + "/positioning-checks", [this](const Req& req, Res& res) {
    for (const auto& [name, value] : req.params) {
      if (name != "axis") {
        return WriteProblem(res, 400, "unknown query parameter '" + name + "'",
                            {{0, name, "this route takes only axis"}});
      }
    }
    const std::string axis = req.get_param_value("axis");
    if (req.get_param_value_count("axis") > 1 ||
        (req.has_param("axis") &&
         (axis.size() != 1 || !std::isupper(static_cast<unsigned char>(axis[0]))))) {
      return WriteProblem(res, 400, "invalid positioning check query",
                          {{0, "axis", "one axis letter, given once (X, Y, Z, ...)"}});
    }
    auto list = app_.checks().PositioningChecks(req.matches[1], axis);
    if (!list.ok()) return WriteProblem(res, list.status());
    WriteJson(res, PositioningCheckListToJson(req.matches[1], *list));
  });
  s.Get(m + "/positioning-checks/([0-9]{1,18})", [this](const Req& req, Res& res) {
    auto report = app_.checks().PositioningCheck(req.matches[1], std::stoll(req.matches[2]));
    if (!report.ok()) return WriteProblem(res, report.status());
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, PositioningCheckReportToJson(*report), AsIs,
        [&](const json& j) { return PositioningMarkdown(j, time); },
        [&](const json& j) { return PositioningHtml(j, time); });
  });
  s.Get(m + "/positioning-checks/([0-9]{1,18})/pitch-table", [this](const Req& req, Res& res) {
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "csv";
    const std::string direction =
        req.has_param("per_direction") ? req.get_param_value("per_direction") : "false";
    FieldErrors errors;
    if (format != "csv" && format != "linuxcnc" && format != "sinumerik" && format != "beckhoff") {
      errors.push_back({0, "format", "must be csv, linuxcnc, sinumerik or beckhoff"});
    }
    if (direction != "true" && direction != "false") {
      errors.push_back({0, "per_direction", "must be true or false"});
    } else if (direction == "true" && format == "sinumerik") {
      // The table written is LEC's one curve per axis (the bidirectional
      // mean, the direction difference as backlash): refused, not ignored.
      errors.push_back({0, "per_direction",
                        "not available for sinumerik: its table is the bidirectional mean "
                        "with the backlash (MD32450); use csv, linuxcnc or beckhoff"});
    }
    if (!errors.empty()) return WriteProblem(res, 400, "invalid pitch table query", errors);
    std::string axis;
    auto table = app_.checks().PitchTableOf(req.matches[1], std::stoll(req.matches[2]), &axis);
    if (!table.ok()) return WriteProblem(res, table.status());
    auto text = RenderPitchTable(*table, axis, format, direction == "true");
    if (!text.ok()) {
      return WriteProblem(res, text.status(), {{0, "format", text.status().message()}});
    }
    res.set_content(*text, format == "csv" ? "text/csv" : "text/plain");
  });
}

}  // namespace thermocomp::api
