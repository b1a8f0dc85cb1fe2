#include "api/auth.h"

#include <arpa/inet.h>

#include <cctype>

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

// "axes/{axis}/thermal-error": the feed axis' table a control reads like
// its compensation (not its history, which is for people).
bool IsThermalErrorTable(const std::string& rest) {
  const std::string prefix = "axes/", suffix = "/thermal-error";
  return rest.size() > prefix.size() + suffix.size() && rest.rfind(prefix, 0) == 0 &&
         rest.compare(rest.size() - suffix.size(), suffix.size(), suffix) == 0 &&
         rest.find('/', prefix.size()) == rest.size() - suffix.size();
}

// "column-checks/requests/{id}/acknowledge": the line or maintenance says
// it will run a requested check. Any id segment is passed on, so that the
// route can name a malformed one (400) rather than this refusing it.
bool IsRequestAcknowledgement(const std::string& rest) {
  const std::string prefix = "column-checks/requests/", suffix = "/acknowledge";
  return rest.size() > prefix.size() + suffix.size() && rest.rfind(prefix, 0) == 0 &&
         rest.compare(rest.size() - suffix.size(), suffix.size(), suffix) == 0 &&
         rest.find('/', prefix.size()) == rest.size() - suffix.size();
}

// The part tests quality staff record and evaluate (docs/api.md, Parts):
// "plates...", "turned-parts...", "process-records...", "part-models...",
// "surfaces..." under a machine.
bool IsPartPath(const std::string& rest) {
  for (const char* prefix :
       {"plates", "turned-parts", "process-records", "part-models", "surfaces"}) {
    const size_t n = std::char_traits<char>::length(prefix);
    if (rest.compare(0, n, prefix) == 0 && (rest.size() == n || rest[n] == '/')) return true;
  }
  return false;
}

bool Permitted(const AccessToken& t, const std::string& method, const std::string& path) {
  if (t.role == "admin") return true;
  const bool read = method == "GET" || method == "HEAD";
  if (t.role == "reader") return read;
  // Quality staff judge parts: they record and evaluate part tests.
  if (t.role == "quality") return read || IsPartPath(MachineOf(path).second);
  if (t.role == "maintenance") {
    // Maintenance logs what it did to a machine, requests and enters checks.
    const std::string rest = MachineOf(path).second;
    return read ||
           (method == "POST" &&
            (rest == "events" || rest == "column-checks" || rest == "column-checks/requests" ||
             rest == "positioning-checks" || IsRequestAcknowledgement(rest)));
  }
  if (t.role == "machine") {
    auto [machine, rest] = MachineOf(path);
    if (machine.empty() || machine != t.machine) return false;
    if (read)
      return rest.empty() || rest == "compensation" || rest == "column-checks/requests" ||
             rest == "temperatures/latest" || IsThermalErrorTable(rest);
    return method == "POST" && (rest == "temperatures" || rest == "probe-points" ||
                                rest == "signals" || rest == "events" || rest == "column-checks" ||
                                rest == "compensation/applied" || IsRequestAcknowledgement(rest));
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

std::string ExposureRefusal(const std::string& host, const std::vector<AccessToken>& tokens,
                            bool allow_network_without_tokens) {
  if (!tokens.empty() || allow_network_without_tokens) return "";
  std::string name = host;
  if (name.size() > 2 && name.front() == '[' && name.back() == ']') {
    name = name.substr(1, name.size() - 2);
  }
  if (IsLoopbackName(name)) return "";
  return "server.listen is " + host +
         ", beyond loopback, and no [[auth.tokens]] are configured: every client on the network "
         "would be refused, and a proxy on this host would pass them all in as local. Give every "
         "client a token, or listen on 127.0.0.1 behind the TLS proxy (deploy/nginx/), or set "
         "server.allow_network_without_tokens = true to serve only this host on that address "
         "(docs/operations.md, Exposure and TLS).";
}

AuthDecision Authorizer::Decide(const std::string& method, const std::string& path,
                                const std::string& remote_addr,
                                const std::string& authorization) const {
  if (path == "/healthz" || path == "/readyz") return {200, "", "probe", ""};
  if (tokens_.empty()) {
    if (IsLoopback(remote_addr)) return {200, "", "local:" + remote_addr, ""};
    return {403, "no access tokens are configured: only loopback clients are served", "", ""};
  }
  const bool is_public = IsPublic(method, path);
  if (is_public && authorization.empty()) return {200, "", "anonymous:" + remote_addr, ""};
  const std::string bearer = "Bearer ";
  if (authorization.rfind(bearer, 0) != 0) {
    return {401, "Authorization: Bearer <token> required", "", R"(Bearer realm="thermocomp")"};
  }
  const std::string secret = authorization.substr(bearer.size());
  for (const AccessToken& t : tokens_) {
    if (!SameSecret(t.token, secret)) continue;
    const std::string actor = "token:" + t.name;
    if (!is_public && !Permitted(t, method, path)) {
      std::string why = "role " + t.role;
      if (!t.machine.empty()) why += " of machine " + t.machine;
      why.append(" may not ").append(method).append(" ").append(path);
      return {403, why, actor, ""};
    }
    return {200, "", actor, ""};
  }
  return {401, "unknown token", "", R"(Bearer realm="thermocomp", error="invalid_token")"};
}

std::optional<HostName> ParseHost(const std::string& header) {
  HostName host;
  std::string rest;
  if (!header.empty() && header[0] == '[') {
    const size_t close = header.find(']');
    if (close == std::string::npos) return std::nullopt;
    host.name = header.substr(1, close - 1);
    in6_addr v6{};
    if (inet_pton(AF_INET6, host.name.c_str(), &v6) != 1) return std::nullopt;
    rest = header.substr(close + 1);
  } else {
    const size_t colon = header.find(':');
    host.name = header.substr(0, colon);
    rest = colon == std::string::npos ? "" : header.substr(colon);
    if (host.name.empty() || host.name.size() > 253) return std::nullopt;
    for (char c : host.name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') return std::nullopt;
    }
  }
  if (!rest.empty()) {
    const std::string digits = rest.substr(1);
    if (rest[0] != ':' || digits.empty() || digits.size() > 5 ||
        digits.find_first_not_of("0123456789") != std::string::npos || std::stoi(digits) > 65535) {
      return std::nullopt;
    }
    host.port = std::stoi(digits);
  }
  for (char& c : host.name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return host;
}

bool IsLoopbackName(const std::string& name) {
  if (name == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, name.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

std::string HostRefusal(const std::string& host_header, bool host_given,
                        const std::vector<std::string>& allowed_hosts, bool tokens_configured) {
  if (!host_given || (allowed_hosts.empty() && tokens_configured)) return "";
  const std::optional<HostName> host = ParseHost(host_header);
  const std::string shown = host_header.substr(0, 100);
  if (!host) return "Host '" + shown + "' is not a host name with an optional port";
  if (IsLoopbackName(host->name)) return "";
  for (const std::string& entry : allowed_hosts) {
    const std::optional<HostName> allowed = ParseHost(entry);
    if (allowed && allowed->name == host->name &&
        (allowed->port < 0 || allowed->port == host->port)) {
      return "";
    }
  }
  return "Host '" + shown + "' is not a name of this server" +
         (allowed_hosts.empty() ? " (without tokens only loopback names are served)"
                                : " (server.allowed_hosts)");
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
