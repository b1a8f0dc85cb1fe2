// Small helpers shared by the route files (http_server.cc, check_routes.cc).
#pragma once

#include <cctype>
#include <optional>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "reports/json_text.h"

namespace thermocomp::api {

// The handler signature of every route: (const Req&, Res&).
using Req = httplib::Request;
using Res = httplib::Response;

// The paths of a machine and of one of its axes, as route patterns.
inline const std::string kMachinePath = "/api/v1/machines/([A-Za-z0-9_.-]{1,64})";
inline const std::string kAxisPath = kMachinePath + "/axes/([A-Z])";

inline void WriteJson(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  res.set_content(JsonText(body), "application/json");
}

// The media type of the body, lower case, without parameters:
// "Application/JSON; charset=utf-8" -> "application/json".
inline std::string MediaType(const httplib::Request& req) {
  std::string type = req.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  while (!type.empty() && (type.back() == ' ' || type.back() == '\t')) type.pop_back();
  for (char& c : type) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return type;
}

inline bool IsCsv(const httplib::Request& req) {
  return MediaType(req) == "text/csv";
}

// 415 unless the body is JSON (or CSV where `csv_ok`).
inline bool CheckMediaType(const httplib::Request& req, httplib::Response& res, bool csv_ok) {
  const std::string type = req.get_header_value("Content-Type");
  if (MediaType(req) == "application/json" || (csv_ok && IsCsv(req))) return true;
  WriteProblem(res, 415,
               "Content-Type must be application/json" + std::string(csv_ok ? " or text/csv" : "") +
                   ", got '" + type + "'");
  return false;
}

// The request's JSON object body (media type checked, nesting and size
// bounded), or nullopt with the problem written.
inline std::optional<nlohmann::json> JsonObjectBody(const httplib::Request& req,
                                                    httplib::Response& res) {
  if (!CheckMediaType(req, res, false)) return std::nullopt;
  FieldErrors errors;
  Status status;
  std::optional<nlohmann::json> body = ParseJsonBody(req.body, errors, &status);
  if (!body) {
    WriteProblem(res, status, errors);
    return std::nullopt;
  }
  if (!body->is_object()) {
    WriteProblem(res, 400, "malformed JSON", {{0, "body", "must be a JSON object"}});
    return std::nullopt;
  }
  return body;
}

// For WriteReport when the report already is its JSON.
inline const nlohmann::json& AsIs(const nlohmann::json& report) {
  return report;
}

// A report as ?format= asks: json (default), markdown or html, each made
// from the report by the function given for it.
template <typename Report, typename ToJson, typename Markdown, typename Html>
void WriteReport(const httplib::Request& req, httplib::Response& res, const Report& report,
                 ToJson to_json, Markdown markdown, Html html) {
  const std::string format = req.get_param_value("format");
  if (format.empty() || format == "json") return WriteJson(res, to_json(report));
  if (format == "markdown") return res.set_content(markdown(report), "text/markdown");
  if (format == "html") return res.set_content(html(report), "text/html");
  WriteProblem(res, 400, "format: must be json, markdown or html",
               {{0, "format", "unknown format '" + format + "'"}});
}

}  // namespace thermocomp::api
