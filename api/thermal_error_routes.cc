// Thermal error table routes (docs/api.md): being written.
#include "api/http_server.h"

namespace thermocomp::api {

void HttpServer::ThermalErrorRoutes() {}

}  // namespace thermocomp::api
