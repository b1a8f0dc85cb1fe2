// Routes the pages read most: the line at a glance, a page of machines at
// a time (?limit=&offset=, by name, with total and the next page's URL),
// a machine's temperatures over a range, and its sensors now.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "reports/outcome_codec.h"

namespace thermocomp::api {
using nlohmann::json;
namespace {

constexpr size_t kMaxOverviewLimit = 1000;
// Far beyond any line; keeps offset + limit well inside size_t.
constexpr size_t kMaxOverviewOffset = 1000000000;
// How long one overview may spend computing what compensation achieved
// (a machine's whole probe history is read for it); machines beyond carry
// their last summary, or none yet, and later requests fill them in.
constexpr int64_t kOutcomeBudgetMs = 250;

// The query parameter `name` as an integer in [min, max]; `value` is kept
// when it is absent. False with an error naming it when it is not.
bool IntParam(const Req& req, const char* name, size_t min, size_t max, size_t& value,
              FieldErrors& errors) {
  if (!req.has_param(name)) return true;
  const std::string text = req.get_param_value(name);
  size_t n = 0;
  bool ok = !text.empty() && text.size() <= 10;
  for (const char c : text) {
    ok = ok && c >= '0' && c <= '9';
    if (ok) n = n * 10 + static_cast<size_t>(c - '0');
  }
  if (ok && n >= min && n <= max) {
    value = n;
    return true;
  }
  errors.push_back(
      {0, name, "must be an integer from " + std::to_string(min) + " to " + std::to_string(max)});
  return false;
}

}  // namespace

void HttpServer::OverviewRoutes() {
  auto& s = server_;
  s.Get("/api/v1/overview", [this](const Req& req, Res& res) {
    size_t limit = static_cast<size_t>(app_.config().overview_page_size);
    size_t offset = 0;
    FieldErrors errors;
    IntParam(req, "limit", 1, kMaxOverviewLimit, limit, errors);
    IntParam(req, "offset", 0, kMaxOverviewOffset, offset, errors);
    if (!errors.empty()) {
      return WriteProblem(res, Status::InvalidArgument("invalid overview query"), errors);
    }
    const OverviewPage page = app_.machines().Overview(offset, limit);
    std::vector<std::shared_ptr<const MachineCompensation>> served;
    served.reserve(page.machines.size());
    for (const MachineOverview& m : page.machines) {
      auto c = app_.compensation().Get(m.name);
      served.push_back(c.ok() ? *c : nullptr);
    }
    std::optional<std::string> next;
    if (offset + page.machines.size() < page.total) {
      next = "/api/v1/overview?limit=" + std::to_string(limit) +
             "&offset=" + std::to_string(offset + limit);
    }
    json body = OverviewToJson(page, served, app_.clock().NowMs(), next);
    // Per axis what compensation achieved over the last week, and whether
    // its model is still good (service/outcome/outcome_service.h).
    const int64_t started = app_.clock().MonotonicMs();
    for (json& machine : body["machines"]) {
      const std::string name = machine["machine"].get<std::string>();
      const bool in_time = app_.clock().MonotonicMs() - started < kOutcomeBudgetMs;
      const auto summaries =
          in_time ? app_.outcomes().Summary(name) : app_.outcomes().LastSummary(name);
      for (json& axis : machine["axes"]) {
        for (const AxisOutcomeSummary& o : summaries) {
          if (o.axis != axis["axis"].get<std::string>()) continue;
          axis["outcome"] = OutcomeSummaryToJson(o);
          axis["health"] = {
              {"state", o.health.state},
              {"reason", o.health.reason.empty() ? json(nullptr) : json(o.health.reason)}};
        }
      }
    }
    WriteJson(res, body);
  });
  s.Get(kMachinePath + "/temperatures", [this](const Req& req, Res& res) {
    TemperatureQuery q;
    q.machine = req.matches[1];
    FieldErrors errors;
    if (!ParseTimeRange(req, q.from_ms, q.to_ms, q.max_points, 20000, errors)) {
      return WriteProblem(res, Status::InvalidArgument("invalid temperature query"), errors);
    }
    auto h = app_.history().Temperatures(q);
    if (!h.ok()) return WriteProblem(res, h.status());
    WriteJson(res, TemperatureHistoryToJson(*h));
  });
  // What the controls and the OPC UA face poll: every sensor now. A path of
  // its own, taking no query parameters; routes match whole paths, so the
  // history above does not answer it.
  s.Get(kMachinePath + "/temperatures/latest", [this](const Req& req, Res& res) {
    auto latest = app_.latest_temperatures().Latest(req.matches[1]);
    if (!latest.ok()) return WriteProblem(res, latest.status());
    WriteJson(res, LatestTemperaturesToJson(*latest));
  });
}

}  // namespace thermocomp::api
