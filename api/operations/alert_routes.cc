// Placeholder: the alert routes land here.
#include "api/http_server.h"

namespace thermocomp::api {

void HttpServer::AlertRoutes() {}

}  // namespace thermocomp::api
