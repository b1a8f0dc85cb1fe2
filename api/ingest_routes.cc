// Routes of what machines send: temperatures, probe points, signals,
// events. Parse (ingest_parsers), call IngestService, write the result; an
// event beyond the machine's daily allowance is 429 naming events.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/ingest_parsers.h"
#include "api/problem.h"
#include "reports/json_fields.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

void WriteIngest(Res& res, const IngestResult& r) {
  if (!r.status.ok()) return WriteProblem(res, r.status, r.errors);
  WriteJson(res, {{"accepted", r.accepted}, {"duplicates", r.duplicates}});
}

}  // namespace

void HttpServer::IngestRoutes() {
  auto& s = server_;
  const std::string& m = kMachinePath;
  s.Post(m + "/temperatures", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    std::vector<TemperatureInput> samples;
    FieldErrors errors;
    bool ok = IsCsv(req) ? ParseTemperaturesCsv(req.body, samples, errors)
                         : ParseTemperaturesJson(req.body, samples, errors);
    if (!ok) {
      app_.ingest().CountMalformed();
      return WriteProblem(res, Status::InvalidArgument("malformed temperatures"), errors);
    }
    IngestResult r = app_.ingest().AddTemperatures(req.matches[1], samples, Actor(req));
    WriteIngest(res, r);
  });
  s.Post(m + "/probe-points", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    std::vector<ProbePointInput> points;
    FieldErrors errors;
    bool ok = IsCsv(req) ? ParseProbePointsCsv(req.body, points, errors)
                         : ParseProbePointsJson(req.body, points, errors);
    if (!ok) {
      app_.ingest().CountMalformed();
      return WriteProblem(res, Status::InvalidArgument("malformed probe points"), errors);
    }
    IngestResult r = app_.ingest().AddProbePoints(req.matches[1], points, Actor(req));
    WriteIngest(res, r);
  });

  s.Post(m + "/signals", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, true)) return;
    std::vector<SignalInput> samples;
    FieldErrors errors;
    bool ok = IsCsv(req) ? ParseSignalsCsv(req.body, samples, errors)
                         : ParseSignalsJson(req.body, samples, errors);
    if (!ok) return WriteProblem(res, Status::InvalidArgument("malformed signals"), errors);
    WriteIngest(res, app_.ingest().AddSignals(req.matches[1], samples, Actor(req)));
  });
  s.Post(m + "/events", [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, false)) return;
    EventInput event;
    FieldErrors errors;
    if (!ParseEventJson(req.body, event, errors)) {
      return WriteProblem(res, Status::InvalidArgument("malformed event"), errors);
    }
    IngestResult r = app_.ingest().AddEvent(req.matches[1], event, Actor(req));
    if (OverEventLimit(r)) {
      return WriteProblem(res, 429, r.status.message() + ": events: " + r.errors.front().message,
                          r.errors);
    }
    if (!r.status.ok()) return WriteProblem(res, r.status, r.errors);
    WriteJson(res, {{"id", r.id}, {"accepted", r.accepted}, {"duplicates", r.duplicates}},
              r.accepted ? 201 : 200);
  });
}

}  // namespace thermocomp::api
