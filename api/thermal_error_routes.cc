// Thermal error table routes (docs/api.md, "Thermal error table"): each
// feed axis' table now, in JSON, CSV or a control's straight line, and its
// history.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <cmath>
#include <nlohmann/json.hpp>

#include "api/controller_formats.h"
#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "core/time_format.h"

namespace thermocomp::api {
using nlohmann::json;
namespace {

constexpr int64_t kDefaultHistorySpanMs = 7 * 86400000LL;
constexpr size_t kDefaultHistoryPoints = 500;

json Optional(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json TableToJson(const ThermalErrorTable& t) {
  json points = json::array();
  for (const ThermalErrorPoint& p : t.points) {
    points.push_back({{"position_mm", p.position_mm},
                      {"error_um", p.error_um},
                      {"correction_um", p.correction_um},
                      {"valid", p.valid}});
  }
  json sensors = json::array();
  for (const ThermalErrorSensor& s : t.sensors) {
    sensors.push_back({{"name", s.name},
                       {"temperature_c", Optional(s.temperature_c)},
                       {"ts", s.ts_ms ? json(FormatRfc3339(*s.ts_ms)) : json(nullptr)},
                       {"stale", s.stale}});
  }
  return {{"machine", t.machine},
          {"axis", t.axis},
          {"computed_at", FormatRfc3339(t.computed_at_ms)},
          {"state", ServedStateName(t.state)},
          {"status", t.StatusWord()},
          {"valid", t.valid},
          {"stale", t.stale},
          {"clamped", t.clamped},
          {"reason", t.reason},
          {"fallback", t.fallback.empty() ? json(nullptr) : json(t.fallback)},
          {"model_version", t.model_version ? json(*t.model_version) : json(nullptr)},
          {"model_type", t.model_type.empty() ? json(nullptr) : json(t.model_type)},
          {"input_age_s", Optional(t.input_age_s)},
          {"grid", t.grid},
          {"spacing_mm", t.spacing_mm > 0 ? json(t.spacing_mm) : json(nullptr)},
          {"travel_mm", {t.travel.min_mm, t.travel.max_mm}},
          {"clamp_mm", t.clamp_mm},
          {"max_abs_error_um", t.max_abs_error_um},
          {"interpolation_bound_um", Optional(t.interpolation_bound_um)},
          {"line",
           {{"offset_um", t.line.offset_um},
            {"slope_um_per_m", t.line.slope_um_per_m},
            {"reference_position_mm", t.line.reference_position_mm},
            {"max_residual_um", t.line.max_residual_um},
            {"rms_residual_um", t.line.rms_residual_um}}},
          {"sensors", sensors},
          {"points", points}};
}

json HistoryToJson(const ThermalErrorHistory& h) {
  json points = json::array();
  for (const ThermalErrorHistoryPoint& p : h.points) {
    points.push_back({{"ts", FormatRfc3339(p.ts_ms)},
                      {"valid", p.valid},
                      {"error_um", p.error_um},
                      {"max_abs_error_um", p.max_abs_error_um},
                      {"fallback", p.fallback.empty() ? json(nullptr) : json(p.fallback)},
                      {"reason", p.reason}});
  }
  return {{"machine", h.machine},
          {"axis", h.axis},
          {"model_version", h.model_version ? json(*h.model_version) : json(nullptr)},
          {"model_type", h.model_type.empty() ? json(nullptr) : json(h.model_type)},
          {"from", FormatRfc3339(h.from_ms)},
          {"to", FormatRfc3339(h.to_ms)},
          {"positions_mm", h.positions_mm},
          {"reason", h.reason},
          {"points", points}};
}

// A finite decimal number, the whole text.
std::optional<double> ParseNumber(const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// A service's InvalidArgument reads "field: message": a 400 naming the field.
void WriteInvalid(Res& res, const Status& s) {
  const std::string& m = s.message();
  const size_t colon = m.find(':');
  if (s.code() != Status::Code::kInvalidArgument || colon == std::string::npos) {
    return WriteProblem(res, s);
  }
  WriteProblem(res, 400, m, {{0, m.substr(0, colon), m.substr(colon + 2)}});
}

// The flags in every format, so a client of the CSV or a line reads them too.
void FlagHeaders(Res& res, const ThermalErrorTable& t) {
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Thermocomp-Status", std::to_string(t.StatusWord()));
  res.set_header("X-Thermocomp-State", ServedStateName(t.state));
  res.set_header("X-Thermocomp-Valid", t.valid ? "true" : "false");
  res.set_header("X-Thermocomp-Stale", t.stale ? "true" : "false");
  res.set_header("X-Thermocomp-Clamped", t.clamped ? "true" : "false");
}

}  // namespace

void HttpServer::ThermalErrorRoutes() {
  auto& s = server_;
  s.Get(kAxisPath + "/thermal-error", [this](const Req& req, Res& res) {
    FieldErrors errors;
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "json";
    if (format != "json" && format != "csv" && format != "sinumerik" && format != "beckhoff") {
      errors.push_back({0, "format", "must be json, csv, sinumerik or beckhoff"});
    }
    std::optional<double> spacing;
    if (req.has_param("spacing_mm")) {
      spacing = ParseNumber(req.get_param_value("spacing_mm"));
      if (!spacing) errors.push_back({0, "spacing_mm", "must be a number from 1 to 1000"});
    }
    if (!errors.empty()) {
      return WriteProblem(res, 400, errors[0].field + ": " + errors[0].message, errors);
    }
    auto t = app_.thermal_errors().Table(req.matches[1], req.matches[2], spacing);
    if (!t.ok()) return WriteInvalid(res, t.status());
    FlagHeaders(res, *t);
    if (format == "json") return WriteJson(res, TableToJson(*t));
    if (format == "csv") return res.set_content(ThermalErrorCsv(*t), "text/csv");
    res.set_content(RenderThermalErrorLine(*t, format), "text/plain");
  });

  s.Get(kAxisPath + "/thermal-error/history", [this](const Req& req, Res& res) {
    FieldErrors errors;
    int64_t to_ms = app_.clock().NowMs(), from_ms = 0;
    size_t max_points = kDefaultHistoryPoints;
    ParseTimeRange(req, from_ms, to_ms, max_points, ThermalErrorTableService::kMaxHistoryPoints,
                   errors);
    if (!req.has_param("from")) from_ms = to_ms - kDefaultHistorySpanMs;
    std::vector<double> positions;
    if (req.has_param("positions")) {
      const std::string list = req.get_param_value("positions");
      size_t start = 0;
      while (start <= list.size()) {
        const size_t comma = std::min(list.find(',', start), list.size());
        auto v = ParseNumber(list.substr(start, comma - start));
        if (!v) {
          errors.push_back({0, "positions", "must be comma-separated numbers in mm"});
          break;
        }
        positions.push_back(*v);
        start = comma + 1;
      }
    }
    if (!errors.empty()) {
      return WriteProblem(res, 400, errors[0].field + ": " + errors[0].message, errors);
    }
    auto h = app_.thermal_errors().History(req.matches[1], req.matches[2], from_ms, to_ms,
                                           std::move(positions), max_points);
    if (!h.ok()) return WriteInvalid(res, h.status());
    WriteJson(res, HistoryToJson(*h));
  });
}

}  // namespace thermocomp::api
