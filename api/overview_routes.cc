// Routes the pages read most: the line at a glance, and a machine's
// temperatures over a range.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"

namespace thermocomp::api {

void HttpServer::OverviewRoutes() {
  auto& s = server_;
  s.Get("/api/v1/overview", [this](const Req&, Res& res) {
    const std::vector<MachineOverview> machines = app_.machines().Overview();
    std::vector<std::shared_ptr<const MachineCompensation>> served;
    served.reserve(machines.size());
    for (const MachineOverview& m : machines) {
      auto c = app_.compensation().Get(m.name);
      served.push_back(c.ok() ? *c : nullptr);
    }
    WriteJson(res, OverviewToJson(machines, served, app_.clock().NowMs()));
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
}

}  // namespace thermocomp::api
