#include "api/http_server.h"

#include <chrono>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/openapi.h"
#include "api/problem.h"
#include "core/log.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

constexpr const char* kBase = "/api/v1";
thread_local std::chrono::steady_clock::time_point t_request_start;

}  // namespace

HttpServer::Credentials HttpServer::CredentialsOf(const Req& req) {
  Credentials c{req.get_header_value("Authorization"), std::nullopt};
  if (!c.authorization.empty()) return c;
  c.session = sessions_.Find(CookieValue(req.get_header_value("Cookie"), kSessionCookie),
                             app_.clock().NowMs());
  if (c.session) c.authorization = "Bearer " + c.session->token.token;
  return c;
}

// The actor recorded in the audit: the token's name, or the client address.
std::string HttpServer::Actor(const Req& req) {
  return auth_.Decide(req.method, req.path, req.remote_addr, CredentialsOf(req).authorization)
      .actor;
}

namespace {

ConnectionLimits LimitsOf(const Config& c) {
  ConnectionLimits l;
  l.workers = c.http_threads;
  l.max_connections_per_client = c.max_connections_per_client;
  l.header_timeout_s = c.header_timeout_s;
  l.body_timeout_s = c.body_timeout_s;
  l.keep_alive_timeout_s = c.keep_alive_timeout_s;
  l.max_body_bytes = c.max_body_bytes;
  return l;
}

// Framing a proxy and this server could read differently (request
// smuggling) is refused before any body is read.
std::string FramingError(const Req& req) {
  if (req.get_header_value_count("Content-Length") > 1) {
    return "more than one Content-Length header";
  }
  if (req.has_header("Transfer-Encoding")) {
    if (req.has_header("Content-Length")) {
      return "both Content-Length and Transfer-Encoding: send one of them";
    }
    if (req.get_header_value_count("Transfer-Encoding") > 1 ||
        req.get_header_value("Transfer-Encoding") != "chunked") {
      return "Transfer-Encoding must be chunked";
    }
  }
  return "";
}

// The query parameters each route takes (by path, after /api/v1); any other
// is refused, so a typo (?fromat=html) is not silently ignored.
const std::vector<std::pair<std::regex, std::set<std::string>>>& RouteParams() {
  static const std::string m = "/api/v1/machines/[^/]+";
  static const std::vector<std::pair<std::regex, std::set<std::string>>> table = {
      {std::regex(m + "/compensation"), {"format"}},
      {std::regex(m + "/drift"), {"axis", "from", "to", "max_points"}},
      {std::regex(m + "/temperatures"), {"from", "to", "max_points"}},
      {std::regex("/ui/sign-in"), {"next"}},
      {std::regex("/"), {"refresh"}},
      {std::regex("/api/v1/overview"), {"limit", "offset"}},
      {std::regex(m + "/column-checks/requests"), {"state"}},
      {std::regex(m + "/column-checks/[0-9]+"), {"format"}},
      {std::regex(m + "/axes/[^/]+/analysis/[0-9]+"), {"format"}},
      {std::regex(m + "/axes/[^/]+/models/[0-9]+"), {"format"}},
      {std::regex(m + "/positioning-checks/[0-9]+"), {"format"}},
      {std::regex(m + "/positioning-checks/[0-9]+/pitch-table"), {"format", "per_direction"}},
      {std::regex(m + "/positioning-checks"), PositioningQueryParameters()},
  };
  return table;
}

// The first query parameter the route does not take, or empty.
std::string UnknownParameter(const Req& req) {
  if (req.params.empty()) return "";
  const std::set<std::string>* allowed = nullptr;
  for (const auto& [path, names] : RouteParams()) {
    if (std::regex_match(req.path, path)) allowed = &names;
  }
  for (const auto& [name, value] : req.params) {
    if (!allowed || !allowed->count(name)) return name;
  }
  return "";
}

// Why a write is refused as possibly forged by another site, or "". A
// browser names the page's origin on writes: it must be this server. A
// write made with a session cookie must also carry the session's CSRF
// token, which only the server's own pages can read (signing in and out
// excepted: there is no token before, and leaving needs none).
std::string CrossSiteWrite(const Req& req, const std::optional<WebSession>& session) {
  if (req.method == "GET" || req.method == "HEAD") return "";
  const std::string origin = req.get_header_value("Origin");
  const std::string host = req.get_header_value("Host");
  if (!origin.empty() && origin != "http://" + host && origin != "https://" + host) {
    return "cross-origin write refused: Origin " + origin.substr(0, 100) + " is not this server";
  }
  if (!session || req.path == "/api/v1/session") return "";
  const std::string sent = req.get_header_value("X-CSRF-Token");
  if (!SameSecret(sent, session->csrf)) return "X-CSRF-Token missing or wrong for this session";
  return "";
}

// cpp-httplib 0.11 (Debian 12) answers a client that accepts "br" with
// Brotli at quality 11: 0.85 s for a 600 KB JSON body, against 3 ms for
// gzip (docs/benchmarks.md, Pages). Every browser accepts br, so the
// encodings a request accepts lose br before the response is written;
// gzip stays. The request is the server's own non-const object, which the
// hook is only shown as const.
void AcceptNoBrotli(const Req& req) {
  auto& headers = const_cast<Req&>(req).headers;
  auto [first, last] = headers.equal_range("Accept-Encoding");  // names compare case-blind
  for (auto it = first; it != last; ++it) {
    std::string kept;
    std::stringstream tokens(it->second);
    for (std::string token; std::getline(tokens, token, ',');) {
      if (token.find("br") != std::string::npos) continue;
      kept += (kept.empty() ? "" : ",") + token;
    }
    it->second = kept;
  }
}

bool HasBody(const Req& req) {
  return req.has_header("Transfer-Encoding") ||
         (req.has_header("Content-Length") && req.get_header_value("Content-Length") != "0");
}

}  // namespace

HttpServer::HttpServer(App& app)
    : app_(app),
      auth_(app.config().tokens),
      sessions_(static_cast<size_t>(app.config().web_max_sessions),
                int64_t{app.config().web_session_hours} * 3600 * 1000),
      server_(LimitsOf(app.config())) {
  Routes();
}

HttpServer::~HttpServer() {
  Stop();
}

Status HttpServer::Start(const std::string& host, int port) {
  // GuardedServer sizes its pool and bounds connections (api/guarded_server.h).
  server_.set_tcp_nodelay(true);
  server_.set_keep_alive_max_count(100000);
  if (!server_.Listen(host, port, &port_))
    return Status::Unavailable("cannot listen on " + host + ":" + std::to_string(port));
  thread_ = std::thread([this] { server_.listen_after_bind(); });
  while (!server_.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return Status::Ok();
}

void HttpServer::Stop() {
  server_.Shutdown();
  if (thread_.joinable()) thread_.join();
}

std::string HttpServer::CompensationBody(const std::string& machine,
                                         const std::shared_ptr<const MachineCompensation>& c) {
  {
    std::shared_lock lock(rendered_mutex_);
    if (auto it = rendered_.find(machine); it != rendered_.end() && it->second.first == c) {
      return it->second.second;
    }
  }
  std::string body = JsonText(CompensationToJson(*c));
  std::unique_lock lock(rendered_mutex_);
  rendered_[machine] = {c, body};
  return body;
}

void HttpServer::Routes() {
  auto& s = server_;
  const size_t max_body = app_.config().max_body_bytes;
  s.set_pre_routing_handler([this, max_body](const Req& req, Res& res) {
    t_request_start = std::chrono::steady_clock::now();
    AcceptNoBrotli(req);
    // Answered before the body is read: the connection closes after the
    // response, so the unread body is never taken for the next request.
    auto refuse = [&](int status, const std::string& detail, const FieldErrors& errors = {}) {
      if (HasBody(req)) {
        GuardedServer::CloseAfterResponse();
        res.set_header("Connection", "close");
      }
      WriteProblem(res, status, detail, errors);
      return httplib::Server::HandlerResponse::Handled;
    };
    if (std::string framing = FramingError(req); !framing.empty()) {
      return refuse(400, "malformed HTTP framing: " + framing,
                    {{0, "Content-Length / Transfer-Encoding", framing}});
    }
    const std::string length = req.get_header_value("Content-Length");
    if (length.size() > 18 || length.find_first_not_of("0123456789") != std::string::npos) {
      return refuse(400, "malformed HTTP framing: Content-Length must be a number of bytes",
                    {{0, "Content-Length", "must be a number of bytes"}});
    }
    if (!length.empty() && std::stoull(length) > max_body) {
      return refuse(413, "request body larger than server.max_body_bytes (" +
                             std::to_string(max_body) + " bytes)");
    }
    const Credentials credentials = CredentialsOf(req);
    AuthDecision d = auth_.Decide(req.method, req.path, req.remote_addr, credentials.authorization);
    if (!d.challenge.empty()) res.set_header("WWW-Authenticate", d.challenge);
    if (d.status != 200) return refuse(d.status, d.reason);
    if (std::string why = CrossSiteWrite(req, credentials.session); !why.empty()) {
      return refuse(403, why, {{0, "X-CSRF-Token", why}});
    }
    if (std::string name = UnknownParameter(req); !name.empty()) {
      return refuse(400, "unknown query parameter '" + name + "'",
                    {{0, name, "not a parameter of " + req.method + " " + req.path}});
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  s.set_logger([this](const Req& req, const Res& res) {
    double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_request_start).count();
    app_.metrics().ObserveRequest(secs);
    if (res.status >= 500)
      log::Error("request failed", "method=" + req.method + " path=" + req.path);
  });
  s.set_error_handler([max_body](const Req& req, Res& res) {
    if (!res.body.empty()) return;
    // It runs outside the handlers' exception handling: it must not throw.
    try {
      if (GuardedServer::BodyTooLarge() || res.status == 413) {
        res.set_header("Connection", "close");
        return WriteProblem(res, 413,
                            "request body larger than server.max_body_bytes (" +
                                std::to_string(max_body) + " bytes, chunked framing included)");
      }
      if (GuardedServer::TimedOut()) {
        res.set_header("Connection", "close");
        return WriteProblem(res, 408, "the request was not sent completely in time");
      }
      switch (res.status) {
        case 404:
          return WriteProblem(res, 404, "no such resource: " + req.method + " " + req.path);
        case 414:
          return WriteProblem(res, 414, "request line longer than 8192 bytes");
        case 400:
          return WriteProblem(
              res, 400, "malformed HTTP request (a POST needs Content-Length, e.g. curl -d '')");
        default:
          return WriteProblem(res, res.status, "request failed");
      }
    } catch (...) {
      res.status = 500;
      res.body.clear();
    }
  });
  s.set_exception_handler([](const Req&, Res& res, const std::exception_ptr& ep) {
    std::string what = "unexpected error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    log::Error("handler threw", "error=\"" + what + "\"");
    WriteProblem(res, 500, what);
  });

  s.Get("/healthz", [](const Req&, Res& res) { WriteJson(res, {{"status", "ok"}}); });
  s.Get(std::string(kBase) + "/openapi.json",
        [](const Req&, Res& res) { res.set_content(OpenApiJson(), "application/json"); });
  s.Get("/readyz", [this](const Req&, Res& res) {
    if (app_.storage().storage_full()) {
      return WriteProblem(res, 503, "not ready: the disk holding the database is full");
    }
    WriteJson(res, {{"status", "ready"}, {"schema_version", app_.storage().schema_version()}});
  });
  s.Get("/metrics", [this](const Req&, Res& res) {
    res.set_content(app_.metrics().Render(app_.ModelGauges()), "text/plain; version=0.0.4");
  });

  MachineRoutes();
  IngestRoutes();
  ModelRoutes();
  CompensationRoutes();
  CheckRoutes();
  OverviewRoutes();
  SessionRoutes();
  PageRoutes();
}

}  // namespace thermocomp::api
