// OpenCentre: the centre a line ships to (storage/shipping.h), a PostgreSQL
// database at `url` opened as an archive (collation checked, migrated to
// this program's schema) and written through SqlCentre.
#pragma once

#include <memory>
#include <string>

#include "core/status.h"
#include "storage/shipping.h"

namespace thermocomp {

StatusOr<std::unique_ptr<Centre>> OpenCentre(const std::string& url);

}  // namespace thermocomp
