// The feed axis' thermal error as a model type (docs/model.md §14): what a
// type must offer so that fitting, held-out validation, champion/challenger,
// storage and serving treat every type alike. A type is fitted from
// positioning checks (their thermal error: deviation minus the cold
// reference check's, µm, machine coordinates, at each target) and the
// archived temperatures at each check's time, and predicts the error at any
// machine position from temperatures now. A new type (a transfer function,
// a part-error model) implements FeedModelType and registers itself in
// FeedModelTypes(); nothing else changes.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "model/screw/screw_model.h"

namespace thermocomp {

// One positioning check as the types see it.
struct FeedCheck {
  int64_t check_id = 0;
  int64_t ts_ms = 0;
  std::vector<double> position_mm;  // machine positions of the targets
  std::vector<double> error_um;     // thermal error at each target
  // Every configured sensor's temperature at the check (screw sensors
  // first in the axis' order, then body sensors), by name.
  std::map<std::string, double> temperature_c;
  std::optional<double> zeroed_at_mm;
};

// The temperatures a prediction is made from, by sensor name.
using FeedTemperatures = std::map<std::string, double>;

// One predicted value. `valid` false with `reason` when the model must not
// be served here (a neural input outside its trained range, a sensor
// missing); `fallback` names the type that produced error_um instead.
struct FeedPrediction {
  double error_um = 0;
  bool valid = true;
  std::string reason;
  std::string fallback;
};

// A fitted model of one axis, immutable once made.
class FeedModel {
 public:
  virtual ~FeedModel() = default;
  virtual std::string type() const = 0;  // "screw" | "neural" | "regression"
  // The thermal error at each machine position (µm, the sign of
  // ScrewErrorUm: the correction a control adds is its negative).
  virtual std::vector<FeedPrediction> Predict(const FeedTemperatures& t,
                                              const std::vector<double>& position_mm) const = 0;
  // Everything needed to rebuild the model (stored as model_json).
  virtual nlohmann::json ToJson() const = 0;
};

// A model type: fits models of its kind and reads them back.
class FeedModelType {
 public:
  virtual ~FeedModelType() = default;
  virtual std::string name() const = 0;
  // Fits on `training` with the axis' configuration; Unprocessable when the
  // checks cannot determine the model. `fallback` is the physical model fit
  // on the same checks, for types that guard their range (may be null).
  virtual StatusOr<std::shared_ptr<const FeedModel>> Fit(
      const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
      const std::vector<FeedCheck>& training, std::shared_ptr<const FeedModel> fallback) const = 0;
  virtual StatusOr<std::shared_ptr<const FeedModel>> FromJson(
      const ScrewAxis& axis, const nlohmann::json& model_json,
      std::shared_ptr<const FeedModel> fallback) const = 0;
};

// The registered types, "screw" first (it is every other type's fallback).
const std::vector<const FeedModelType*>& FeedModelTypes();
const FeedModelType* FindFeedModelType(const std::string& name);

}  // namespace thermocomp
