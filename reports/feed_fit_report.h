// FeedFitReport: what one refit of a feed axis did (docs/model.md §14):
// the checks it used and skipped, every model type fitted on the same
// training checks and scored on the same held-out checks (before and after
// per check), the active model (the champion) scored on them too, the
// decision, and the sensor advice. JSON both ways:
// reports/feed_fit_report_codec.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

// A positioning check left out of the fit, and why.
struct FeedSkippedCheck {
  int64_t check_id = 0;
  std::string why;
};

// A model on one held-out check: the thermal error as measured (before)
// and what the model's correction leaves (after), over the check's targets.
struct FeedCheckScore {
  int64_t check_id = 0;
  int64_t ts_ms = 0;
  double max_before_um = 0, rms_before_um = 0;
  double max_after_um = 0, rms_after_um = 0;
  double reduction = 0;  // 1 − max_after / max_before (0 when nothing to remove)
  // Targets the model would not serve itself: predicted by its fallback,
  // or not at all (then left uncorrected in `after`).
  int fallback_targets = 0, invalid_targets = 0;
};

// A model's scores over the held-out checks together.
struct FeedHeldOut {
  std::vector<FeedCheckScore> checks;
  double max_before_um = 0, max_after_um = 0, rms_after_um = 0;
  double reduction = 0;  // of the largest error: 1 − max_after / max_before
};

// What a type identified; fields a type does not have stay empty.
struct FeedTypeParameters {
  std::optional<double> alpha_um_per_m_k, alpha_se;           // screw
  std::optional<double> stiffness_ratio, stiffness_ratio_se;  // screw, preloaded
  std::optional<int> hidden_units, weights;                   // neural
  std::optional<double> effective_parameters;                 // neural: γ
  std::optional<int> coefficients;                            // regression
  std::vector<std::string> inputs;                            // neural, regression
};

// One model type's fit.
struct FeedTypeResult {
  std::string type;
  bool fitted = false;
  std::string error;  // why it could not be fitted (then nothing is stored)
  FeedTypeParameters parameters;
  double training_rmse_um = 0;
  int training_targets = 0;
  FeedHeldOut held_out;
  int version = 0;     // the stored version, 0 when not stored
  std::string status;  // active | candidate | rejected
  std::string reason;
};

// The active model before this fit, scored on the same held-out checks.
struct FeedChampion {
  int version = 0;
  std::string type;
  std::optional<FeedHeldOut> held_out;  // none when it cannot be rebuilt
  std::string note;                     // why it could not be scored
};

// A sensor the fit did without, and why (no data, stuck, out of range).
struct FeedDroppedSensor {
  std::string name;
  bool screw = true;  // a screw sensor (else a body sensor)
  std::string why;
};

// Sensor advice: the interpolation bound at each held-out check, the
// sensors dropped, and what dropping them cost the physical model.
struct FeedSensorAdvice {
  struct Bound {
    int64_t check_id = 0;
    std::optional<double> bound_um;  // none with fewer than three screw sensors
  };
  std::vector<Bound> interpolation_bound;
  std::vector<FeedDroppedSensor> dropped;
  // Held-out max error the physical model leaves with and without the
  // dropped sensors, when both can be computed (their values exist).
  std::optional<double> held_out_max_with_um, held_out_max_without_um;
  std::string cost;  // the same in words
};

struct FeedFitReport {
  std::string machine, axis;
  int64_t created_ms = 0;
  std::string actor, trigger;
  // Checks.
  int64_t reference_check_id = 0;
  std::vector<int64_t> training_check_ids, held_out_check_ids;
  std::vector<FeedSkippedCheck> skipped;
  // Types in the order fitted ("screw" first).
  std::vector<FeedTypeResult> types;
  std::optional<FeedChampion> champion;
  // The decision: the challenger (smallest held-out max error left), and
  // whether it became active.
  std::string challenger;  // type, empty when none could be fitted
  bool accepted = false;
  int active_version = 0;  // the served version after this fit (0: none)
  std::string decision;    // the reason in words
  FeedSensorAdvice sensors;
};

}  // namespace thermocomp
