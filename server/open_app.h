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
// The same over an archive in memory (SQLite, migrated), for a command
// that builds a new database alone and writes it to its file once
// complete (Storage::Backup): the demo, whose minute-by-minute replay
// would otherwise wait for the disk at every small commit.
StatusOr<std::unique_ptr<App>> OpenAppInMemory(const Config& config, const Clock& clock);

}  // namespace thermocomp
