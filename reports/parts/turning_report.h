// Turned parts as reports (docs/model.md §15, docs/api.md "Turned parts"):
// a part's four diameters with their components, a feature's history, and
// a machine's report per feature (counts, means, latest, the thermal share
// over time and before/after the latest compensation change). Values the
// TurningService returns; JSON in turning_report.cc (components in mm as
// measured, exact; means and trends in µm), Markdown in
// turning_report_text.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/parts/diameter_decomposition.h"

namespace thermocomp {

struct TurnedPart {
  std::string part, feature;
  int64_t cut_ms = 0;
  FourDiameters d;
  DiameterComponents c;
};

// A model version put into service on one of the machine's axes.
struct CompensationChange {
  int64_t ts_ms = 0;
  std::string axis;
  int version = 0;
  std::string kind;    // drift | feed
  std::string action;  // fit | activate | feed-fit | activate-feed-model
};

// One page of a machine's turned parts, oldest cut first.
struct TurnedPartHistory {
  std::string machine;
  std::optional<std::string> feature;
  int64_t from_ms = 0, to_ms = 0;
  int64_t offset = 0, limit = 0, total = 0;
  std::vector<TurnedPart> parts;
  std::vector<CompensationChange> changes;  // within [from, to]
};

struct TurnedPeriod {
  int64_t start_ms = 0;  // a week (Monday, plant time)
  ComponentSummary summary;
};

struct TurnedFeatureReport {
  std::string feature;
  int64_t first_ms = 0, last_ms = 0;
  ComponentSummary all;
  TurnedPart latest;
  ShareTrend trend;
  std::vector<TurnedPeriod> weeks;
  // Before and after the machine's latest compensation change that has
  // parts of this feature on both sides (a change newer than the feature's
  // last part says nothing about it yet).
  std::optional<CompensationChange> change;
  std::optional<ComponentSummary> before, after;
};

struct TurningReport {
  std::string machine;
  int64_t created_ms = 0, from_ms = 0, to_ms = 0;
  int64_t parts = 0;
  std::vector<CompensationChange> changes;          // every one, oldest first
  std::optional<CompensationChange> latest_change;  // at or before `to`
  std::vector<TurnedFeatureReport> features;        // by name
};

nlohmann::json TurnedPartToJson(const TurnedPart& p);
nlohmann::json CompensationChangeToJson(const CompensationChange& c);
nlohmann::json TurnedPartHistoryToJson(const TurnedPartHistory& h);
nlohmann::json TurningReportToJson(const TurningReport& r);

// JSON text with every floating-point number in its shortest round-trip
// form (std::to_chars), so the double nearest 0.015 prints "0.015":
// nlohmann's own writer does not always find the shortest form (it wrote
// -0.9997779999999999 for -0.999778). Whole doubles keep a ".0".
// Strings are written as JsonText writes them (invalid UTF-8 replaced).
std::string TurningJsonText(const nlohmann::json& j);

}  // namespace thermocomp
