// Every ingest body parser (temperatures, signals, probe points; JSON and
// CSV; continuous displacement CSV) on arbitrary bytes: the first byte picks the parser. A parse
// either succeeds or reports errors; never a crash, never unbounded errors.
#include <cstddef>
#include <cstdint>
#include <string>

#include "api/ingest_parsers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  if (size == 0) return 0;
  const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
  FieldErrors errors;
  bool ok = false;
  switch (data[0] % 7) {
    case 0: {
      std::vector<TemperatureInput> out;
      ok = api::ParseTemperaturesJson(body, out, errors);
      break;
    }
    case 1: {
      std::vector<TemperatureInput> out;
      ok = api::ParseTemperaturesCsv(body, out, errors);
      break;
    }
    case 2: {
      std::vector<SignalInput> out;
      ok = api::ParseSignalsJson(body, out, errors);
      break;
    }
    case 3: {
      std::vector<SignalInput> out;
      ok = api::ParseSignalsCsv(body, out, errors);
      break;
    }
    case 4: {
      std::vector<ProbePointInput> out;
      ok = api::ParseProbePointsJson(body, out, errors);
      break;
    }
    case 5: {
      std::vector<ProbePointInput> out;
      ok = api::ParseProbePointsCsv(body, out, errors);
      break;
    }
    default: {
      std::vector<ProbePointInput> out;
      ok = api::ParseDisplacementsCsv(body, 30 * 60000, out, errors);
      break;
    }
  }
  if (ok != errors.empty() || errors.size() > FieldErrors::kMaxReported) __builtin_trap();
  return 0;
}
