// Time parsing: whatever is accepted lies in 2000..2099 and formats back
// to a text that parses to the same millisecond.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/time_format.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)ParseRfc3339(text);
  auto ms = ParseTimestamp(text);
  if (!ms) return 0;
  if (*ms < kEarliestTsMs || *ms >= kLatestTsMs) __builtin_trap();
  auto back = ParseTimestamp(FormatRfc3339(*ms));
  if (!back || *back != *ms) __builtin_trap();
  return 0;
}
