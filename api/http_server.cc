#include "api/http_server.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "api/body_guard.h"
#include "api/client_address.h"
#include "api/http_util.h"
#include "api/json_mapping.h"
#include "api/openapi.h"
#include "api/problem.h"
#include "core/log.h"
#include "service/operations/operator_gauges.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

constexpr const char* kBase = "/api/v1";
// The request was turned away to shed load (the anonymous share): not a
// failure of the server, and a flood of them must not flood the log.
thread_local bool t_shed = false;
// What the hooks learned about the request on this thread, for its access
// log line; `routed` is false for a request httplib answered without the
// hooks (a malformed request line).
struct RequestFacts {
  bool routed = false;
  bool malformed_forward = false;
  std::string actor;
};
thread_local RequestFacts t_facts;
// The archive's lost-connection count when the request began
// (Storage::lost_connections), and whether the request is a read whose
// answer a loss during it makes a 503.
thread_local uint64_t t_lost_before = 0;
thread_local bool t_watch_archive = false;

}  // namespace

HttpServer::Credentials HttpServer::CredentialsOf(const Req& req) {
  Credentials c{req.get_header_value("Authorization"), std::nullopt};
  if (!c.authorization.empty()) return c;
  c.session = sessions_.Find(CookieValue(req.get_header_value("Cookie"), kSessionCookie),
                             app_.clock().MonotonicMs());
  if (c.session) c.authorization = "Bearer " + c.session->token.token;
  return c;
}

// The actor recorded in the audit: the token's name, or the client address.
std::string HttpServer::Actor(const Req& req) {
  return exposure()
      ->auth.Decide(req.method, req.path, req.remote_addr, CredentialsOf(req).authorization)
      .actor;
}

AuthDecision HttpServer::Throttled(const std::string& client, const std::string& presented,
                                   const std::function<AuthDecision()>& check) {
  const int64_t now = app_.clock().MonotonicMs();
  auto too_many = [](const std::string& who, int wait_s) {
    AuthDecision d;
    d.status = 429;
    d.reason =
        "too many failed credentials " + who + ": try again in " + std::to_string(wait_s) + " s";
    d.retry_after_s = wait_s;
    return d;
  };
  // Before the credential is looked at: it failed too often, from anywhere.
  if (int wait = auth_throttle_.CredentialWaitS(presented, now); wait > 0) {
    return too_many("with this credential", wait);
  }
  AuthDecision d = check();
  if (d.status != 401) return d;
  const int wait = auth_throttle_.AddressWaitS(client, now);
  auth_throttle_.Failed(client, presented, now);
  return wait > 0 ? too_many("from this address", wait) : d;
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
  l.body_grace_s = c.body_grace_s;
  l.body_min_rate_bytes_per_s = c.body_min_rate_bytes_per_s;
  l.anonymous_worker_share = c.anonymous_worker_share;
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
      {std::regex(m + "/compensation/outcome"), {"axis", "from", "to", "bucket"}},
      {std::regex(m + "/compensation/applied"), {"axis", "limit"}},
      {std::regex(m + "/temperatures"), {"from", "to", "max_points"}},
      {std::regex("/ui/sign-in"), {"next"}},
      {std::regex("/"), {"refresh"}},
      {std::regex("/api/v1/overview"), {"limit", "offset"}},
      {std::regex("/api/v1/audit"), {"machine", "from", "to", "action", "limit", "next"}},
      {std::regex(m + "/column-checks/requests"), {"state"}},
      {std::regex(m + "/column-checks/[0-9]+"), {"format"}},
      {std::regex(m + "/axes/[^/]+/analysis/[0-9]+"), {"format"}},
      {std::regex(m + "/axes/[^/]+/models/[0-9]+"), {"format"}},
      {std::regex(m + "/positioning-checks/[0-9]+"), {"format"}},
      {std::regex(m + "/positioning-checks/[0-9]+/pitch-table"), {"format", "per_direction"}},
      {std::regex(m + "/positioning-checks"), PositioningQueryParameters()},
      {std::regex(m + "/axes/[^/]+/thermal-error"), {"format", "spacing_mm"}},
      {std::regex(m + "/axes/[^/]+/thermal-error/history"),
       {"from", "to", "positions", "max_points"}},
      // Parts (docs/api.md, Parts).
      {std::regex(m + "/plates/[^/]+"), {"axis", "format"}},
      {std::regex(m + "/turned-parts"), {"feature", "from", "to", "limit", "offset"}},
      {std::regex(m + "/turned-parts/report"), {"from", "to", "format"}},
      {std::regex(m + "/process-records"), {"limit"}},
      {std::regex(m + "/part-models/[0-9]+"), {"format"}},
      {std::regex(m + "/surfaces/[^/]+"), {"format"}},
      {std::regex(m + "/surfaces/[^/]+/corrected"), {"iteration", "format"}},
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

// Every X-Forwarded-For header's value, in order.
std::vector<std::string> ForwardedFor(const Req& req) {
  std::vector<std::string> values;
  const size_t n = req.get_header_value_count("X-Forwarded-For");
  values.reserve(n);
  for (size_t i = 0; i < n; ++i) values.push_back(req.get_header_value("X-Forwarded-For", i));
  return values;
}

// `value` as a logfmt value: as it is when it has nothing but letters,
// digits and - _ . / : (a method, most paths, an address), else quoted
// with quotes and backslashes escaped (core/log.h turns control characters
// into '?'). At most 2 KiB of it.
std::string Quoted(std::string_view value) {
  value = value.substr(0, 2048);
  const bool bare = !value.empty() && std::all_of(value.begin(), value.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ||
           c == '/' || c == ':';
  });
  if (bare) return std::string(value);
  std::string out = "\"";
  for (char c : value) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The access log line's fields (docs/operations.md, "Access log"): never a
// query string, header, cookie or token. The path is httplib's, without
// its query.
std::string AccessFields(const Req& req, const Res& res, const std::string& route, double secs,
                         const RequestFacts& facts) {
  char duration[32];
  std::snprintf(duration, sizeof duration, "%.3f", secs * 1000);
  std::string f = "method=" + Quoted(req.method) + " path=" + Quoted(req.path) +
                  " route=" + Quoted(route) + " status=" + std::to_string(res.status) +
                  " bytes=" + std::to_string(res.body.size()) + " duration_ms=" + duration +
                  " actor=" + Quoted(facts.actor.empty() ? "anonymous" : facts.actor) +
                  " client=" + Quoted(req.remote_addr);
  if (facts.malformed_forward) f += " forwarded=\"malformed\"";
  return f;
}

// Nothing here needs byte ranges (no large downloads), and a request for
// thousands of overlapping ranges of one asset multiplies the response:
// the Range header is dropped (httplib parsed it already), so every
// response is the whole resource.
void DropRanges(const Req& req) {
  auto& request = const_cast<Req&>(req);
  request.ranges.clear();
  request.headers.erase("Range");
}

bool IsProbe(const Req& req) {
  return req.path == "/healthz" || req.path == "/readyz";
}

bool HasBody(const Req& req) {
  return req.has_header("Transfer-Encoding") ||
         (req.has_header("Content-Length") && req.get_header_value("Content-Length") != "0");
}

}  // namespace

std::shared_ptr<const HttpServer::Exposure> HttpServer::ExposureOf(const Config& config) {
  return std::make_shared<const Exposure>(Exposure{
      Authorizer(config.tokens), std::make_shared<const ClientAddresses>(config.trusted_proxies),
      config.allowed_hosts, config.access_log});
}

void HttpServer::Reload(const Config& config) {
  std::shared_ptr<const Exposure> fresh = ExposureOf(config);
  std::lock_guard<std::mutex> lock(exposure_mutex_);
  exposure_ = std::move(fresh);
}

HttpServer::HttpServer(App& app)
    : app_(app),
      exposure_(ExposureOf(app.config())),
      sessions_(static_cast<size_t>(app.config().web_max_sessions),
                static_cast<size_t>(app.config().web_max_sessions_per_token),
                int64_t{app.config().web_session_hours} * 3600 * 1000),
      auth_throttle_(app.config().auth_max_failures,
                     int64_t{app.config().auth_failure_window_s} * 1000),
      server_(LimitsOf(app.config())) {
  Routes();
  app_.metrics().SetRoutes(server_.routes().templates());
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
                                         const std::shared_ptr<const MachineCompensation>& c,
                                         const std::shared_ptr<const AppliedByAxis>& applied) {
  {
    std::shared_lock lock(rendered_mutex_);
    if (auto it = rendered_.find(machine);
        it != rendered_.end() && it->second.compensation == c && it->second.applied == applied) {
      return it->second.body;
    }
  }
  std::string body = JsonText(CompensationToJson(*c, applied.get()));
  std::unique_lock lock(rendered_mutex_);
  rendered_[machine] = {c, applied, body};
  return body;
}

void HttpServer::Routes() {
  auto& s = server_;
  const size_t max_body = app_.config().max_body_bytes;
  s.set_pre_routing_handler([this, max_body](const Req& req, Res& res) {
    // One snapshot of what a reload may change, for the whole request.
    const std::shared_ptr<const Exposure> exposure = this->exposure();
    const Authorizer& auth = exposure->auth;
    // Who the request is from (api/client_address.h): the client a trusted
    // proxy names, else the socket's peer.
    const ClientAddresses& clients = *exposure->clients;
    t_shed = false;
    t_facts = RequestFacts{};
    // Reads only: a write that committed is never answered "retry".
    t_lost_before = app_.storage().lost_connections();
    t_watch_archive =
        (req.method == "GET" || req.method == "HEAD") && !IsProbe(req) && req.path != "/metrics";
    t_facts.routed = true;
    const std::string peer = req.remote_addr;
    const bool forwarded = req.has_header("X-Forwarded-For") || req.has_header("Forwarded");
    {
      ClientAddress client = clients.Of(peer, ForwardedFor(req));
      t_facts.malformed_forward = client.malformed_forward;
      // Every consumer (the throttle, the audit's actor, the sign-in, the
      // log) sees the client; connection limits keep the socket's peer.
      const_cast<Req&>(req).remote_addr = std::move(client.address);
    }
    AcceptNoBrotli(req);
    DropRanges(req);
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
    // cpp-httplib reads a body only for POST, PUT, PATCH and DELETE; one
    // sent with another method would stay on the connection and be read
    // as the next request.
    if (HasBody(req) && req.method != "POST" && req.method != "PUT" && req.method != "PATCH" &&
        req.method != "DELETE") {
      return refuse(400, "a " + req.method + " request has no body",
                    {{0, "Content-Length / Transfer-Encoding", "no body with " + req.method}});
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
    // Neither Content-Length nor Transfer-Encoding: a request without a
    // body (RFC 9112, 6.3), answered at once instead of waiting for one
    // until the body deadline.
    if (length.empty() && !req.has_header("Transfer-Encoding")) {
      const_cast<Req&>(req).headers.emplace("Content-Length", "0");
    }
    GuardedServer::ExpectBody(length.empty() ? 0 : std::stoull(length),
                              req.has_header("Transfer-Encoding"));
    if (!IsProbe(req)) {
      const std::string why =
          HostRefusal(req.get_header_value("Host"), req.get_header_value_count("Host") == 1,
                      exposure->allowed_hosts, !auth.open());
      if (!why.empty() || req.get_header_value_count("Host") > 1) {
        const std::string detail = why.empty() ? "more than one Host header" : why;
        return refuse(421, detail, {{0, "Host", detail}});
      }
    }
    // A read-only server (the centre's) shows what the plants ship: no
    // writes, except signing in and out of the pages, and no compensation,
    // which only a line server computes and serves.
    if (app_.config().read_only) {
      const bool session = req.path == "/api/v1/session";
      if (req.method != "GET" && req.method != "HEAD" && !session) {
        res.set_header("Allow", "GET, HEAD");
        return refuse(405,
                      "read-only server (server.read_only): it shows what the plants ship;"
                      " write to the machine's line server");
      }
      static const std::regex served("/api/v1/machines/[^/]+/compensation/?");
      if (std::regex_match(req.path, served)) {
        return refuse(409,
                      "read-only server (server.read_only): compensation is computed and"
                      " served by the machine's line server");
      }
    }
    switch (TakeContentEncoding(req)) {
      case BodyEncoding::kIdentity:
        break;
      case BodyEncoding::kCompressed:
        GuardedServer::ExpectCompressedBody();
        break;
      case BodyEncoding::kUnsupported:
        return refuse(415, "Content-Encoding: only gzip and deflate request bodies are accepted",
                      {{0, "Content-Encoding", "must be gzip, deflate or identity"}});
    }
    // Without tokens only this host is served. A request a proxy forwarded
    // is not from this host, whatever its socket says: from a proxy not
    // listed in server.trusted_proxies it is refused, so a proxy set up
    // without tokens cannot open the server to the network.
    if (auth.open() && forwarded && !IsProbe(req) && !clients.Trusted(peer)) {
      return refuse(403,
                    "forwarded by a proxy: without [[auth.tokens]] only clients on this host are "
                    "served (configure tokens, and server.trusted_proxies for the proxy)");
    }
    const Credentials credentials = CredentialsOf(req);
    auto decide = [&] {
      return auth.Decide(req.method, req.path, req.remote_addr, credentials.authorization);
    };
    const std::string presented = req.get_header_value("Authorization");
    const bool checked = !auth.open() && !IsProbe(req) && !presented.empty();
    AuthDecision d = checked ? Throttled(req.remote_addr, presented, decide) : decide();
    t_facts.actor = d.actor;
    if (!d.challenge.empty()) res.set_header("WWW-Authenticate", d.challenge);
    if (d.retry_after_s > 0) res.set_header("Retry-After", std::to_string(d.retry_after_s));
    if (d.status != 200) return refuse(d.status, d.reason);
    if (std::string why = CrossSiteWrite(req, credentials.session); !why.empty()) {
      return refuse(403, why, {{0, "X-CSRF-Token", why}});
    }
    if (std::string name = UnknownParameter(req); !name.empty()) {
      return refuse(400, "unknown query parameter '" + name + "'",
                    {{0, name, "not a parameter of " + req.method + " " + req.path}});
    }
    // A request without a valid credential, or signing in, may hold only a
    // share of the workers while its body arrives (without tokens every
    // loopback client is authorized: its sign-ins are still anonymous).
    const bool anonymous = d.actor.rfind("anonymous:", 0) == 0 ||
                           (req.method == "POST" && req.path == "/api/v1/session");
    if (anonymous && HasBody(req) && !server_.HoldAnonymousWorker()) {
      t_shed = true;
      return refuse(503, "too many anonymous requests are sending their bodies: retry");
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  // Every HTML response (pages and ?format=html reports) carries the
  // policy; no response offers byte ranges.
  s.set_post_routing_handler([this](const Req&, Res& res) {
    // The archive's server went away while this request read it: what it
    // read may be missing (a store's read that fails returns nothing), so
    // the answer is "retry", not an empty or partial one.
    if (t_watch_archive && res.status < 500 && app_.storage().lost_connections() != t_lost_before) {
      // The framing headers the server set stay; the others were the
      // lost answer's.
      const std::string connection = res.get_header_value("Connection");
      const std::string keep_alive = res.get_header_value("Keep-Alive");
      res.headers.clear();
      WriteProblem(res, 503, "the archive's database cannot be reached: retry");
      res.headers.erase("Retry-After");
      res.set_header("Retry-After", "5");
      res.set_header("Content-Length", std::to_string(res.body.size()));
      if (!connection.empty()) res.set_header("Connection", connection);
      if (!keep_alive.empty()) res.set_header("Keep-Alive", keep_alive);
    }
    t_watch_archive = false;
    if (res.get_header_value("Content-Type").rfind("text/html", 0) == 0 &&
        !res.has_header("Content-Security-Policy")) {
      res.set_header("Content-Security-Policy", kHtmlSecurityPolicy);
    }
    res.headers.erase("Accept-Ranges");
    res.set_header("Accept-Ranges", "none");
  });
  // Per request: its route's counters and latency (service/metrics.h)
  // and, unless server.access_log is off, one access log line.
  s.set_logger([this](const Req& req, const Res& res) {
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                      GuardedServer::RequestStarted())
                            .count();
    const size_t route = server_.routes().Match(req.path);
    app_.metrics().ObserveRequest(route, req.method, res.status, secs);
    if (res.status >= 500 && !t_shed)
      log::Error("request failed", "method=" + req.method + " path=" + Quoted(req.path));
    if (log::Enabled(log::Level::kInfo) && exposure()->access_log) {
      static const std::string kUnmatched = RouteTable::kUnmatchedName;
      static const RequestFacts kUnrouted;
      const auto& names = server_.routes().templates();
      log::Info("request", AccessFields(req, res, route < names.size() ? names[route] : kUnmatched,
                                        secs, t_facts.routed ? t_facts : kUnrouted));
    }
    t_shed = false;
    t_facts = RequestFacts{};
  });
  s.set_error_handler([max_body](const Req& req, Res& res) {
    if (!res.body.empty()) return;
    // It runs outside the handlers' exception handling: it must not throw.
    try {
      // An error the HTTP library answered itself (a Range it refused, a
      // request line it would not take) may come before the body was
      // read: the connection ends with the answer, so no unread body is
      // read as the next request.
      if (HasBody(req) || res.status == 414) {
        res.set_header("Connection", "close");
        GuardedServer::CloseAfterResponse();
      }
      if (auto head = GuardedServer::HeadTooLargeIn(); head != GuardedServer::HeadTooLarge::kNo) {
        res.set_header("Connection", "close");
        if (head == GuardedServer::HeadTooLarge::kRequestLine) {
          return WriteProblem(res, 414, "request line longer than 64 KiB");
        }
        return WriteProblem(res, 431,
                            "request headers too large (a line over 8 KiB, or 64 KiB in all)");
      }
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
          // The request was not understood, so neither is where the next
          // one starts (RFC 9112 9.3): the connection ends with this answer.
          res.set_header("Connection", "close");
          GuardedServer::CloseAfterResponse();
          return WriteProblem(res, 400,
                              "malformed HTTP request: a body needs Content-Length or well-formed "
                              "chunked framing (e.g. curl -d '')");
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
    if (Status s = app_.storage().Ping(); !s.ok()) {
      return WriteProblem(res, 503, "not ready: the archive's database cannot be reached");
    }
    WriteJson(res, {{"status", "ready"}, {"schema_version", app_.storage().schema_version()}});
  });
  s.Get("/metrics", [this](const Req&, Res& res) {
    res.set_content(app_.metrics().Render(app_.ModelGauges() + OperatorGauges(app_) +
                                          app_.shipping_board().Render()),
                    "text/plain; version=0.0.4");
  });

  MachineRoutes();
  IngestRoutes();
  ModelRoutes();
  CompensationRoutes();
  CheckRoutes();
  FeedAxisRoutes();
  ThermalErrorRoutes();
  PlateRoutes();
  TurningRoutes();
  PartModelRoutes();
  SurfaceRoutes();
  OverviewRoutes();
  AlertRoutes();
  AuditRoutes();
  SessionRoutes();
  PageRoutes();
}

}  // namespace thermocomp::api
