#include "service/mtconnect/mtconnect_config.h"

#include <set>

#include "service/ingest_service.h"

namespace thermocomp {

namespace mtconnect_config {

std::string ReadSensors(const toml::node& n, MtconnectSourceConfig& s) {
  const toml::table* t = n.as_table();
  if (!t) return "sensors must be a table of data item id = \"sensor\"";
  std::set<std::string> seen;
  for (const auto& [key, value] : *t) {
    const std::string item(key.str());
    auto sensor = value.value_exact<std::string>();
    if (item.empty() || item.size() > 255) return "sensors: a data item id of 1 to 255 characters";
    if (!sensor || !ValidIdentifier(*sensor)) {
      return "sensors." + item + " must be a sensor id ([A-Za-z0-9_.-]{1,64})";
    }
    if (!seen.insert(*sensor).second) {
      return "sensors: sensor '" + *sensor + "' is fed by two data items";
    }
    s.sensors[item] = *sensor;
  }
  if (s.sensors.empty() || s.sensors.size() > kMtconnectMaxSensors) {
    return "sensors must map 1 to " + std::to_string(kMtconnectMaxSensors) + " data items";
  }
  return "";
}

std::string ReadSource(const toml::table& t, MtconnectSourceConfig& s) {
  for (const auto& [key, value] : t) {
    const std::string k(key.str());
    if (k == "sensors") {
      if (std::string why = ReadSensors(value, s); !why.empty()) return why;
    } else if (k == "machine" || k == "url" || k == "device") {
      auto v = value.value_exact<std::string>();
      if (!v) return k + " must be a string";
      (k == "machine" ? s.machine : k == "url" ? s.url : s.device) = *v;
    } else if (k == "poll_interval_s" || k == "count") {
      auto v = value.value_exact<int64_t>();
      const int64_t max = k == "count" ? kMtconnectMaxCount : 3600;
      if (!v || *v < 1 || *v > max)
        return k + " must be an integer within 1.." + std::to_string(max);
      (k == "count" ? s.count : s.poll_s) = static_cast<int>(*v);
    } else {
      return "unknown key '" + k + "' (machine, url, device, poll_interval_s, count, sensors)";
    }
  }
  if (!ValidIdentifier(s.machine)) return "machine must be a machine id ([A-Za-z0-9_.-]{1,64})";
  AgentUrl url;
  if (!ParseAgentUrl(s.url, &url)) {
    return s.machine + ": url must be http://host[:port][/path] (plain HTTP, no query)";
  }
  if (s.device.size() > 255 || s.device.find_first_of("/?#% ") != std::string::npos) {
    return s.machine + ": device must be a device's name or uuid without / ? # % or spaces";
  }
  if (s.sensors.empty()) return s.machine + ": sensors must map at least one data item";
  return "";
}

}  // namespace mtconnect_config

bool ParseAgentUrl(const std::string& url, AgentUrl* out) {
  const std::string scheme = "http://";
  if (url.size() > 2048 || url.compare(0, scheme.size(), scheme) != 0) return false;
  const size_t slash = url.find('/', scheme.size());
  const std::string authority = url.substr(scheme.size(), slash - scheme.size());
  if (authority.empty() || authority.find_first_of("@?# ") != std::string::npos) return false;
  std::string prefix = slash == std::string::npos ? "" : url.substr(slash);
  if (prefix.find_first_of("?# ") != std::string::npos) return false;
  while (!prefix.empty() && prefix.back() == '/') prefix.pop_back();
  out->host_port = scheme + authority;
  out->prefix = prefix;
  return true;
}

std::string ReadMtconnectSources(const toml::node& n, Config& c) {
  const toml::array* list = n.as_array();
  if (!list) return "must be [[mtconnect.sources]] tables";
  std::set<std::string> machines;
  for (size_t i = 0; i < list->size(); ++i) {
    const toml::table* t = (*list)[i].as_table();
    const std::string where = "[" + std::to_string(i) + "]: ";
    if (!t) return where + "each entry must be a table";
    MtconnectSourceConfig s;
    if (std::string why = mtconnect_config::ReadSource(*t, s); !why.empty()) return where + why;
    if (!machines.insert(s.machine).second) {
      return where + s.machine + " has two sources; one agent per machine";
    }
    c.mtconnect_sources.push_back(std::move(s));
  }
  return "";
}

}  // namespace thermocomp
