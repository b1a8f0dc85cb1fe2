// The demo's parts (docs/model.md §15): on the demo machine, so that a new
// user can try each part test from the README. Each returns a one-line
// summary for the demo's output.
#pragma once

#include <string>

#include "core/status.h"
#include "service/app.h"

namespace thermocomp {

// Compensation on/off test plates bored on `machine` (simulated, with truth).
Status DemoPlates(App& app, const std::string& machine, std::string* summary);
// Turned features measured four times (the four-diameter decomposition).
Status DemoTurning(App& app, const std::string& machine, std::string* summary);
// Process records and part-error models fitted on them.
Status DemoPartModels(App& app, const std::string& machine, std::string* summary);
// A free-form surface measured on a CMM, mirrored and re-measured.
Status DemoSurfaces(App& app, const std::string& machine, std::string* summary);

}  // namespace thermocomp
