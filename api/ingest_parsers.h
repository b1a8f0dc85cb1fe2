// Parsers of ingest bodies (JSON and CSV) into the service's inputs. They
// check syntax and types only; the rules on content live in IngestService.
// Shared by the HTTP routes and `thermocomp import`.
#pragma once

#include <string>
#include <vector>

#include "core/ingest_inputs.h"

namespace thermocomp::api {

// Each returns false and fills `errors` (index = item or CSV data row,
// 0-based) when the body is malformed.
bool ParseTemperaturesJson(const std::string& body, std::vector<TemperatureInput>& out,
                           FieldErrors& errors);
// Long form "ts,sensor,value" or wide form "ts,<sensor>,<sensor>,...".
bool ParseTemperaturesCsv(const std::string& body, std::vector<TemperatureInput>& out,
                          FieldErrors& errors);
// Auxiliary signals: the temperature shapes with "signal" for "sensor".
bool ParseSignalsJson(const std::string& body, std::vector<SignalInput>& out, FieldErrors& errors);
bool ParseSignalsCsv(const std::string& body, std::vector<SignalInput>& out, FieldErrors& errors);
// {"ts": ..., "kind": "...", "note": "..."}.
bool ParseEventJson(const std::string& body, EventInput& out, FieldErrors& errors);
bool ParseProbePointsJson(const std::string& body, std::vector<ProbePointInput>& out,
                          FieldErrors& errors);
// "ts,run,k,pos_X...,dev_X...,[sensor...]".
bool ParseProbePointsCsv(const std::string& body, std::vector<ProbePointInput>& out,
                         FieldErrors& errors);
// Displacement measured continuously (a test mandrel and displacement
// sensors): "ts,[run,]dev_X,dev_Y,..." in time order, deviations in mm. A
// run is a heating cycle: it starts at the first sample, where the `run`
// value changes, or after a gap longer than `run_gap_ms` (then named by its
// start, "D20260301T060000Z"); its first sample is its datum (k = 0), the others
// follow as k = 1, 2, ... Each file holds whole runs.
bool ParseDisplacementsCsv(const std::string& body, int64_t run_gap_ms,
                           std::vector<ProbePointInput>& out, FieldErrors& errors);

}  // namespace thermocomp::api
