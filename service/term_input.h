// The probe points of an axis as effect terms see them (each point with its
// datum's time, temperatures and positions) plus the raw series the terms
// read. Built once from the archive, it serves the effect search and every
// evaluation of a stored model on past points (fit comparison, history), so
// an extended model is evaluated the same way everywhere.
#pragma once

#include <string>
#include <vector>

#include "model/drift_model.h"
#include "model/effect_search.h"
#include "model/held_out.h"
#include "service/drift_dataset.h"
#include "storage/storage.h"

namespace thermocomp {

// Which raw channels to load: all sensors and signals with the memory the
// search's longest lag needs, or only those a model's lags, rates and
// signals read, with theirs.
struct RawChannels {
  bool all = false;
  int64_t history_ms = 0;         // raw history before the first datum
  std::vector<EffectTerm> terms;  // when not all: the terms whose channels are read
  static RawChannels ForSearch(const EffectSearchOptions& options);
  static RawChannels ForModel(const DriftModel& model);
};

// `declared` become the input's declared terms.
EffectSearchInput LoadTermInput(Session& s, const MachineRecord& machine, const std::string& axis,
                                const DriftDataset& data, const std::vector<std::string>& holdout,
                                const std::vector<std::string>& declared, int64_t max_gap_ms,
                                const RawChannels& raw);

}  // namespace thermocomp
