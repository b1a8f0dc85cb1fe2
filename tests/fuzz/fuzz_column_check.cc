// A column check end to end on the model side: the artifact definition and
// the check as JSON, evaluated; results are finite or the check refused.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/column_check.h"
#include "reports/check_codec.h"
#include "reports/json_text.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t cut = text.find('\n');
  if (cut == std::string::npos) return 0;
  FieldErrors errors;
  auto a = ParseJsonBody(text.substr(0, cut), errors);
  auto c = ParseJsonBody(text.substr(cut + 1), errors);
  if (!a || !c) return 0;
  auto artifact = ArtifactFromJson(*a, errors);
  auto check = ColumnCheckFromJson(*c, errors);
  if (!artifact || !check) return 0;
  auto r = EvaluateColumnCheck(*artifact, check->temperature_c, check->spheres, check->points,
                               check->parallelism);
  if (!r.ok()) return 0;
  if (!std::isfinite(r->machine_zero_mm.x) || !std::isfinite(r->machine_zero_mm.y) ||
      !std::isfinite(r->machine_zero_mm.z)) {
    __builtin_trap();
  }
  (void)JsonText(ColumnResultToJson(*r));
  return 0;
}
