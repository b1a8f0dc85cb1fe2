// part-error models from the process (docs/api.md): placeholder, the routes follow.
#include "api/http_server.h"  // first: Eigen before httplib.h

namespace thermocomp::api {

void HttpServer::PartModelRoutes() {}

}  // namespace thermocomp::api
