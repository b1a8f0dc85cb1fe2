#include "api/auth.h"

namespace thermocomp::api {
namespace {

// "/api/v1/machines/{m}/rest" -> {m, rest}; empty machine otherwise.
std::pair<std::string, std::string> MachineOf(const std::string& path) {
  const std::string prefix = "/api/v1/machines/";
  if (path.rfind(prefix, 0) != 0) return {};
  std::string tail = path.substr(prefix.size());
  auto slash = tail.find('/');
  if (slash == std::string::npos) return {tail, ""};
  return {tail.substr(0, slash), tail.substr(slash + 1)};
}

bool Permitted(const AccessToken& t, const std::string& method, const std::string& path) {
  if (t.role == "admin") return true;
  const bool read = method == "GET" || method == "HEAD";
  if (t.role == "reader") return read;
  if (t.role == "maintenance") {
    // Maintenance logs what it did to a machine, requests and enters checks.
    const std::string rest = MachineOf(path).second;
    return read ||
           (method == "POST" && (rest == "events" || rest == "column-checks" ||
                                 rest == "column-checks/requests" || rest == "positioning-checks"));
  }
  if (t.role == "machine") {
    auto [machine, rest] = MachineOf(path);
    if (machine.empty() || machine != t.machine) return false;
    if (read) return rest.empty() || rest == "compensation" || rest == "column-checks/requests";
    return method == "POST" && (rest == "temperatures" || rest == "probe-points" ||
                                rest == "signals" || rest == "events" || rest == "column-checks");
  }
  return false;
}

// The pages and their assets carry no data (they fetch it through the API
// with the browser's credentials), and signing in needs no credentials yet.
bool IsPublic(const std::string& method, const std::string& path) {
  if (path == "/api/v1/session") return true;
  if (method != "GET" && method != "HEAD") return false;
  return path == "/" || path.rfind("/ui/", 0) == 0 || path.rfind("/static/", 0) == 0;
}

}  // namespace

bool SameSecret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

bool IsLoopback(const std::string& addr) {
  return addr.rfind("127.", 0) == 0 || addr == "::1" || addr.rfind("::ffff:127.", 0) == 0;
}

std::string ExposureWarning(const std::string& host, const std::vector<AccessToken>& tokens) {
  if (!tokens.empty() || IsLoopback(host) || host == "localhost") return "";
  return "listening on " + host +
         " without [[auth.tokens]]: clients on other hosts get 403 Forbidden; only this host is "
         "served. Give every client a token (docs/operations.md, Access).";
}

AuthDecision Authorizer::Decide(const std::string& method, const std::string& path,
                                const std::string& remote_addr,
                                const std::string& authorization) const {
  if (path == "/healthz" || path == "/readyz") return {200, "", "probe", ""};
  if (tokens_.empty()) {
    if (IsLoopback(remote_addr)) return {200, "", "local:" + remote_addr, ""};
    return {403, "no access tokens are configured: only loopback clients are served", "", ""};
  }
  if (IsPublic(method, path)) return {200, "", "anonymous:" + remote_addr, ""};
  const std::string bearer = "Bearer ";
  if (authorization.rfind(bearer, 0) != 0) {
    return {401, "Authorization: Bearer <token> required", "", R"(Bearer realm="thermocomp")"};
  }
  const std::string secret = authorization.substr(bearer.size());
  for (const AccessToken& t : tokens_) {
    if (!SameSecret(t.token, secret)) continue;
    const std::string actor = "token:" + t.name;
    if (!Permitted(t, method, path)) {
      std::string why = "role " + t.role;
      if (!t.machine.empty()) why += " of machine " + t.machine;
      why.append(" may not ").append(method).append(" ").append(path);
      return {403, why, actor, ""};
    }
    return {200, "", actor, ""};
  }
  return {401, "unknown token", "", R"(Bearer realm="thermocomp", error="invalid_token")"};
}

std::optional<AccessToken> Authorizer::FindToken(const std::string& secret) const {
  std::optional<AccessToken> found;
  // Every token is compared, so the time taken does not tell which matched.
  for (const AccessToken& t : tokens_) {
    if (SameSecret(t.token, secret)) found = t;
  }
  return found;
}

}  // namespace thermocomp::api
