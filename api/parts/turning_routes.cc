// Turned-part routes (docs/api.md "Turned parts"): record a machine's
// features measured four times (CSV or JSON), page their history, and the
// report per feature in JSON, Markdown or HTML. Parse, call
// TurningService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <charconv>
#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/parts/turning_csv.h"
#include "api/problem.h"
#include "api/report_page.h"
#include "core/time_format.h"
#include "reports/parts/turning_report_text.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

// The problem's detail names where the first error is: "row 3, d_w_mm:
// ..." (CSV data row) or "parts[3].d_w_mm: ..." (JSON item).
void WriteRowProblem(Res& res, const Status& status, const FieldErrors& errors, bool csv) {
  if (errors.empty()) return WriteProblem(res, status);
  const FieldError& e = errors.front();
  std::string where;
  if (e.field == "header" || e.field == "body" || e.field == "parts" || (csv && e.index == 0)) {
    where = e.field;
  } else {
    where = csv ? "row " + std::to_string(e.index) + ", " + e.field
                : "parts[" + std::to_string(e.index) + "]." + e.field;
  }
  WriteProblem(res, HttpStatus(status), status.message() + ": " + where + ": " + e.message, errors);
}

// from and to (cut times, RFC 3339 or Unix ms), defaulting to the whole
// range the API accepts.
bool TimeRange(const Req& req, int64_t& from_ms, int64_t& to_ms, FieldErrors& errors) {
  from_ms = kEarliestTsMs;
  to_ms = kLatestTsMs - 1;
  for (const char* key : {"from", "to"}) {
    if (!req.has_param(key)) continue;
    auto ts = ParseTimestamp(req.get_param_value(key));
    if (!ts) {
      errors.push_back({0, key, "must be RFC 3339 UTC or Unix milliseconds, from 2000 to 2099"});
    } else {
      (std::string(key) == "from" ? from_ms : to_ms) = *ts;
    }
  }
  if (errors.empty() && from_ms > to_ms) errors.push_back({0, "from", "must not be after to"});
  return errors.empty();
}

bool Integer(const Req& req, const char* key, int64_t min, int64_t max, int64_t& out,
             FieldErrors& errors) {
  if (!req.has_param(key)) return true;
  const std::string v = req.get_param_value(key);
  int64_t n = 0;
  auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
  if (ec != std::errc() || p != v.data() + v.size() || n < min || n > max) {
    errors.push_back(
        {0, key, "must be an integer from " + std::to_string(min) + " to " + std::to_string(max)});
    return false;
  }
  out = n;
  return true;
}

// JSON whose numbers print as the decimals they are (TurningJsonText).
void WriteExactJson(Res& res, const json& body, int status = 200) {
  res.status = status;
  res.set_content(TurningJsonText(body), "application/json");
}

void WriteQueryProblem(Res& res, const FieldErrors& errors) {
  WriteProblem(res, 400, errors.front().field + ": " + errors.front().message, errors);
}

}  // namespace

void HttpServer::TurningRoutes() {
  // The guarded server's own Get and Post (api/guarded_server.h), as in
  // api/check_routes.cc: its writes release the anonymous worker share,
  // get a compressed body inflated, and count under their route names.
  GuardedServer& s = server_;
  const std::string path = kMachinePath + "/turned-parts";

  s.Post(path, [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    const bool csv = IsCsv(req);
    std::vector<TurnedPartInput> parts;
    FieldErrors errors;
    Status status;
    const bool parsed = csv ? ParseTurnedPartsCsv(req.body, parts, errors, &status)
                            : ParseTurnedPartsJson(req.body, parts, errors, &status);
    if (!parsed) return WriteRowProblem(res, status, errors, csv);
    auto result = app_.turning().Record(req.matches[1], parts, Actor(req), &errors);
    if (!result.ok()) return WriteRowProblem(res, result.status(), errors, csv);
    json rows = json::array();
    for (const TurnedPart& p : result->parts) rows.push_back(TurnedPartToJson(p));
    // 201 when something was stored; a re-sent file stores nothing: 200.
    WriteExactJson(res,
                   {{"machine", req.matches[1].str()},
                    {"accepted", result->accepted},
                    {"duplicates", result->duplicates},
                    {"parts", std::move(rows)}},
                   result->accepted > 0 ? 201 : 200);
  });

  s.Get(path, [this](const Req& req, Res& res) {
    FieldErrors errors;
    TurnedPartQuery q;
    TimeRange(req, q.from_ms, q.to_ms, errors);
    q.limit = TurningService::kDefaultHistoryLimit;
    Integer(req, "limit", 1, TurningService::kMaxHistoryLimit, q.limit, errors);
    Integer(req, "offset", 0, int64_t{1} << 40, q.offset, errors);
    if (req.has_param("feature")) {
      q.feature = req.get_param_value("feature");
      if (!TurningService::ValidName(*q.feature)) {
        errors.push_back({0, "feature", "must match [A-Za-z0-9_.-]{1,64}"});
      }
    }
    if (!errors.empty()) return WriteQueryProblem(res, errors);
    auto h = app_.turning().History(req.matches[1], q);
    if (!h.ok()) return WriteProblem(res, h.status());
    WriteExactJson(res, TurnedPartHistoryToJson(*h));
  });

  s.Get(path + "/report", [this](const Req& req, Res& res) {
    FieldErrors errors;
    int64_t from_ms = 0, to_ms = 0;
    if (!TimeRange(req, from_ms, to_ms, errors)) return WriteQueryProblem(res, errors);
    auto report = app_.turning().Report(req.matches[1], from_ms, to_ms);
    if (!report.ok()) return WriteProblem(res, report.status());
    const std::string format = req.get_param_value("format");
    if (format.empty() || format == "json")
      return WriteExactJson(res, TurningReportToJson(*report));
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, *report, TurningReportToJson,
        [&](const TurningReport& r) { return TurningReportMarkdown(r, time); },
        [&](const TurningReport& r) {
          return ReportPage("Turned parts " + r.machine, TurningReportMarkdown(r, time));
        });
  });
}

}  // namespace thermocomp::api
