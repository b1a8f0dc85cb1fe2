// Routes of what the line and quality staff read: the compensation (JSON
// and each control's format) and the drift history.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/controller_formats.h"
#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/problem.h"
#include "core/time_format.h"
#include "service/drift_history_codec.h"
#include "service/json_fields.h"

namespace thermocomp::api {
using nlohmann::json;

void HttpServer::CompensationRoutes() {
  auto& s = server_;
  const std::string& m = kMachinePath;
  s.Get(m + "/compensation", [this](const Req& req, Res& res) {
    auto c = app_.compensation().Get(req.matches[1]);
    if (!c.ok()) return WriteProblem(res, c.status());
    // A control polls this: no cache between may hand it an older value.
    res.set_header("Cache-Control", "no-store");
    std::string format = req.get_param_value("format");
    if (format.empty() || format == "json") {
      return res.set_content(CompensationBody(req.matches[1], *c), "application/json");
    }
    if (format == "native") {
      if (!KnownControllerFormat((*c)->controller)) {
        return WriteProblem(res, 400,
                            "format: native: the machine's control '" + (*c)->controller +
                                "' has no native format; use json",
                            {{0, "format", "no native format for '" + (*c)->controller + "'"}});
      }
      format = (*c)->controller;
    }
    if (!KnownControllerFormat(format)) {
      return WriteProblem(
          res, 400,
          "format: must be json, native, sinumerik, beckhoff, heidenhain, fanuc or linuxcnc",
          {{0, "format", "unknown format '" + format + "'"}});
    }
    res.set_content(RenderForController(**c, format), "text/plain");
  });

  s.Get(m + "/drift", [this](const Req& req, Res& res) {
    HistoryQuery q;
    FieldErrors errors;
    if (!ParseHistoryQuery(req, q, errors)) {
      return WriteProblem(res, Status::InvalidArgument("invalid drift query"), errors);
    }
    q.machine = req.matches[1];
    auto h = app_.history().Drift(q);
    if (!h.ok()) return WriteProblem(res, h.status());
    WriteJson(res, DriftHistoryToJson(*h));
  });
}

}  // namespace thermocomp::api
