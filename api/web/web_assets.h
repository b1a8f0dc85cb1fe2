// The pages' own files (api/web/assets/: the page shell, scripts and the
// stylesheet), embedded at build time so the server needs nothing beside
// its binary but Debian's charting library.
#pragma once

#include <string_view>

namespace thermocomp::api {

struct WebAsset {
  const char* name;  // "overview.js"
  const char* type;  // Content-Type
  const char* body;
};

// The asset with this file name, or nullptr.
const WebAsset* FindWebAsset(std::string_view name);

}  // namespace thermocomp::api
