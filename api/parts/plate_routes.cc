// Test-plate routes (docs/api.md, "Test plates"): import a plate's CMM file,
// list a machine's plates, a plate's report (JSON, Markdown, HTML) and its
// holes as CSV. Parse, call PlateService, map.
#include "api/http_server.h"  // first: Eigen before httplib.h
#include "service/parts/plates/plate_service.h"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/parts/plate_csv.h"
#include "api/problem.h"
#include "api/report_page.h"
#include "core/time_format.h"
#include "reports/parts/plate_report_codec.h"
#include "reports/parts/plate_report_text.h"

namespace thermocomp::api {
using nlohmann::json;

namespace {

const std::string kPlateName = "([A-Za-z0-9_.-]{1,64})";

// ?format= when given (json, markdown, html), else what Accept asks for
// first among text/markdown and text/html, else json.
std::string ReportFormat(const Req& req) {
  if (req.has_param("format")) return req.get_param_value("format");
  const std::string accept = req.get_header_value("Accept");
  const size_t md = accept.find("text/markdown"), html = accept.find("text/html");
  if (md != std::string::npos && (html == std::string::npos || md < html)) return "markdown";
  if (html != std::string::npos) return "html";
  return "json";
}

std::string Optional(const std::optional<double>& v, const char* format) {
  if (!v) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

// The holes as stored and joined: the CMM columns plus what was served.
std::string HolesCsv(const PlateReport& r) {
  std::string csv =
      "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,bored_at,"
      "served_offset_mm,predicted_drift_mm,model_version\n";
  char buf[512];
  for (const auto& h : r.holes) {
    // A hole id is free text: quoted, quotes doubled.
    std::string id = "\"";
    for (char c : h.hole) id += c == '"' ? std::string("\"\"") : std::string(1, c);
    id += "\"";
    std::snprintf(
        buf, sizeof buf, "%s,%d,%.4f,%.4f,%.6f,%.6f,%s,%s,%s,%s,%s\n", id.c_str(), h.pair,
        h.nominal_x_mm, h.nominal_y_mm, h.dev_x_um / 1000.0, h.dev_y_um / 1000.0,
        h.compensated ? "on" : "off", FormatRfc3339(h.bored_ms).c_str(),
        Optional(h.served_offset_um ? std::optional(*h.served_offset_um / 1000.0) : std::nullopt,
                 "%.6f")
            .c_str(),
        Optional(
            h.predicted_drift_um ? std::optional(*h.predicted_drift_um / 1000.0) : std::nullopt,
            "%.6f")
            .c_str(),
        h.model_version ? std::to_string(*h.model_version).c_str() : "");
    csv += buf;
  }
  return csv;
}

}  // namespace

void HttpServer::PlateRoutes() {
  // The guarded server's own Get and Post (api/guarded_server.h), as in
  // api/check_routes.cc: its writes release the anonymous worker share,
  // get a compressed body inflated, and count under their route names.
  GuardedServer& s = server_;
  const std::string plates = kMachinePath + "/plates";

  // The plate's name from the path, the axis from ?axis= (Y when absent).
  auto import = [this](const Req& req, Res& res, const std::string& name) {
    if (!IsCsv(req)) {
      return WriteProblem(
          res, 415,
          "Content-Type must be text/csv, got '" + req.get_header_value("Content-Type") + "'");
    }
    PlateImport in;
    in.machine = req.matches[1];
    in.plate = name;
    in.axis = req.has_param("axis") ? req.get_param_value("axis") : "Y";
    in.actor = Actor(req);
    FieldErrors errors;
    if (Status st = ParsePlateCsv(req.body, in.holes, errors); !st.ok()) {
      return WriteProblem(res, st, errors);
    }
    auto report = app_.plates().Import(in, &errors);
    if (!report.ok()) return WriteProblem(res, report.status(), errors);
    res.set_header("Location", "/api/v1/machines/" + in.machine + "/plates/" + in.plate);
    WriteJson(res, PlateReportToJson(*report), 201);
  };
  s.Post(plates + "/" + kPlateName,
         [import](const Req& req, Res& res) { import(req, res, req.matches[2]); });

  s.Get(plates, [this](const Req& req, Res& res) {
    auto list = app_.plates().List(req.matches[1]);
    if (!list.ok()) return WriteProblem(res, list.status());
    json items = json::array();
    for (const auto& summary : *list) items.push_back(PlateSummaryToJson(summary));
    WriteJson(res, {{"machine", std::string(req.matches[1])}, {"plates", items}});
  });

  s.Get(plates + "/" + kPlateName, [this](const Req& req, Res& res) {
    auto report = app_.plates().Report(req.matches[1], req.matches[2]);
    if (!report.ok()) return WriteProblem(res, report.status());
    const PlantTime& time = app_.plant_time();
    const std::string format = ReportFormat(req);
    if (format == "json") return WriteJson(res, PlateReportToJson(*report));
    if (format == "markdown") {
      return res.set_content(PlateReportMarkdown(*report, time), "text/markdown");
    }
    if (format == "html") {
      return res.set_content(
          ReportPage("Test plate " + report->plate, PlateReportMarkdown(*report, time)),
          "text/html");
    }
    WriteProblem(res, 400, "format: must be json, markdown or html",
                 {{0, "format", "unknown format '" + format + "'"}});
  });

  s.Get(plates + "/" + kPlateName + "/holes\\.csv", [this](const Req& req, Res& res) {
    auto report = app_.plates().Report(req.matches[1], req.matches[2]);
    if (!report.ok()) return WriteProblem(res, report.status());
    res.set_content(HolesCsv(*report), "text/csv");
  });
}

}  // namespace thermocomp::api
