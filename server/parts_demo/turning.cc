// The demo's turned parts: the four-diameter decomposition (placeholder).
#include "server/parts_demo.h"

namespace thermocomp {

Status DemoTurning(App& app, const std::string& machine, std::string* summary) {
  (void)app;
  (void)machine;
  *summary = "";
  return Status::Ok();
}

}  // namespace thermocomp
