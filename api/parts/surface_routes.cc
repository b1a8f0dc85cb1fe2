// Surface routes (docs/api.md, "Surfaces"): a part's CMM measurements in,
// its iterations report and the corrected program points out. Parse, call
// SurfaceService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <charconv>

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/parts/cmm_csv.h"
#include "api/problem.h"
#include "api/report_page.h"
#include "reports/parts/surface_export.h"
#include "reports/parts/surface_report_codec.h"
#include "reports/parts/surface_report_text.h"
#include "service/parts/surfaces/surface_service.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

const std::string kPartPath = "/surfaces/([A-Za-z0-9_.-]{1,64})";

// ?iteration=N (0..999999999) or nullopt when absent; false on a bad one.
bool IterationParam(const Req& req, Res& res, std::optional<int>* out) {
  if (!req.has_param("iteration")) return true;
  const std::string v = req.get_param_value("iteration");
  int n = -1;
  auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
  if (v.empty() || v.size() > 9 || ec != std::errc() || p != v.data() + v.size() || n < 0) {
    WriteProblem(res, 400, "iteration: must be a whole number from 0",
                 {{0, "iteration", "'" + v.substr(0, 32) + "' is not an iteration number"}});
    return false;
  }
  *out = n;
  return true;
}

}  // namespace

void HttpServer::SurfaceRoutes() {
  // The guarded server's own Get and Post (api/guarded_server.h), as in
  // api/check_routes.cc: its writes release the anonymous worker share,
  // get a compressed body inflated, and count under their route names.
  GuardedServer& s = server_;
  const std::string part = kMachinePath + kPartPath;

  s.Post(part + "/measurements", [this](const Req& req, Res& res) {
    if (!IsCsv(req)) {
      return WriteProblem(res, 415,
                          "Content-Type must be text/csv (the CMM report export), got '" +
                              req.get_header_value("Content-Type") + "'");
    }
    FieldErrors errors;
    std::vector<CmmPoint> points;
    if (Status st = ParseCmmCsv(req.body, points, errors); !st.ok()) {
      return WriteProblem(res, st, errors);
    }
    auto it =
        app_.surfaces().AddMeasurement(req.matches[1], req.matches[2], points, Actor(req), &errors);
    if (!it.ok()) return WriteProblem(res, it.status(), errors);
    json out = SurfaceIterationToJson(*it, false);
    out["machine"] = req.matches[1].str();
    out["part"] = req.matches[2].str();
    WriteJson(res, out, 201);
  });

  s.Get(kMachinePath + "/surfaces", [this](const Req& req, Res& res) {
    auto parts = app_.surfaces().Parts(req.matches[1]);
    if (!parts.ok()) return WriteProblem(res, parts.status());
    json list = json::array();
    for (const SurfacePartSummary& p : *parts) list.push_back(SurfacePartSummaryToJson(p));
    WriteJson(res, {{"machine", req.matches[1].str()}, {"parts", std::move(list)}});
  });

  s.Get(part, [this](const Req& req, Res& res) {
    auto report = app_.surfaces().Part(req.matches[1], req.matches[2]);
    if (!report.ok()) return WriteProblem(res, report.status());
    const PlantTime& time = app_.plant_time();
    WriteReport(
        req, res, *report, SurfacePartReportToJson,
        [&](const SurfacePartReport& r) { return SurfacePartMarkdown(r, time); },
        [&](const SurfacePartReport& r) {
          return ReportPage("Surface " + r.part, SurfacePartMarkdown(r, time));
        });
  });

  s.Get(part + "/corrected", [this](const Req& req, Res& res) {
    std::optional<int> iteration;
    if (!IterationParam(req, res, &iteration)) return;
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "csv";
    if (format != "csv" && format != "dxf") {
      return WriteProblem(res, 400, "format: must be csv or dxf",
                          {{0, "format", "unknown format '" + format.substr(0, 32) + "'"}});
    }
    auto program = app_.surfaces().Corrected(req.matches[1], req.matches[2], iteration);
    if (!program.ok()) return WriteProblem(res, program.status());
    // Named after the program it is: the one made after the iteration measured.
    const std::string name = req.matches[2].str() + "-program-" +
                             std::to_string(program->after_iteration + 1) + "." + format;
    res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
    if (format == "dxf") return res.set_content(SurfacePointsDxf(program->points), "image/vnd.dxf");
    res.set_content(SurfacePointsCsv(program->points), "text/csv");
  });
}

}  // namespace thermocomp::api
