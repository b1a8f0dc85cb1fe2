// The operator's conditions (service/operations/alerts.h): GET
// /api/v1/alerts lists the active ones, for every role that may read; and
// the webhook's HTTP client (alert_post.h).
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/operations/alert_post.h"
#include "core/time_format.h"
#include "service/operations/alerts.h"

namespace thermocomp::api {
namespace {

struct UrlParts {
  std::string origin;  // scheme://host[:port]
  std::string path;    // at least "/"
};

bool SplitUrl(const std::string& url, UrlParts& parts) {
  const size_t scheme_end = url.find("://");
  if (scheme_end == std::string::npos) return false;
  const std::string scheme = url.substr(0, scheme_end);
  if (scheme != "http" && scheme != "https") return false;
  const size_t host_start = scheme_end + 3;
  const size_t path_start = url.find('/', host_start);
  parts.origin = url.substr(0, path_start);
  parts.path = path_start == std::string::npos ? "/" : url.substr(path_start);
  if (parts.origin.size() <= host_start) return false;
  for (const char c : url) {
    if (c <= ' ' || c == 0x7f) return false;  // no spaces or controls in a request line
  }
  return true;
}

}  // namespace

bool ValidAlertUrl(const std::string& url) {
  UrlParts parts;
  return url.empty() || SplitUrl(url, parts);
}

Status PostAlert(const std::string& url, const std::string& json) {
  UrlParts parts;
  if (!SplitUrl(url, parts)) return Status::InvalidArgument("alerts.webhook_url: not a URL");
  httplib::Client client(parts.origin);
  client.set_connection_timeout(kAlertPostTimeoutS, 0);
  client.set_read_timeout(kAlertPostTimeoutS, 0);
  client.set_write_timeout(kAlertPostTimeoutS, 0);
  auto res = client.Post(parts.path, json, "application/json");
  if (!res) return Status::Unavailable("webhook not reached: " + httplib::to_string(res.error()));
  if (res->status < 200 || res->status > 299) {
    return Status::Unavailable("webhook answered " + std::to_string(res->status));
  }
  return Status::Ok();
}

void HttpServer::AlertRoutes() {
  server_.Get("/api/v1/alerts", [this](const Req&, Res& res) {
    nlohmann::json alerts = nlohmann::json::array();
    for (const Alert& a : EvaluateAlerts(app_)) {
      alerts.push_back({{"kind", a.kind},
                        {"machine", a.machine},
                        {"axis", a.axis.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.axis)},
                        {"since", FormatRfc3339(a.since_ms)},
                        {"detail", a.detail}});
    }
    WriteJson(res, {{"computed_at", FormatRfc3339(app_.clock().NowMs())}, {"alerts", alerts}});
  });
}

}  // namespace thermocomp::api
