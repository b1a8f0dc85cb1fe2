// The demo's plates: the compensation on/off plate test (placeholder).
#include "server/parts_demo.h"

namespace thermocomp {

Status DemoPlates(App& app, const std::string& machine, std::string* summary) {
  (void)app;
  (void)machine;
  *summary = "";
  return Status::Ok();
}

}  // namespace thermocomp
