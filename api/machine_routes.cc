// Routes of machines: the list, one machine, registration.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "reports/json_fields.h"
#include "reports/machine_status_codec.h"

namespace thermocomp::api {
using nlohmann::json;

void HttpServer::MachineRoutes() {
  auto& s = server_;
  const std::string& m = kMachinePath;
  s.Get("/api/v1/machines", [this](const Req&, Res& res) {
    json list = json::array();
    for (const auto& mr : app_.machines().List()) list.push_back(MachineToJson(mr));
    WriteJson(res, {{"machines", list}});
  });
  s.Get(m, [this](const Req& req, Res& res) {
    auto mr = app_.machines().Find(req.matches[1]);
    if (!mr) return WriteProblem(res, 404, "unknown machine '" + std::string(req.matches[1]) + "'");
    json j = MachineToJson(*mr);
    j.update(MachineStatusToJson(app_.machines().Summary(*mr)));
    WriteJson(res, j);
  });
  s.Put(m, [this](const Req& req, Res& res) {
    if (!CheckMediaType(req, res, false)) return;
    FieldErrors errors;
    auto record = MachineFromJson(req.matches[1], req.body, errors);  // a MachineDefinition
    if (!record)
      return WriteProblem(res, Status::InvalidArgument("invalid machine definition"), errors);
    auto created = app_.machines().Register(*record, Actor(req), &errors);
    if (!created.ok()) return WriteProblem(res, created.status(), errors);
    (void)app_.compensation().Recompute(record->name);
    WriteJson(res, MachineToJson(*app_.machines().Find(record->name)), *created ? 201 : 200);
  });
}

}  // namespace thermocomp::api
