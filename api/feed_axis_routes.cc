// Feed-axis routes (docs/api.md): being written.
#include "api/http_server.h"

namespace thermocomp::api {

void HttpServer::FeedAxisRoutes() {}

}  // namespace thermocomp::api
