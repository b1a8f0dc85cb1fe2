// What is read back from the database as JSON (a stored model, its terms):
// a damaged row is an error, never a crash, and a model that loads is
// evaluated to a finite, clamped offset or none.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/drift_model.h"
#include "reports/model_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto m = DriftModelFromJson(text);
  if (!m.ok()) return 0;
  std::vector<double> terms(m->inputs.size(), 1.0);
  const Compensation c = Compensate(*m, terms);
  if (!std::isfinite(c.offset_mm) || std::fabs(c.offset_mm) > std::fabs(m->clamp_mm)) {
    if (c.valid) __builtin_trap();
  }
  for (size_t j = 0; j < m->inputs.size(); ++j) (void)m->TermAt(j).Name();
  return 0;
}
