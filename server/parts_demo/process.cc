// The demo's part-error models from the process (placeholder).
#include "server/parts_demo.h"

namespace thermocomp {

Status DemoPartModels(App& app, const std::string& machine, std::string* summary) {
  (void)app;
  (void)machine;
  *summary = "";
  return Status::Ok();
}

}  // namespace thermocomp
