// RFC 9457 problem details (application/problem+json), as api.md specifies:
// type, title, status, detail and, for bad items in a batch, errors[].
#pragma once

#include <string>
#include <vector>

#include <httplib.h>

#include "core/ingest_inputs.h"
#include "core/status.h"

namespace thermocomp::api {

int HttpStatus(const Status& s);
void WriteProblem(httplib::Response& res, int http_status, const std::string& detail,
                  const FieldErrors& errors = {});
void WriteProblem(httplib::Response& res, const Status& s, const FieldErrors& errors = {});

}  // namespace thermocomp::api
