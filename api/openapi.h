// The OpenAPI 3 description of the HTTP API (docs/openapi.json, embedded
// at build time), served at GET /api/v1/openapi.json.
#pragma once

namespace thermocomp::api {

const char* OpenApiJson();

}  // namespace thermocomp::api
