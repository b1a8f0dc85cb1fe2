// surfaces: the CMM mirror correction (docs/api.md): placeholder, the routes follow.
#include "api/http_server.h"  // first: Eigen before httplib.h

namespace thermocomp::api {

void HttpServer::SurfaceRoutes() {}

}  // namespace thermocomp::api
