// Live evaluation of a model's terms: each term's value now relative to the
// current run's datum, computed with the same FeatureBuilder as in the fit,
// from a window of the raw archive long enough for its lags (10 tau).
#pragma once

#include <string>
#include <vector>

#include "core/records.h"
#include "model/drift_model.h"
#include "storage/storage.h"

namespace thermocomp {

struct LiveContext {
  const MachineRecord* machine = nullptr;
  std::string axis;  // the axis served; positions vary along it
  int64_t now_ms = 0;
  int64_t datum_ts_ms = 0;
  std::vector<double> temperature;        // filtered now, per machine sensor; NaN unknown
  std::vector<double> datum_temperature;  // filtered at the datum, per machine sensor
  // Per machine axis, then per axis of `probe_axes`; NaN unknown.
  std::vector<double> datum_position_mm;
  // Axes a term reads that the machine does not compensate (a Y error
  // growing with Z): evaluated where the datum was probed, reference 0.
  std::vector<std::string> probe_axes;
  int64_t max_gap_ms = 5 * 60000;
};

// For each position of `axis`, the model's term values (aligned with
// model.inputs); NaN where an input is missing.
std::vector<std::vector<double>> LiveTermValues(Session& s, const DriftModel& model,
                                                const LiveContext& context,
                                                const std::vector<double>& positions_mm);

// The axes the model's terms read that are not the machine's.
std::vector<std::string> AxesBeyondMachine(const DriftModel& model, const MachineRecord& machine);

// Whether any term reads the position of an axis other than `axis`.
bool ReadsOtherAxes(const DriftModel& model, const std::string& axis);

// Whether any term depends on the position of `axis`.
bool DependsOnPosition(const DriftModel& model, const std::string& axis);

}  // namespace thermocomp
