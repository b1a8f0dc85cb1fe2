// PartFitReport: what one fit of part-error models from the process did
// (docs/model.md §15): the random split, the input ranking by sensitivity
// on the training part, each requested type's model and its scores on the
// held-out records against predicting the training mean, the champion and
// the decision. Errors in the target's unit (µm for every target so far).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

struct PartInputRank {
  std::string name;
  double cv_rmse_without = 0;  // the model without this input, cross-validated
  double ratio = 0;            // ÷ the model with every input
  bool kept = false;
};

struct PartRanking {
  std::string structure;  // the quadratic the ranking compares
  int folds = 0;
  double threshold = 0;
  double cv_rmse_all = 0, cv_rmse_mean = 0;
  std::vector<PartInputRank> inputs;  // highest ratio first
};

// One held-out record and what was measured on it.
struct PartHeldOutRow {
  int64_t record_id = 0;
  std::string part, feature;
  double measured = 0;
};

struct PartHeldOutScore {
  size_t rows = 0;
  size_t refused = 0;  // outside the trained range: scored as the training mean
  double rmse = 0, mae = 0, r2 = 0;
  // Over the rows the model did predict (all but the refused), for the
  // model's accuracy where it serves.
  double served_rmse = 0;
  double baseline_rmse = 0;     // predicting the training mean
  bool beats_baseline = false;  // by more than chance (paired, 2 standard errors)
};

struct PartTypeResult {
  std::string type;
  bool fitted = false;
  std::string error;  // why it could not be fitted
  int version = 0;
  std::string status, reason;
  std::vector<std::string> inputs;
  std::vector<std::string> terms;  // quadratic: the terms kept
  std::optional<int> hidden_units;
  std::optional<double> effective_parameters;
  double training_rmse = 0;
  PartHeldOutScore held_out;
  // Per held-out row (PartFitReport::held_out order); null where refused.
  std::vector<std::optional<double>> predicted;
};

struct PartChampion {
  int version = 0;
  std::string type;
  std::optional<PartHeldOutScore> held_out;
  std::string note;
};

struct PartFitReport {
  std::string machine, target;
  int64_t created_ms = 0;
  std::string actor;
  size_t records = 0, training_rows = 0;
  double held_out_share = 0;
  uint64_t seed = 0;
  double training_mean = 0;
  std::vector<std::string> candidates;  // inputs offered to the ranking
  PartRanking ranking;
  std::vector<std::string> kept;  // inputs the types were fitted on
  std::vector<PartHeldOutRow> held_out;
  std::vector<PartTypeResult> types;
  std::optional<PartChampion> champion;
  std::string challenger;
  bool accepted = false;
  std::string decision;
  int active_version = 0;  // served for the target after the fit; 0: none
};

}  // namespace thermocomp
