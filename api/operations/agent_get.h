// The MTConnect sources' HTTP client (service/mtconnect/mtconnect_source.h):
// GETs a document from an agent over plain HTTP with bounded time and
// size, so a hanging or flooding agent costs its source's thread at most
// the timeouts and the server at most kAgentMaxBytes per request.
#pragma once

#include <cstddef>
#include <string>

#include "core/status.h"

namespace thermocomp::api {

inline constexpr int kAgentTimeoutS = 10;                          // connect, and each read
inline constexpr size_t kAgentMaxBytes = size_t{8} * 1024 * 1024;  // one document

// The body of a 200 answer, or of a 4xx one (an agent's MTConnectError);
// InvalidArgument for a URL that is not http://host[:port][/prefix];
// Unavailable when not reached, answered otherwise, or beyond max_bytes.
StatusOr<std::string> GetFromAgent(const std::string& url, const std::string& path_and_query,
                                   size_t max_bytes = kAgentMaxBytes);

}  // namespace thermocomp::api
