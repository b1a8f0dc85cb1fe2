#include "api/client_address.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <cstring>

namespace thermocomp::api {
namespace {

// More hops than any plant's proxies add: beyond, the header is not trusted.
constexpr size_t kMaxHops = 32;

std::string_view TrimSpaces(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::optional<std::array<unsigned char, 16>> ParseIp(std::string_view text) {
  if (text.empty() || text.size() >= INET6_ADDRSTRLEN) return std::nullopt;
  char buf[INET6_ADDRSTRLEN] = {0};
  std::memcpy(buf, text.data(), text.size());
  std::array<unsigned char, 16> out{};
  in_addr v4{};
  if (inet_pton(AF_INET, buf, &v4) == 1) {
    out[10] = out[11] = 0xff;
    std::memcpy(out.data() + 12, &v4, 4);
    return out;
  }
  in6_addr v6{};
  if (inet_pton(AF_INET6, buf, &v6) == 1) {
    std::memcpy(out.data(), &v6, 16);
    return out;
  }
  return std::nullopt;
}

ClientAddresses::ClientAddresses(const std::vector<std::string>& trusted_proxies) {
  for (const std::string& p : trusted_proxies) {
    if (auto ip = ParseIp(p)) trusted_.push_back(*ip);
  }
}

bool ClientAddresses::Trusted(std::string_view address) const {
  if (trusted_.empty()) return false;
  const auto ip = ParseIp(address);
  return ip && std::find(trusted_.begin(), trusted_.end(), *ip) != trusted_.end();
}

ClientAddress ClientAddresses::Of(const std::string& peer,
                                  const std::vector<std::string>& forwarded_for) const {
  ClientAddress client{peer};
  if (forwarded_for.empty() || !Trusted(peer)) return client;
  // The hops in order, every header's list after the previous one's.
  std::vector<std::string_view> hops;
  for (const std::string& header : forwarded_for) {
    std::string_view rest = header;
    while (true) {
      const size_t comma = rest.find(',');
      const std::string_view hop = TrimSpaces(rest.substr(0, comma));
      if (!ParseIp(hop) || hops.size() == kMaxHops) {
        client.malformed_forward = true;
        return client;
      }
      hops.push_back(hop);
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
  }
  // The rightmost hop no trusted proxy is: the proxies append, so
  // everything left of it is what the client itself claimed.
  std::string_view chosen = hops.front();
  for (auto it = hops.rbegin(); it != hops.rend(); ++it) {
    if (!Trusted(*it)) {
      chosen = *it;
      break;
    }
  }
  client.address = std::string(chosen);
  client.forwarded = true;
  return client;
}

}  // namespace thermocomp::api
