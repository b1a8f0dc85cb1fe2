// Placeholder: the audit routes land here.
#include "api/http_server.h"

namespace thermocomp::api {

void HttpServer::AuditRoutes() {}

}  // namespace thermocomp::api
