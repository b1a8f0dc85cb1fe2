// Routes of what the line and quality staff read: the compensation (JSON
// and each control's format), what the controls report they applied, what
// it achieved, and the drift history.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/controller_formats.h"
#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "core/time_format.h"
#include "reports/drift_history_codec.h"
#include "reports/json_fields.h"
#include "reports/outcome_codec.h"
#include "service/applied_compensation_service.h"

namespace thermocomp::api {
using nlohmann::json;
namespace {

constexpr int64_t kDefaultOutcomeSpanMs = 28 * 86400000LL;
// Buckets one answer may hold: days over almost three years.
constexpr int64_t kMaxOutcomeBuckets = 1000;

bool ParseOutcomeQuery(const Req& req, int64_t now_ms, OutcomeQuery& q, FieldErrors& errors) {
  if (req.has_param("axis")) {
    q.axis = req.get_param_value("axis");
    if (!ValidAxisName(*q.axis)) errors.push_back({0, "axis", "must be one of X Y Z A B C U V W"});
  }
  const std::string bucket = req.has_param("bucket") ? req.get_param_value("bucket") : "day";
  if (bucket == "week") {
    q.bucket = OutcomeBucketSize::kWeek;
  } else if (bucket != "day") {
    errors.push_back({0, "bucket", "must be day or week"});
  }
  // The range: `to` defaults to now, `from` to 28 days before `to`.
  q.to_ms = now_ms;
  q.from_ms = 0;
  size_t unused = 0;
  if (!ParseTimeRange(req, q.from_ms, q.to_ms, unused, 0, errors)) return false;
  if (!req.has_param("from")) q.from_ms = q.to_ms - kDefaultOutcomeSpanMs;
  if (q.from_ms > q.to_ms) errors.push_back({0, "from", "must not be after to"});
  const int64_t bucket_ms = (q.bucket == OutcomeBucketSize::kWeek ? 7 : 1) * 86400000LL;
  if (errors.empty() && (q.to_ms - q.from_ms) / bucket_ms + 2 > kMaxOutcomeBuckets) {
    errors.push_back({0, "from",
                      "the range holds more than 1000 buckets; use bucket=week or a "
                      "shorter range"});
  }
  return errors.empty();
}

// The body of POST .../compensation/applied. Unknown fields are ignored,
// as in the other JSON bodies; a stated value given as null is not stated.
AppliedInput ParseAppliedBody(const json& body, FieldErrors& errors) {
  JsonFields f(body, errors);
  AppliedInput in;
  in.axis = f.String("axis", JsonFields::kRequired, 64).value_or("");
  in.sequence = f.Integer("sequence", JsonFields::kRequired, 0, kMaxAppliedSequence).value_or(0);
  auto value = [&](const char* key) -> std::optional<double> {
    if (body.contains(key) && body[key].is_null()) return std::nullopt;
    return f.Number(key, JsonFields::kOptional, -kMaxAppliedValue, kMaxAppliedValue);
  };
  in.offset_mm = value("offset_mm");
  in.slope_um_per_m = value("slope_um_per_m");
  in.offset_at_probe_mm = value("offset_at_probe_mm");
  if (auto via = f.String("via", JsonFields::kOptional, 64)) {
    if (std::string why = AppliedViaError(*via); !why.empty()) errors.push_back({0, "via", why});
    in.via = *via;
  }
  return in;
}

json AppliedRecordJson(const std::string& machine, const std::string& axis,
                       const AppliedRecord& r) {
  json j = {{"machine", machine}, {"axis", axis}};
  j.update(AppliedToJson(r));
  return j;
}

// The history's page: 1..1000 records, 100 unless asked.
constexpr int kDefaultAppliedLimit = 100;
constexpr int kMaxAppliedLimit = 1000;

}  // namespace

void HttpServer::CompensationRoutes() {
  auto& s = server_;
  const std::string& m = kMachinePath;
  s.Get(m + "/compensation", [this](const Req& req, Res& res) {
    auto c = app_.compensation().Get(req.matches[1]);
    if (!c.ok()) return WriteProblem(res, c.status());
    // A control polls this: no cache between may hand it an older value.
    res.set_header("Cache-Control", "no-store");
    std::string format = req.get_param_value("format");
    if (format.empty() || format == "json") {
      auto applied = app_.applied().Newest(req.matches[1]);
      if (!applied.ok()) return WriteProblem(res, applied.status());
      return res.set_content(CompensationBody(req.matches[1], *c, *applied), "application/json");
    }
    if (format == "native") {
      if (!KnownControllerFormat((*c)->controller)) {
        return WriteProblem(res, 400,
                            "format: native: the machine's control '" + (*c)->controller +
                                "' has no native format; use json",
                            {{0, "format", "no native format for '" + (*c)->controller + "'"}});
      }
      format = (*c)->controller;
    }
    if (!KnownControllerFormat(format)) {
      return WriteProblem(
          res, 400,
          "format: must be json, native, sinumerik, beckhoff, heidenhain, fanuc or linuxcnc",
          {{0, "format", "unknown format '" + format + "'"}});
    }
    res.set_content(RenderForController(**c, format), "text/plain");
  });

  s.Post(m + "/compensation/applied", [this](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    const AppliedInput in = ParseAppliedBody(*body, errors);
    if (!errors.empty()) {
      return WriteProblem(res, Status::InvalidArgument("invalid applied compensation"), errors);
    }
    auto r = app_.applied().Record(req.matches[1], in, Actor(req), &errors);
    if (!r.ok()) return WriteProblem(res, r.status(), errors);
    WriteJson(res, AppliedRecordJson(req.matches[1], r->axis, r->record), r->created ? 201 : 200);
  });

  s.Get(m + "/compensation/applied", [this](const Req& req, Res& res) {
    FieldErrors errors;
    const std::string axis = req.get_param_value("axis");
    if (!req.has_param("axis")) errors.push_back({0, "axis", "required"});
    int limit = kDefaultAppliedLimit;
    if (req.has_param("limit")) {
      const std::string text = req.get_param_value("limit");
      if (text.empty() || text.size() > 4 ||
          text.find_first_not_of("0123456789") != std::string::npos || std::stoi(text) < 1 ||
          std::stoi(text) > kMaxAppliedLimit) {
        errors.push_back({0, "limit", "must be an integer from 1 to 1000"});
      } else {
        limit = std::stoi(text);
      }
    }
    if (!errors.empty()) {
      return WriteProblem(res, Status::InvalidArgument("invalid applied query"), errors);
    }
    auto history = app_.applied().History(req.matches[1], axis, limit);
    if (!history.ok()) return WriteProblem(res, history.status());
    json records = json::array();
    for (const AppliedRecord& r : *history)
      records.push_back(AppliedRecordJson(req.matches[1], axis, r));
    WriteJson(res, {{"machine", req.matches[1]}, {"axis", axis}, {"records", records}});
  });

  s.Get(m + "/compensation/outcome", [this](const Req& req, Res& res) {
    OutcomeQuery q;
    FieldErrors errors;
    if (!ParseOutcomeQuery(req, app_.clock().NowMs(), q, errors)) {
      return WriteProblem(res, Status::InvalidArgument("invalid outcome query"), errors);
    }
    q.machine = req.matches[1];
    auto o = app_.outcomes().Outcome(q);
    if (!o.ok()) return WriteProblem(res, o.status());
    WriteJson(res, MachineOutcomeToJson(*o));
  });

  s.Get(m + "/drift", [this](const Req& req, Res& res) {
    HistoryQuery q;
    FieldErrors errors;
    if (!ParseHistoryQuery(req, q, errors)) {
      return WriteProblem(res, Status::InvalidArgument("invalid drift query"), errors);
    }
    q.machine = req.matches[1];
    auto h = app_.history().Drift(q);
    if (!h.ok()) return WriteProblem(res, h.status());
    WriteJson(res, DriftHistoryToJson(*h));
  });
}

}  // namespace thermocomp::api
