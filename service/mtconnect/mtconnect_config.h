// Reading [[mtconnect.sources]] (service/config.cc's reader of that key):
// each a table with machine, url (http:// only: the agent speaks plain
// HTTP and is reached on the plant network or loopback), device,
// poll_interval_s, count and a [mtconnect.sources.sensors] table of data
// item id = sensor. A refusal names the entry and key.
#pragma once

#include <string>

#include <toml++/toml.h>

#include "service/config.h"

namespace thermocomp {

// Limits of one source's settings.
inline constexpr int kMtconnectMaxCount = 10000;
inline constexpr int kMtconnectMaxSensors = 256;

// Appends the sources to c.mtconnect_sources; the reason when refused.
std::string ReadMtconnectSources(const toml::node& n, Config& c);

// Splits an agent URL "http://host[:port][/prefix]" into the scheme, host
// and port httplib's client takes and a path prefix without its trailing
// "/"; false when it is not one.
struct AgentUrl {
  std::string host_port;  // "http://host:port"
  std::string prefix;     // "" or "/agent"
};
bool ParseAgentUrl(const std::string& url, AgentUrl* out);

}  // namespace thermocomp
