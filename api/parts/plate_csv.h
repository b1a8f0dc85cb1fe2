// The CMM file of a test plate (docs/api.md, "Test plates"): UTF-8 CSV with
// the header hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,
// compensation,bored_at in any order (each once, no others), one hole per
// row; cells may be double-quoted. Syntax and types only (finite numbers,
// pair an integer 1..1 000 000, compensation on|off, bored_at RFC 3339 or
// Unix ms); the rules on content live in PlateService. Blank lines are
// skipped but counted: at most kMaxPlateCsvLines lines in all.
#pragma once

#include <string_view>
#include <vector>

#include "core/field_errors.h"
#include "core/status.h"
#include "service/parts/plates/plate_service.h"

namespace thermocomp::api {

inline constexpr size_t kMaxPlateCsvLines = kMaxPlateHoles + 1;

// Ok, or InvalidArgument / TooLarge with `errors` (index = data row, 1 =
// the first row after the header; 0 for the body or the header).
Status ParsePlateCsv(std::string_view body, std::vector<PlateHoleInput>& out, FieldErrors& errors);

}  // namespace thermocomp::api
