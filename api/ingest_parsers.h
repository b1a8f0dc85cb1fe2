// Parsers of ingest bodies (JSON and CSV) into the service's inputs. They
// check syntax and types only; the rules on content live in IngestService.
// Shared by the HTTP routes and `thermocomp import`.
#pragma once

#include <string>
#include <vector>

#include "server/ingest_service.h"

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

}  // namespace thermocomp::api
