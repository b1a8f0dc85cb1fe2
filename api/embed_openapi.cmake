# Writes OUT: docs/openapi.json as a string the server serves.
file(READ ${IN} text)
file(WRITE ${OUT} "// Generated from docs/openapi.json by embed_openapi.cmake. Do not edit.\n#include \"api/openapi.h\"\nnamespace thermocomp::api {\nconst char* OpenApiJson() {\n  return R\"thermocomp_json(${text})thermocomp_json\";\n}\n}  // namespace thermocomp::api\n")
