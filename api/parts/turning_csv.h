// Bodies of POST .../turned-parts (docs/api.md "Turned parts") into the
// TurningService's inputs: syntax and types only, the content rules live
// in the service. Diameters are read as exact decimals in mm (whole nm,
// model/parts/diameter_decimal.h).
#pragma once

#include <string>
#include <vector>

#include "core/field_errors.h"
#include "core/status.h"
#include "service/parts/turning/turning_service.h"

namespace thermocomp::api {

// "part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,cut_at" in any order, no
// other columns; errors name the data row (1 = first after the header,
// blank lines counted and skipped) and the column. More data rows than
// TurningService::kMaxRows: TooLarge in `status`.
bool ParseTurnedPartsCsv(const std::string& body, std::vector<TurnedPartInput>& out,
                         FieldErrors& errors, Status* status);
// {"parts": [{part, feature, d_des_mm, ..., cut_at}]}; a diameter is a
// JSON number (read as its shortest decimal) or a decimal string
// ("40.030"); errors name the item (from 0) and the field.
bool ParseTurnedPartsJson(const std::string& body, std::vector<TurnedPartInput>& out,
                          FieldErrors& errors, Status* status);

}  // namespace thermocomp::api
