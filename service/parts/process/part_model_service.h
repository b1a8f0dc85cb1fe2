// PartModelService: a machine's process records and the part-error models
// fitted on them (docs/model.md §15).
//
// Fit: the machine's records that have the target and every candidate
// input are split at random (seeded; held_out_share of them held out, and
// the held-out records never reach the ranking, the structure search or
// training). On the training part the inputs are ranked by sensitivity
// (model/parts/process_sensitivity.h) and those below 1.05 dropped; each
// requested type is fitted on the kept inputs and scored on the held-out
// records against predicting the training mean (a prediction the guard
// refuses there counts as the mean). The challenger is the type with the
// smallest held-out RMSE; it becomes active for the target only if it
// beats the mean by more than chance (paired squared errors, mean > 2
// standard errors) and does no worse than the target's active model on the
// same records. Every fitted type is stored as a version (active,
// candidate or rejected, with the reason and the report) in one
// transaction; when the ranking keeps no input nothing is fitted or stored
// and the report says so.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "core/records.h"
#include "reports/parts/part_model_report.h"
#include "service/config.h"
#include "service/parts/process/part_model.h"
#include "storage/parts/part_model_store.h"
#include "storage/storage.h"

namespace thermocomp {

// One record as received (api/parts/process_csv.h, or JSON).
struct ProcessRecordInput {
  std::string part, feature;
  int64_t cut_ms = 0;
  std::map<std::string, double> values;  // ProcessRecordFields() given
};

struct PartFitRequest {
  std::string target = "size_error_um";
  std::vector<std::string> inputs;  // candidates; empty: every input all records have
  std::vector<std::string> types;   // empty: every registered type
  double held_out_share = 0.25;
  uint64_t seed = 1;
  int neural_hidden = 3;
  int neural_restarts = 3;
};

struct PartPredictionResult {
  int version = 0;
  std::string type, target;
  PartPrediction prediction;
};

class PartModelService {
 public:
  PartModelService(Storage& storage, const Clock& clock, const Config& config);

  static constexpr size_t kMaxRecords = 100000;    // per request
  static constexpr size_t kMaxFitRecords = 20000;  // the newest, per fit
  static constexpr double kSensitivityThreshold = 1.05;
  static constexpr int kSensitivityFolds = 5;
  static constexpr double kBeatsMeanZ = 2.0;

  // The inputs and targets a record may carry.
  static const std::vector<std::string>& Inputs();
  static const std::vector<std::string>& Targets();
  // InvalidArgument with a FieldError per bad value (index = the record,
  // field = the column); NotFound for an unknown machine; Conflict for a
  // (part, feature) the machine already has. Nothing stored on any error.
  StatusOr<size_t> AddRecords(const std::string& machine,
                              const std::vector<ProcessRecordInput>& records,
                              const std::string& actor, FieldErrors* errors);
  StatusOr<std::vector<ProcessRecordRow>> Records(const std::string& machine, size_t limit);

  // InvalidArgument (errors) for a bad request; Unprocessable when the
  // records cannot support it (too few, an input that does not vary, no
  // type fitted). `stored` tells whether versions were stored.
  StatusOr<PartFitReport> Fit(const std::string& machine, const PartFitRequest& request,
                              const std::string& actor, FieldErrors* errors);
  StatusOr<std::vector<PartModelRecord>> Models(const std::string& machine);
  StatusOr<PartModelRecord> Model(const std::string& machine, int version);
  StatusOr<AuditEntry> Activate(const std::string& machine, int version, const std::string& actor);
  // InvalidArgument (errors) for an input the model does not know or a
  // value that is not finite; out of range is a result, never an error.
  StatusOr<PartPredictionResult> Predict(const std::string& machine, int version,
                                         const PartInputs& inputs, FieldErrors* errors);

 private:
  Storage& storage_;
  const Clock& clock_;
  [[maybe_unused]] const Config& config_;
};

}  // namespace thermocomp
