// Authorizer: who may do what (docs/api.md, "Authentication"). Without
// configured tokens only loopback clients are served, without tokens. With
// tokens, every request but /healthz, /readyz, the pages' shells and
// assets and signing in (/api/v1/session) needs `Authorization: Bearer
// <token>` or a signed-in session cookie (api/web/web_sessions.h):
//   machine      of its own machine: posts temperatures, probe points,
//                signals, events, column-check results and what its
//                control applied (compensation/applied); reads the
//                machine, its compensation and its open check requests
//   reader       reads everything
//   maintenance  reads everything; posts events, check requests, column
//                and positioning checks
//   admin        everything
// A credential presented on a public route is checked too (a wrong one is
// 401 there as well), so no route answers guesses unchecked; the failure
// throttle (api/auth_throttle.h) is applied by the caller.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/config.h"

namespace thermocomp::api {

struct AuthDecision {
  int status = 200;    // 200 allowed, 401 no/unknown token, 403 not permitted
  std::string reason;  // why not, for the problem detail
  std::string actor;   // who, for the audit
  // With 401: the WWW-Authenticate challenge (RFC 6750), so a client knows
  // which scheme to answer with.
  std::string challenge;
  // With 429: seconds until the client may try again (Retry-After).
  int retry_after_s = 0;
};

class Authorizer {
 public:
  explicit Authorizer(std::vector<AccessToken> tokens) : tokens_(std::move(tokens)) {}
  AuthDecision Decide(const std::string& method, const std::string& path,
                      const std::string& remote_addr, const std::string& authorization) const;
  // The configured token with this secret (signing in to the pages).
  std::optional<AccessToken> FindToken(const std::string& secret) const;
  bool open() const { return tokens_.empty(); }  // no tokens: loopback only, no sign-in

 private:
  std::vector<AccessToken> tokens_;
};

bool IsLoopback(const std::string& addr);

// A Host header's parts: a name (lower case; an IPv6 address without its
// brackets) and the port, -1 when none is given.
struct HostName {
  std::string name;
  int port = -1;
};
// "name", "name:port", "[v6]" or "[v6]:port"; nullopt when malformed.
std::optional<HostName> ParseHost(const std::string& header);
// localhost, an address in 127.0.0.0/8, or ::1.
bool IsLoopbackName(const std::string& name);
// Why the Host header is refused, or "" (docs/api.md, "Host names"): with
// allowed_hosts, only those names (an entry without a port allows any
// port) and loopback names; without, and without tokens, loopback names
// only; with tokens and no list, any name. Guards a server without tokens
// on this host against DNS rebinding (a site whose name a browser resolves
// to 127.0.0.1 would otherwise be this server's origin). A request without
// Host (not a browser) is not checked.
std::string HostRefusal(const std::string& host_header, bool host_given,
                        const std::vector<std::string>& allowed_hosts, bool tokens_configured);
// Compares without an early exit, so timing does not reveal a prefix.
bool SameSecret(const std::string& a, const std::string& b);
// What to tell the operator when the server listens beyond this host
// without tokens (every remote client would get 403); empty otherwise.
std::string ExposureWarning(const std::string& listen_host, const std::vector<AccessToken>& tokens);
// Why `thermocomp serve` must not start on `listen_host`, or "": a
// listen address beyond loopback (127.0.0.0/8, ::1, localhost; a name or
// 0.0.0.0 is beyond) without [[auth.tokens]] is refused unless
// server.allow_network_without_tokens says the operator means it.
std::string ExposureRefusal(const std::string& listen_host, const std::vector<AccessToken>& tokens,
                            bool allow_network_without_tokens);

}  // namespace thermocomp::api
