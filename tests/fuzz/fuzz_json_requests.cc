// The JSON request bodies of every route that is not a plain ingest batch:
// machine definitions, events, artifacts, column checks, positioning
// checks; through the bounded parser and the field readers, and the result
// written back out as JSON (nesting and invalid UTF-8 must not reach the
// writer).
#include <cstddef>
#include <cstdint>
#include <string>

#include "api/ingest_parsers.h"
#include "api/json_mapping.h"
#include "reports/check_codec.h"
#include "reports/json_text.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  if (size == 0) return 0;
  const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
  FieldErrors errors;
  switch (data[0] % 5) {
    case 0: {
      if (auto m = api::MachineFromJson("m1", body, errors)) {
        MachineRecord r;
        r.name = m->name;
        r.sensors = m->sensors;
        r.axes = m->axes;
        (void)JsonText(api::MachineToJson(r));
      }
      break;
    }
    case 1: {
      EventInput e;
      (void)api::ParseEventJson(body, e, errors);
      break;
    }
    default: {
      auto j = ParseJsonBody(body, errors);
      if (!j) break;
      (void)JsonText(*j);  // a parsed body is always writable
      if (data[0] % 5 == 2) (void)ArtifactFromJson(*j, errors);
      if (data[0] % 5 == 3) (void)ColumnCheckFromJson(*j, errors);
      if (data[0] % 5 == 4) {
        if (auto p = PositioningFromJson(*j, errors)) (void)JsonText(PositioningInputToJson(*p));
      }
      break;
    }
  }
  return 0;
}
