// Process records as CSV (docs/api.md, "Part models"): a header naming the
// columns, then one turned feature per line:
//   part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min[,fc_n,ff_n,fp_n,
//   displacement_um,temperature_c],size_error_um[,cylindricity_um,roundness_um]
// in any order; at least one of the three errors. An empty cell in an
// optional column is "not logged / not measured". cut_at is RFC 3339 or
// Unix milliseconds. No quoting (names and numbers only).
//
// Errors name the data row (1 = the first line after the header; blank
// lines count) and the column. The body must be valid UTF-8; at most
// kMaxProcessCsvRows lines after the header, blank ones included
// (TooLarge beyond).
#pragma once

#include <string_view>
#include <vector>

#include "core/field_errors.h"
#include "core/status.h"
#include "service/parts/process/part_model_service.h"

namespace thermocomp::api {

inline constexpr size_t kMaxProcessCsvRows = PartModelService::kMaxRecords;

// `rows[i]`: the data row of out[i]. InvalidArgument (errors) or TooLarge.
Status ParseProcessCsv(std::string_view body, std::vector<ProcessRecordInput>& out,
                       std::vector<size_t>& rows, FieldErrors& errors);

}  // namespace thermocomp::api
