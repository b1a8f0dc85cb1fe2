// Part error from the process as a model type (docs/model.md §15): what a
// type must offer so that the split, the ranking, held-out scoring,
// champion/challenger, storage and serving treat every type alike. A type
// is fitted on process records (the selected inputs: cutting settings and
// logged signals, against one target: a size or form error, µm) and
// predicts the target from named inputs. A new type implements
// PartModelType and registers itself in PartModelTypes(); nothing else
// changes.
//
// The extrapolation guard lives in PartModel, not in the types: each
// input's trained range (its minimum and maximum over the training
// records) is stored with every model, and Predict refuses an input outside
// it (valid false, in_range false, the inputs outside with their ranges, no
// value) before a type's own evaluation is reached. A value is never
// returned for inputs outside the trained ranges.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/parts/part_model_report.h"

namespace thermocomp {

using PartInputs = std::map<std::string, double>;

struct PartInputRange {
  std::string name;
  double low = 0, high = 0;
};

struct PartOutOfRange {
  std::string name;
  double value = 0, low = 0, high = 0;
};

struct PartPrediction {
  bool valid = false;
  bool in_range = false;
  std::optional<double> value;  // only when valid
  std::string reason;           // why not valid
  std::vector<PartOutOfRange> outside;
  std::vector<std::string> missing;  // inputs the model needs and was not given
};

// What a type is fitted on: rows of x (one column per input, in `inputs`
// order) against y (the target).
struct PartTrainingSet {
  std::string target;
  std::vector<std::string> inputs;
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
};

struct PartFitOptions {
  double t_min = 2.0;  // quadratic: backward elimination below this |t|
  int neural_hidden = 3;
  int neural_restarts = 3;
  uint64_t seed = 1;
};

// A fitted model of one target, immutable once made.
class PartModel {
 public:
  PartModel(std::string target, std::vector<PartInputRange> ranges)
      : target_(std::move(target)), ranges_(std::move(ranges)) {}
  virtual ~PartModel() = default;

  virtual std::string type() const = 0;
  virtual double training_rmse() const = 0;
  // What the report shows of the model (terms, hidden units).
  virtual void Describe(PartTypeResult& result) const = 0;

  // The guarded prediction: missing or non-finite inputs and inputs outside
  // their trained range give valid = false and no value.
  PartPrediction Predict(const PartInputs& inputs) const;
  // {"type", "target", "inputs", "ranges": [{"name", "low", "high"}], ...}:
  // everything needed to rebuild the model.
  nlohmann::json ToJson() const;

  const std::string& target() const { return target_; }
  const std::vector<PartInputRange>& ranges() const { return ranges_; }
  std::vector<std::string> inputs() const;

 protected:
  // The type's value at x (inputs in ranges() order), called only in range.
  virtual double Evaluate(const Eigen::VectorXd& x) const = 0;
  // The type's own fields of the JSON.
  virtual nlohmann::json Body() const = 0;

 private:
  std::string target_;
  std::vector<PartInputRange> ranges_;
};

// The ranges of the columns of a training set.
std::vector<PartInputRange> TrainedRanges(const PartTrainingSet& set);
// The common fields of a stored model; InvalidArgument when malformed.
struct PartModelHeader {
  std::string target;
  std::vector<PartInputRange> ranges;
};
StatusOr<PartModelHeader> ReadPartModelHeader(const nlohmann::json& j);

// A model type: fits models of its kind and reads them back.
class PartModelType {
 public:
  virtual ~PartModelType() = default;
  virtual std::string name() const = 0;
  // Unprocessable when the records cannot determine the model (too few for
  // its size, an input that does not vary).
  virtual StatusOr<std::shared_ptr<const PartModel>> Fit(const PartTrainingSet& set,
                                                         const PartFitOptions& options) const = 0;
  virtual StatusOr<std::shared_ptr<const PartModel>> FromJson(
      const nlohmann::json& model_json) const = 0;
};

// The registered types, "quadratic" first.
const std::vector<const PartModelType*>& PartModelTypes();
const PartModelType* FindPartModelType(const std::string& name);
// A stored model rebuilt by its type.
StatusOr<std::shared_ptr<const PartModel>> PartModelFromJson(const nlohmann::json& model_json);

}  // namespace thermocomp
