// An MTConnect agent's documents (service/mtconnect/): whatever the agent
// sends parses or is refused without a crash, and the observations of a
// parsed one, put on the grid, give points on the minute, never one twice
// for an item.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string_view>
#include <vector>

#include "service/mtconnect/mtconnect_document.h"
#include "service/mtconnect/temperature_resampler.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  auto doc = ParseMtconnectDocument(xml);
  if (!doc.ok()) return 0;
  TemperatureResampler grid;
  std::vector<GridSample> out;
  for (const auto& o : doc->temperatures) {
    if (o.data_item_id.empty()) __builtin_trap();
    grid.Observe(o.data_item_id, o.ts_ms, o.value, &out);
  }
  grid.AdvanceTo(doc->header.creation_ms, &out);
  grid.Forget();
  grid.AdvanceTo(doc->header.creation_ms + kGridMs, &out);
  std::map<std::string, int64_t> last;
  for (const auto& g : out) {
    if (g.ts_ms % kGridMs != 0) __builtin_trap();
    auto it = last.find(g.data_item_id);
    if (it != last.end() && g.ts_ms <= it->second) __builtin_trap();
    last[g.data_item_id] = g.ts_ms;
  }
  return 0;
}
