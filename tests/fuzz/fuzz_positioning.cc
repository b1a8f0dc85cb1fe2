// The laser software's CSV and the ISO 230-2 / VDI 3441 evaluation: any
// data that passes validation is evaluated to finite numbers, and every
// pitch table derived from it is finite too.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/pitch_table.h"
#include "reports/check_codec.h"
#include "reports/json_text.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  const std::string body(reinterpret_cast<const char*>(data), size);
  PositioningData d;
  FieldErrors errors;
  if (!PositioningFromCsv(body, d, errors)) return 0;
  if (!ValidatePositioning(d).ok()) return 0;
  UncertaintyInputs u;
  u.stated = true;
  u.device_um_per_m = 0.5;
  auto e = EvaluatePositioning(d, u);
  if (!e.ok()) return 0;
  (void)JsonText(EvaluationToJson(*e));
  const PitchTable t = MakePitchTable(e->iso);
  for (double v : t.correction_mm) {
    if (!std::isfinite(v)) __builtin_trap();
  }
  return 0;
}
