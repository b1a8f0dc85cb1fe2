// Signing in to the pages (docs/pages.md, Access): a token is traded once
// for a session cookie; the pages ask who they are to show what the role
// may do.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/problem.h"
#include "core/time_format.h"
#include "reports/json_fields.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

// The cookie: never readable by scripts, never sent by another site.
std::string SessionCookie(const std::string& value, int64_t max_age_s, bool secure) {
  // Appended, not a chain of operator+: GCC 12 reports a false
  // -Warray-bounds inside such a chain when it inlines it (GCC PR 105651).
  std::string cookie(kSessionCookie);
  cookie.append("=").append(value).append("; Path=/; Max-Age=");
  cookie.append(std::to_string(max_age_s)).append("; HttpOnly; SameSite=Strict");
  if (secure) cookie.append("; Secure");
  return cookie;
}

json Identity(const std::string& auth, const AccessToken& t) {
  return {{"auth", auth},
          {"name", t.name},
          {"role", t.role},
          {"machine", t.machine.empty() ? json(nullptr) : json(t.machine)}};
}

}  // namespace

void HttpServer::SessionRoutes() {
  auto& s = server_;
  const std::string path = "/api/v1/session";
  // Every answer says whether the server takes writes at all (a centre's
  // does not), so the pages offer only what it takes.
  auto mode = [this](json out) {
    out["read_only"] = app_.config().read_only;
    return out;
  };
  s.Post(path, [this, mode](const Req& req, Res& res) {
    auto body = JsonObjectBody(req, res);
    if (!body) return;
    FieldErrors errors;
    JsonFields f(*body, errors);
    auto secret = f.String("token", JsonFields::kRequired, 512);
    if (secret && secret->empty()) errors.push_back({0, "token", "must not be empty"});
    if (!errors.empty() || !secret) return WriteProblem(res, 400, "invalid sign-in", errors);
    if (exposure()->auth.open()) {
      return WriteProblem(res, 409,
                          "no access tokens are configured: the pages work without signing in "
                          "(loopback clients only)");
    }
    // Guessing is slowed per client address and per token tried; a right
    // token is never refused, and a success forgets no failure.
    std::optional<AccessToken> token;
    const AuthDecision d = Throttled(req.remote_addr, "Bearer " + *secret, [&] {
      token = exposure()->auth.FindToken(*secret);
      AuthDecision found;
      if (!token) {
        found.status = 401;
        found.reason = "unknown token";
      }
      return found;
    });
    if (d.status == 429) {
      res.set_header("Retry-After", std::to_string(d.retry_after_s));
      return WriteProblem(res, 429, d.reason);
    }
    if (!token) {
      res.set_header("WWW-Authenticate", R"(Bearer realm="thermocomp", error="invalid_token")");
      return WriteProblem(res, 401, "unknown token", {{0, "token", "not a configured token"}});
    }
    const WebSession session =
        sessions_.Create(*token, app_.clock().NowMs(), app_.clock().MonotonicMs());
    const Config& c = app_.config();
    res.set_header("Set-Cookie", SessionCookie(session.id, int64_t{c.web_session_hours} * 3600,
                                               c.web_secure_cookie));
    json out = Identity("session", *token);
    out["csrf_token"] = session.csrf;
    out["expires_at"] = FormatRfc3339(session.expires_ms);
    WriteJson(res, mode(out), 201);
  });
  s.Get(path, [this, mode](const Req& req, Res& res) {
    if (exposure()->auth.open()) {
      // Every loopback client may do everything (docs/api.md, Authentication).
      return WriteJson(res, mode(Identity("open", {"local", "", "admin", ""})));
    }
    const Credentials c = CredentialsOf(req);
    if (c.session) {
      json out = Identity("session", c.session->token);
      out["csrf_token"] = c.session->csrf;
      out["expires_at"] = FormatRfc3339(c.session->expires_ms);
      return WriteJson(res, mode(out));
    }
    const std::string bearer = "Bearer ";
    if (c.authorization.rfind(bearer, 0) == 0) {
      if (auto t = exposure()->auth.FindToken(c.authorization.substr(bearer.size()))) {
        return WriteJson(res, mode(Identity("bearer", *t)));
      }
    }
    // Not signed in is an answer, not an error: the pages then offer to sign in.
    WriteJson(res,
              mode({{"auth", "none"}, {"name", nullptr}, {"role", nullptr}, {"machine", nullptr}}));
  });
  s.Delete(path, [this, mode](const Req& req, Res& res) {
    const std::string id = CookieValue(req.get_header_value("Cookie"), kSessionCookie);
    if (!id.empty()) sessions_.Remove(id);
    res.set_header("Set-Cookie", SessionCookie("", 0, app_.config().web_secure_cookie));
    WriteJson(res,
              mode({{"auth", "none"}, {"name", nullptr}, {"role", nullptr}, {"machine", nullptr}}));
  });
}

}  // namespace thermocomp::api
