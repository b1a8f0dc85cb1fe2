#include "api/operations/agent_get.h"

#include <charconv>

// Before cpp-httplib: the configuration brings Eigen, which glibc's
// resolv.h (pulled in by httplib.h) breaks with its `_res` macro.
#include "service/mtconnect/mtconnect_config.h"

#include <httplib.h>

namespace thermocomp::api {

StatusOr<std::string> GetFromAgent(const std::string& url, const std::string& path_and_query,
                                   size_t max_bytes) {
  AgentUrl where;
  if (!ParseAgentUrl(url, &where)) {
    return Status::InvalidArgument("not an http://host[:port][/prefix] URL: " + url);
  }
  httplib::Client client(where.host_port);
  client.set_connection_timeout(kAgentTimeoutS, 0);
  client.set_read_timeout(kAgentTimeoutS, 0);
  client.set_write_timeout(kAgentTimeoutS, 0);
  client.set_follow_location(false);
  std::string body;
  bool too_large = false;
  int status = 0;
  const httplib::Result res = client.Get(
      where.prefix + path_and_query, httplib::Headers{{"Accept", "application/xml"}},
      [&](const httplib::Response& r) {
        status = r.status;
        // A declared length beyond the limit is refused before its body.
        const std::string declared = r.get_header_value("Content-Length");
        size_t length = 0;
        const auto [end, ec] =
            std::from_chars(declared.data(), declared.data() + declared.size(), length);
        if (!declared.empty() && (ec != std::errc() || length > max_bytes)) {
          too_large = true;
          return false;
        }
        return true;
      },
      [&](const char* data, size_t length) {
        if (body.size() + length > max_bytes) {
          too_large = true;
          return false;
        }
        body.append(data, length);
        return true;
      });
  if (too_large) {
    return Status::Unavailable("the agent's answer exceeds " + std::to_string(max_bytes) +
                               " bytes");
  }
  if (!res) {
    return Status::Unavailable("agent " + where.host_port +
                               " not reached: " + httplib::to_string(res.error()));
  }
  if (status == 200 || (status >= 400 && status < 500 && !body.empty())) return body;
  return Status::Unavailable("agent answered HTTP " + std::to_string(status));
}

}  // namespace thermocomp::api
