// Part-error model routes (docs/api.md, "Part models"): a machine's process
// records (CSV or JSON), the fit of part-error models on them, the stored
// versions (list, one as JSON, Markdown or HTML, activation) and a
// prediction, which is refused, never served unflagged, outside the
// trained ranges. Parse, call PartModelService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <algorithm>
#include <set>

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/parts/process_csv.h"
#include "api/problem.h"
#include "api/report_page.h"
#include "core/process_record.h"
#include "core/time_format.h"
#include "reports/json_fields.h"
#include "reports/parts/part_model_codec.h"
#include "reports/parts/part_model_text.h"
#include "service/parts/process/part_model_service.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

constexpr size_t kDefaultRecordLimit = 1000;

json Parsed(const std::string& text) {
  json j = json::parse(text, nullptr, false);
  return j.is_discarded() ? json() : j;
}

// This version's held-out scores, from the report of the fit that made it.
json HeldOutSummary(const PartModelRecord& m, const json& report) {
  if (!report.is_object() || !report.contains("types") || !report["types"].is_array()) {
    return nullptr;
  }
  for (const json& t : report["types"]) {
    if (t.is_object() && t.value("version", 0) == m.version && t.contains("held_out")) {
      return t["held_out"];
    }
  }
  return nullptr;
}

json ModelSummary(const PartModelRecord& m) {
  const json model = Parsed(m.model_json);
  const json report = Parsed(m.report_json);
  return {{"version", m.version},
          {"target", m.target},
          {"type", m.type},
          {"status", m.status},
          {"reason", m.reason},
          {"created_at", FormatRfc3339(m.created_ms)},
          {"inputs", model.is_object() && model.contains("inputs") ? model["inputs"] : json()},
          {"held_out", HeldOutSummary(m, report)}};
}

json RecordToJson(const ProcessRecordRow& r) {
  json j = {
      {"id", r.id}, {"part", r.part}, {"feature", r.feature}, {"cut_at", FormatRfc3339(r.cut_ms)}};
  for (const std::string& f : ProcessRecordFields()) {
    auto it = r.values.find(f);
    j[f] = it == r.values.end() ? json() : json(it->second);
  }
  return j;
}

json PredictionToJson(const PartPredictionResult& p) {
  json outside = json::array();
  for (const PartOutOfRange& o : p.prediction.outside) {
    outside.push_back({{"input", o.name}, {"value", o.value}, {"low", o.low}, {"high", o.high}});
  }
  json j = {{"version", p.version},
            {"type", p.type},
            {"target", p.target},
            {"valid", p.prediction.valid},
            {"in_range", p.prediction.in_range},
            {"value", p.prediction.value ? json(*p.prediction.value) : json()},
            {"outside", std::move(outside)}};
  if (!p.prediction.valid) j["reason"] = p.prediction.reason;
  return j;
}

// {"records": [{"part", "feature", "cut_at", "ap_mm", ...}]}.
bool ParseRecordsJson(const json& body, std::vector<ProcessRecordInput>& out, FieldErrors& errors) {
  JsonFields f(body, errors);
  const json* records = f.Array("records");
  if (!records) return false;
  if (records->size() > PartModelService::kMaxRecords) {
    errors.push_back(
        {0, "records", "at most " + std::to_string(PartModelService::kMaxRecords) + " records"});
    return false;
  }
  for (size_t i = 0; i < records->size(); ++i) {
    JsonFields item = f.Item((*records)[i], i, "records.");
    if (!item.IsObject("record")) continue;
    ProcessRecordInput r;
    r.part = item.String("part").value_or("");
    r.feature = item.String("feature").value_or("");
    r.cut_ms = item.Timestamp("cut_at").value_or(0);
    for (const std::string& name : ProcessRecordFields()) {
      if (auto v = item.Number(name.c_str(), JsonFields::kOptional)) r.values[name] = *v;
    }
    for (const auto& [key, value] : (*records)[i].items()) {
      const auto& fields = ProcessRecordFields();
      if (key != "part" && key != "feature" && key != "cut_at" &&
          std::find(fields.begin(), fields.end(), key) == fields.end()) {
        errors.push_back({i, "records." + key, "unknown field"});
      }
    }
    out.push_back(std::move(r));
  }
  return errors.empty();
}

bool ParseFitRequest(const json& body, PartFitRequest& request, FieldErrors& errors) {
  JsonFields f(body, errors);
  if (auto t = f.String("target", JsonFields::kOptional, 64)) request.target = *t;
  if (auto in = f.Strings("inputs", JsonFields::kOptional, 16)) request.inputs = *in;
  if (auto ty = f.Strings("types", JsonFields::kOptional, 16)) request.types = *ty;
  if (auto s = f.Number("held_out_share", JsonFields::kOptional, 0.1, 0.5)) {
    request.held_out_share = *s;
  }
  if (auto s = f.Integer("seed", JsonFields::kOptional, 0, int64_t{1} << 53)) {
    request.seed = static_cast<uint64_t>(*s);
  }
  if (auto h = f.Integer("neural_hidden", JsonFields::kOptional, 1, 8)) {
    request.neural_hidden = static_cast<int>(*h);
  }
  if (auto r = f.Integer("neural_restarts", JsonFields::kOptional, 1, 5)) {
    request.neural_restarts = static_cast<int>(*r);
  }
  static const std::set<std::string> known = {
      "target", "inputs", "types", "held_out_share", "seed", "neural_hidden", "neural_restarts"};
  for (const auto& [key, value] : body.items()) {
    if (!known.count(key)) errors.push_back({0, key, "unknown field"});
  }
  return errors.empty();
}

}  // namespace

void HttpServer::PartModelRoutes() {
  // The guarded server's own Get and Post (api/guarded_server.h), as in
  // api/check_routes.cc: its writes release the anonymous worker share,
  // get a compressed body inflated, and count under their route names.
  GuardedServer& s = server_;
  const std::string& machine = kMachinePath;

  s.Post(machine + "/process-records", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    std::vector<ProcessRecordInput> records;
    std::vector<size_t> rows;
    FieldErrors errors;
    if (IsCsv(req)) {
      if (Status st = ParseProcessCsv(req.body, records, rows, errors); !st.ok()) {
        return WriteProblem(res, st, errors);
      }
    } else {
      auto body = JsonObjectBody(req, res);
      if (!body) return;
      if (!ParseRecordsJson(*body, records, errors)) {
        return WriteProblem(res, Status::InvalidArgument("invalid process records"), errors);
      }
    }
    FieldErrors service_errors;
    auto added =
        app_.part_models().AddRecords(req.matches[1], records, Actor(req), &service_errors);
    if (!added.ok()) {
      // CSV: the record's data row, not its index among the parsed records.
      FieldErrors mapped;
      for (const FieldError& e : service_errors) {
        mapped.push_back({rows.empty() || e.index >= rows.size() ? e.index : rows[e.index],
                          rows.empty() ? "records." + e.field : e.field, e.message});
      }
      return WriteProblem(res, added.status(), mapped);
    }
    WriteJson(res, {{"machine", req.matches[1].str()}, {"accepted", *added}}, 201);
  });
  s.Get(machine + "/process-records", [this](const Req& req, Res& res) {
    size_t limit = kDefaultRecordLimit;
    if (req.has_param("limit")) {
      const std::string text = req.get_param_value("limit");
      if (text.empty() || text.size() > 6 ||
          text.find_first_not_of("0123456789") != std::string::npos || std::stoul(text) < 1 ||
          std::stoul(text) > PartModelService::kMaxRecords) {
        return WriteProblem(res, 400, "limit: must be an integer from 1 to 100000",
                            {{0, "limit", "must be an integer from 1 to 100000"}});
      }
      limit = std::stoul(text);
    }
    auto records = app_.part_models().Records(req.matches[1], limit);
    if (!records.ok()) return WriteProblem(res, records.status());
    json items = json::array();
    for (const ProcessRecordRow& r : *records) items.push_back(RecordToJson(r));
    WriteJson(res, {{"machine", req.matches[1].str()}, {"records", std::move(items)}});
  });

  s.Post(machine + "/part-models/fit", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    PartFitRequest request;
    FieldErrors errors;
    if (!ParseFitRequest(*body, request, errors)) {
      return WriteProblem(res, Status::InvalidArgument("invalid fit request"), errors);
    }
    auto report = app_.part_models().Fit(req.matches[1], request, Actor(req), &errors);
    if (!report.ok()) return WriteProblem(res, report.status(), errors);
    const bool stored = std::any_of(report->types.begin(), report->types.end(),
                                    [](const PartTypeResult& t) { return t.version > 0; });
    WriteJson(res, PartFitReportToJson(*report), stored ? 201 : 200);
  });
  s.Get(machine + "/part-models", [this](const Req& req, Res& res) {
    auto list = app_.part_models().Models(req.matches[1]);
    if (!list.ok()) return WriteProblem(res, list.status());
    json models = json::array();
    for (const PartModelRecord& m : *list) models.push_back(ModelSummary(m));
    WriteJson(res, {{"machine", req.matches[1].str()}, {"models", std::move(models)}});
  });
  s.Get(machine + "/part-models/([0-9]{1,9})", [this](const Req& req, Res& res) {
    auto one = app_.part_models().Model(req.matches[1], std::stoi(req.matches[2]));
    if (!one.ok()) return WriteProblem(res, one.status());
    const std::string format = req.get_param_value("format");
    if (format.empty() || format == "json") {
      json j = ModelSummary(*one);
      j["model"] = Parsed(one->model_json);
      j["report"] = Parsed(one->report_json);
      return WriteJson(res, j);
    }
    auto report = PartFitReportFromJson(Parsed(one->report_json));
    if (!report.ok()) return WriteProblem(res, Status::Internal("stored report is unreadable"));
    const PlantTime& time = app_.plant_time();
    if (format == "markdown") {
      return res.set_content(PartFitReportMarkdown(*report, time), "text/markdown");
    }
    if (format == "html") {
      return res.set_content(
          ReportPage("Part model " + req.matches[1].str() + " v" + req.matches[2].str(),
                     PartFitReportMarkdown(*report, time)),
          "text/html");
    }
    WriteProblem(res, 400, "format: must be json, markdown or html",
                 {{0, "format", "unknown format '" + format + "'"}});
  });
  s.Post(machine + "/part-models/([0-9]{1,9})/activate", [this](const Req& req, Res& res) {
    const int version = std::stoi(req.matches[2]);
    auto audit = app_.part_models().Activate(req.matches[1], version, Actor(req));
    if (!audit.ok()) return WriteProblem(res, audit.status());
    auto one = app_.part_models().Model(req.matches[1], version);
    json out = one.ok() ? ModelSummary(*one) : json{{"version", version}};
    out["audit"] = {{"ts", FormatRfc3339(audit->ts_ms)},
                    {"actor", audit->actor},
                    {"action", audit->action},
                    {"machine", audit->machine},
                    {"detail", audit->detail}};
    WriteJson(res, out);
  });
  s.Post(machine + "/part-models/([0-9]{1,9})/predict", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    auto it = body->find("inputs");
    if (it == body->end() || !it->is_object()) {
      return WriteProblem(res, 400, "inputs: required object of input name to number",
                          {{0, "inputs", "required object {\"ap_mm\": 1.2, ...}"}});
    }
    for (const auto& [key, value] : body->items()) {
      if (key != "inputs") errors.push_back({0, key, "unknown field"});
    }
    PartInputs inputs;
    for (const auto& [name, value] : it->items()) {
      if (!value.is_number()) {
        errors.push_back({0, "inputs." + name.substr(0, 64), "must be a number"});
      } else {
        inputs[name.substr(0, 64)] = value.get<double>();
      }
    }
    if (!errors.empty()) {
      return WriteProblem(res, Status::InvalidArgument("invalid inputs"), errors);
    }
    auto p = app_.part_models().Predict(req.matches[1], std::stoi(req.matches[2]), inputs, &errors);
    if (!p.ok()) return WriteProblem(res, p.status(), errors);
    WriteJson(res, PredictionToJson(*p));
  });
}

}  // namespace thermocomp::api
