// The demo's surfaces: the CMM mirror correction (placeholder).
#include "server/parts_demo.h"

namespace thermocomp {

Status DemoSurfaces(App& app, const std::string& machine, std::string* summary) {
  (void)app;
  (void)machine;
  *summary = "";
  return Status::Ok();
}

}  // namespace thermocomp
