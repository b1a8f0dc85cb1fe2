// turned parts: the four-diameter decomposition (docs/api.md): placeholder, the routes follow.
#include "api/http_server.h"  // first: Eigen before httplib.h

namespace thermocomp::api {

void HttpServer::TurningRoutes() {}

}  // namespace thermocomp::api
