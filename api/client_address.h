// ClientAddresses: who a request comes from, for the credential throttle,
// the audit's actor and the access log (docs/operations.md, "Exposure and
// TLS"). A request whose socket peer is one of server.trusted_proxies (the
// TLS proxy, deploy/nginx/) comes from the rightmost X-Forwarded-For
// address that is not itself a trusted proxy (all of them trusted: the
// leftmost); a header that is not a comma-separated list of IP addresses
// leaves the peer, flagged, so the access log can say so. From any other
// peer X-Forwarded-For is ignored: a client cannot name itself someone
// else. Connection limits stay on the socket peer (api/guarded_server.h).
// Immutable after construction: safe from every worker.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace thermocomp::api {

// An IPv4 or IPv6 address as 16 bytes (IPv4 as ::ffff:a.b.c.d), so that
// "127.0.0.1" and "::ffff:127.0.0.1" compare equal; nullopt when `text`
// is not an address literal.
std::optional<std::array<unsigned char, 16>> ParseIp(std::string_view text);

struct ClientAddress {
  std::string address;             // the client as this server sees it
  bool forwarded = false;          // named by a trusted proxy's X-Forwarded-For
  bool malformed_forward = false;  // a trusted proxy sent a header that is not a list of addresses
};

class ClientAddresses {
 public:
  // `trusted_proxies`: IP literals (service/config.cc validates them).
  explicit ClientAddresses(const std::vector<std::string>& trusted_proxies);
  // `forwarded_for`: every X-Forwarded-For header value in order ("" when
  // none was sent).
  ClientAddress Of(const std::string& peer, const std::vector<std::string>& forwarded_for) const;
  bool Trusted(std::string_view address) const;
  bool empty() const { return trusted_.empty(); }

 private:
  std::vector<std::array<unsigned char, 16>> trusted_;
};

}  // namespace thermocomp::api
