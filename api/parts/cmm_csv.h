// The CMM report export (text/csv) of a surface measurement, parsed into
// CmmPoints (docs/api.md, "Surfaces"). Header, in any order:
// point,x_mm,y_mm,z_mm,i,j,k and either mx_mm,my_mm,mz_mm (the measured
// point) or dev_mm (the deviation along the file's normal), optionally
// allowance_mm. Comma separated, '.' decimals, a UTF-8 BOM allowed, cells
// may be wrapped in double quotes. Every error names the data row
// (1 = the first row after the header; blank lines count) and the column;
// a file with any error yields nothing.
#pragma once

#include <string_view>
#include <vector>

#include "core/field_errors.h"
#include "core/status.h"
#include "model/parts/surface_mirror.h"

namespace thermocomp::api {

// At most this many points per file (a 25 × 25 grid is 625; 100 000 rows
// of about 110 bytes are 11 MB, within the default 16 MiB body limit).
inline constexpr size_t kMaxCmmPoints = 100000;
// Lines in all, blank ones included, so a million empty rows stop early.
inline constexpr size_t kMaxCmmLines = kMaxCmmPoints + 1000;

// InvalidArgument (400) with `errors` for a bad file, TooLarge (413) past
// the limits, Unprocessable (422) for a header without data rows.
Status ParseCmmCsv(std::string_view body, std::vector<CmmPoint>& out, FieldErrors& errors);

}  // namespace thermocomp::api
