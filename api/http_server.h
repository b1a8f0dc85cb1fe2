// HttpServer: the v1 HTTP API (docs/api.md) on cpp-httplib. Handlers parse
// and validate, call a service, and map the result to JSON; nothing else.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <thread>

// service/app.h first: glibc's resolv.h (pulled in by httplib.h) defines
// a macro `_res` that breaks Eigen's headers when they come after it.
#include "service/app.h"
#include "service/applied_compensation_service.h"

#include <httplib.h>

#include "api/auth.h"
#include "api/auth_throttle.h"
#include "api/client_address.h"
#include "api/guarded_server.h"
#include "api/web/web_sessions.h"

namespace thermocomp::api {

// The Content-Security-Policy of every HTML response (the pages' shells and
// the ?format=html reports): no script but the server's own files, nothing
// framed, nothing sent elsewhere.
inline constexpr const char* kHtmlSecurityPolicy =
    "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
    "img-src 'self' data: blob:; object-src 'none'; base-uri 'none'; "
    "frame-ancestors 'none'; form-action 'self'";

class HttpServer {
 public:
  explicit HttpServer(App& app);
  ~HttpServer();

  // Binds host:port (port 0: an ephemeral port) and serves on a thread.
  Status Start(const std::string& host, int port);
  void Stop();
  int port() const { return port_; }
  // Takes what may change while serving from a configuration read again
  // (SIGHUP; docs/operations.md, systemd): the tokens, server.allowed_hosts,
  // server.trusted_proxies and server.access_log. Requests in flight finish
  // with what they started with; signed-in sessions stay (a session whose
  // token was removed is refused from its next request on). Everything
  // else takes effect at the next start.
  void Reload(const Config& config);
  // One request from an in-memory stream, without a socket (fuzzing).
  bool ServeOne(httplib::Stream& stream) { return server_.ServeOne(stream); }

 private:
  // The JSON body of a compensation snapshot with what the control applied,
  // rendered once per pair of snapshots.
  std::string CompensationBody(const std::string& machine,
                               const std::shared_ptr<const MachineCompensation>& c,
                               const std::shared_ptr<const AppliedByAxis>& applied);
  // The hooks every request passes (framing, limits, auth, logging,
  // problems) and the routes, grouped per resource, one file each.
  void Routes();
  void MachineRoutes();       // machine_routes.cc
  void IngestRoutes();        // ingest_routes.cc
  void ModelRoutes();         // model_routes.cc: fits, versions, analyses
  void CompensationRoutes();  // compensation_routes.cc: compensation, outcome, drift
  void CheckRoutes();         // check_routes.cc: column and positioning checks
  void FeedAxisRoutes();      // feed_axis_routes.cc: screw configuration, feed-axis models
  void ThermalErrorRoutes();  // thermal_error_routes.cc: the thermal error table, its history
  void PlateRoutes();         // parts/plate_routes.cc: compensation on/off plates
  void TurningRoutes();       // parts/turning_routes.cc: four-diameter decomposition
  void PartModelRoutes();     // parts/part_model_routes.cc: part-error models from the process
  void SurfaceRoutes();       // parts/surface_routes.cc: CMM mirror correction
  void OverviewRoutes();      // overview_routes.cc: the line at a glance, temperatures
  void AlertRoutes();         // operations/alert_routes.cc: the operator's conditions
  void AuditRoutes();         // operations/audit_routes.cc: the audit trail
  void SessionRoutes();       // web/session_routes.cc: signing in to the pages
  void PageRoutes();          // web/page_routes.cc: the pages and their assets
  // What a request authenticates with: its Authorization header, or the
  // token behind its session cookie.
  struct Credentials {
    std::string authorization;
    std::optional<WebSession> session;
  };
  Credentials CredentialsOf(const httplib::Request& req);
  std::string Actor(const httplib::Request& req);
  // `check` (which looks up the credential `presented` by `client`) under
  // the failure throttle: 429 when this credential failed too often; a 401
  // of `check` is a failure, and 429 when the address failed too often.
  // A valid credential is never refused here (docs/api.md, "Failed
  // credentials").
  AuthDecision Throttled(const std::string& client, const std::string& presented,
                         const std::function<AuthDecision()>& check);
  // What Reload replaces, read by each request as one snapshot.
  struct Exposure {
    Authorizer auth;
    std::shared_ptr<const ClientAddresses> clients;
    std::vector<std::string> allowed_hosts;
    bool access_log = true;
  };
  static std::shared_ptr<const Exposure> ExposureOf(const Config& config);
  std::shared_ptr<const Exposure> exposure() const {
    std::lock_guard<std::mutex> lock(exposure_mutex_);
    return exposure_;
  }
  App& app_;
  mutable std::mutex exposure_mutex_;
  std::shared_ptr<const Exposure> exposure_;
  WebSessions sessions_;
  AuthThrottle auth_throttle_;
  std::shared_mutex rendered_mutex_;
  struct Rendered {
    std::shared_ptr<const MachineCompensation> compensation;
    std::shared_ptr<const AppliedByAxis> applied;
    std::string body;
  };
  std::map<std::string, Rendered> rendered_;
  GuardedServer server_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace thermocomp::api
