// OpenApp: the services over the archive the configuration names (an
// SQLite file, migrated at open). The one place that picks a backend.
#pragma once

#include <memory>

#include "core/clock.h"
#include "core/status.h"
#include "service/app.h"
#include "service/config.h"

namespace thermocomp {

StatusOr<std::unique_ptr<App>> OpenApp(const Config& config, const Clock& clock);

}  // namespace thermocomp
