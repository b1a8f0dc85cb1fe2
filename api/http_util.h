// Small helpers shared by the route files (http_server.cc, check_routes.cc).
#pragma once

#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/problem.h"

namespace thermocomp::api {

inline void WriteJson(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

inline bool IsCsv(const httplib::Request& req) {
  return req.get_header_value("Content-Type").rfind("text/csv", 0) == 0;
}

// 415 unless the body is JSON (or CSV where `csv_ok`).
inline bool CheckMediaType(const httplib::Request& req, httplib::Response& res, bool csv_ok) {
  const std::string type = req.get_header_value("Content-Type");
  if (type.rfind("application/json", 0) == 0 || (csv_ok && IsCsv(req))) return true;
  WriteProblem(res, 415,
               "Content-Type must be application/json" + std::string(csv_ok ? " or text/csv" : "") +
                   ", got '" + type + "'");
  return false;
}

// A stored report as ?format= asks: json (default), markdown or html.
template <typename Markdown, typename Html>
void WriteReport(const httplib::Request& req, httplib::Response& res, const nlohmann::json& report,
                 Markdown markdown, Html html) {
  const std::string format = req.get_param_value("format");
  if (format.empty() || format == "json") return WriteJson(res, report);
  if (format == "markdown") return res.set_content(markdown(report), "text/markdown");
  if (format == "html") return res.set_content(html(report), "text/html");
  WriteProblem(res, 400, "format: must be json, markdown or html",
               {{0, "format", "unknown format '" + format + "'"}});
}

}  // namespace thermocomp::api
