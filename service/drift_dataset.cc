#include "service/drift_dataset.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <unordered_map>

#include "model/block_validation.h"
#include "storage/log_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

using PointTemperatures = std::unordered_map<int64_t, std::vector<double>>;

double FilteredNear(const std::optional<SampleRow>& row, int64_t ts_ms, int64_t max_gap_ms) {
  return row && ts_ms - row->ts_ms <= max_gap_ms ? row->filtered : kUnknown;
}

// The archive's temperatures at every point of `runs` the cache has not
// got, fetched per sensor for all points at once: a year of points is
// thousands of lookups, each a round trip on PostgreSQL.
PointTemperatures Prefetch(SampleStore& samples, const MachineRecord& machine,
                           const std::vector<RunRecord>& runs, int64_t max_gap_ms,
                           ProbeTemperatureCache* cache) {
  std::vector<const ProbePointRecord*> missing;
  for (const RunRecord& run : runs) {
    for (const auto& p : run.points) {
      if (!cache || !cache->Get(p.id, machine.sensors.size())) missing.push_back(&p);
    }
  }
  PointTemperatures out;
  if (missing.size() < 2) return out;  // one point: the lookups below are as cheap
  std::vector<int64_t> times;
  times.reserve(missing.size());
  for (const ProbePointRecord* p : missing) times.push_back(p->ts_ms);
  for (const ProbePointRecord* p : missing) out[p->id].reserve(machine.sensors.size());
  for (const auto& sensor : machine.sensors) {
    const auto rows = samples.AtOrBeforeEach(sensor.id, times);
    for (size_t i = 0; i < missing.size(); ++i) {
      out[missing[i]->id].push_back(FilteredNear(rows[i], missing[i]->ts_ms, max_gap_ms));
    }
  }
  return out;
}

// Filtered temperature of every sensor at the point: its snapshot where it
// has one, else the archive's filtered value (cached), else NaN.
std::vector<double> TemperaturesAt(SampleStore& samples, const MachineRecord& machine,
                                   const ProbePointRecord& p, int64_t max_gap_ms,
                                   ProbeTemperatureCache* cache,
                                   const PointTemperatures& prefetched) {
  std::optional<std::vector<double>> archive;
  if (cache) archive = cache->Get(p.id, machine.sensors.size());
  if (!archive) {
    if (auto it = prefetched.find(p.id); it != prefetched.end()) {
      archive = it->second;
      if (cache) cache->Put(machine.id, p.id, p.ts_ms, *archive);
    }
  }
  if (!archive) {
    archive.emplace();
    for (const auto& sensor : machine.sensors) {
      archive->push_back(FilteredNear(samples.AtOrBefore(sensor.id, p.ts_ms), p.ts_ms, max_gap_ms));
    }
    if (cache) cache->Put(machine.id, p.id, p.ts_ms, *archive);
  }
  for (size_t j = 0; j < machine.sensors.size(); ++j) {
    if (auto it = p.temperatures.find(machine.sensors[j].name); it != p.temperatures.end()) {
      (*archive)[j] = it->second;
    }
  }
  return *archive;
}

}  // namespace

std::optional<CompensationLogRow> ServedAt(LogStore& log, int64_t axis_id, int64_t ts_ms) {
  auto row = log.CompensationAt(axis_id, ts_ms);
  if (!row || ts_ms - row->ts_ms > kServedMaxAgeMs || !std::isfinite(row->offset_mm)) {
    return std::nullopt;
  }
  return row;
}

std::optional<double> RawDeviation(LogStore& log, int64_t axis_id, int64_t ts_ms,
                                   double measured_mm, bool compensated) {
  if (!compensated) return measured_mm;
  auto served = ServedAt(log, axis_id, ts_ms);
  if (!served) return std::nullopt;
  return measured_mm - served->offset_mm;
}

DriftDataset BuildDriftDataset(Session& s, const MachineRecord& machine, const std::string& axis,
                               double gross_error_mm, int64_t max_gap_ms,
                               ProbeTemperatureCache* cache, bool other_axes) {
  DriftDataset d;
  for (const auto& s : machine.sensors) d.sensors.push_back(s.name);
  for (const auto& a : machine.axes) d.axes.push_back(a.name);
  // Every axis the probe points carry a position of, beyond the machine's
  // own: a Y error may grow with X, or with Z where Z is not compensated.
  const std::vector<RunRecord> runs = s.probes().LoadAxisRuns(machine.id, axis, other_axes);
  std::set<std::string> probed;
  for (const RunRecord& run : runs) {
    for (const auto& p : run.points) {
      for (const auto& [name, value] : p.axes) {
        if (value.position_mm) probed.insert(name);
      }
    }
  }
  for (const auto& name : probed) {
    if (std::find(d.axes.begin(), d.axes.end(), name) == d.axes.end()) d.axes.push_back(name);
  }
  auto positions = [&](const ProbePointRecord& p) {
    std::vector<double> v;
    for (const auto& a : d.axes) {
      auto it = p.axes.find(a);
      v.push_back(it != p.axes.end() && it->second.position_mm ? *it->second.position_mm
                                                               : kUnknown);
    }
    return v;
  };
  SampleStore& samples = s.samples();
  LogStore& log = s.log();
  const AxisRecord* axis_record = machine.FindAxis(axis);
  const int64_t axis_id = axis_record ? axis_record->id : 0;
  auto raw = [&](const ProbePointRecord& p, double measured) {
    return RawDeviation(log, axis_id, p.ts_ms, measured, p.compensated);
  };
  const PointTemperatures prefetched = Prefetch(samples, machine, runs, max_gap_ms, cache);
  auto count_points = [&](const RunRecord& run, int& counter) {
    for (const auto& p : run.points) {
      if (p.k > 0 && p.axes.count(axis)) ++counter;
    }
  };
  for (const RunRecord& run : runs) {
    const ProbePointRecord* datum = nullptr;
    for (const auto& p : run.points) {
      if (p.k == 0) datum = &p;
    }
    auto datum_axis =
        datum ? datum->axes.find(axis) : std::map<std::string, AxisValue>::const_iterator{};
    if (!datum || datum_axis == datum->axes.end() || !datum_axis->second.deviation_mm) {
      count_points(run, d.skipped_no_datum);
      continue;
    }
    const double datum_measured = *datum_axis->second.deviation_mm;
    const std::optional<double> datum_raw = raw(*datum, datum_measured);
    if (!datum_raw) {  // nothing of the run can be made raw
      count_points(run, d.skipped_unserved);
      continue;
    }
    const std::vector<double> t0 =
        TemperaturesAt(samples, machine, *datum, max_gap_ms, cache, prefetched);
    const int run_index = static_cast<int>(d.runs.size());
    bool used = false;
    for (const auto& p : run.points) {
      auto it = p.axes.find(axis);
      if (p.k == 0 || it == p.axes.end() || !it->second.deviation_mm) continue;
      const std::optional<double> point_raw = raw(p, *it->second.deviation_mm);
      if (!point_raw) {
        ++d.skipped_unserved;
        continue;
      }
      DriftRow row;
      row.run = run_index;
      row.k = p.k;
      row.ts_ms = p.ts_ms;
      row.drift_mm = *point_raw - *datum_raw;
      row.probed_mm = *it->second.deviation_mm - datum_measured;
      row.compensated = p.compensated;
      if (std::fabs(row.drift_mm) >= gross_error_mm) {
        ++d.skipped_gross;
        continue;
      }
      const std::vector<double> t =
          TemperaturesAt(samples, machine, p, max_gap_ms, cache, prefetched);
      row.datum_ts_ms = datum->ts_ms;
      row.temperature = t;
      row.datum_temperature = t0;
      row.position_mm = positions(p);
      row.datum_position_mm = positions(*datum);
      d.rows.push_back(std::move(row));
      used = true;
    }
    if (used) d.runs.push_back(run.name);
  }
  return d;
}

StatusOr<std::vector<std::string>> ChooseHoldout(
    const DriftDataset& data, const std::optional<std::vector<std::string>>& requested, int count) {
  std::vector<std::string> holdout;
  if (requested) {
    for (const auto& r : *requested) {
      if (std::find(data.runs.begin(), data.runs.end(), r) == data.runs.end()) {
        return Status::Unprocessable("holdout_runs: run '" + r + "' has no usable points");
      }
    }
    return *requested;
  }
  const int runs = static_cast<int>(data.runs.size());
  const int h = std::max(std::min(count, runs - 2), 0);
  for (int i = runs - h; i < runs; ++i) holdout.push_back(data.runs[i]);
  return holdout;
}

StatusOr<std::vector<std::string>> ChooseHoldoutByExtent(
    const DriftDataset& data, const std::optional<std::vector<std::string>>& requested,
    int min_points, double min_days) {
  if (requested) return ChooseHoldout(data, requested, 0);
  std::vector<int> run;
  std::vector<int64_t> ts;
  for (const auto& r : data.rows) {
    run.push_back(r.run);
    ts.push_back(r.ts_ms);
  }
  const std::vector<bool> held = NewestRunsHeldOut(run, ts, min_points, min_days);
  std::set<int> runs;
  for (size_t i = 0; i < held.size(); ++i) {
    if (held[i]) runs.insert(run[i]);
  }
  std::vector<std::string> out;
  out.reserve(runs.size());
  for (int r : runs) out.push_back(data.runs[r]);
  return out;
}

std::vector<int> DriftDataset::RowsOfRuns(const std::vector<std::string>& names,
                                          bool invert) const {
  std::vector<int> out;
  for (size_t i = 0; i < rows.size(); ++i) {
    bool in = std::find(names.begin(), names.end(), runs[rows[i].run]) != names.end();
    if (in != invert) out.push_back(static_cast<int>(i));
  }
  return out;
}

Observations DriftDataset::ToObservations(const std::vector<int>& row_ids,
                                          const std::vector<std::string>& columns) const {
  std::vector<int> cols;
  cols.reserve(columns.size());
  for (const auto& c : columns) {
    cols.push_back(
        static_cast<int>(std::find(sensors.begin(), sensors.end(), c) - sensors.begin()));
  }
  std::vector<int> usable;
  for (int r : row_ids) {
    bool ok = true;
    for (int c : cols)
      ok = ok && c < static_cast<int>(sensors.size()) &&
           std::isfinite(rows[r].temperature[c] - rows[r].datum_temperature[c]);
    if (ok) usable.push_back(r);
  }
  Observations obs;
  obs.names = columns;
  obs.x.resize(usable.size(), cols.size());
  obs.y.resize(usable.size());
  for (size_t i = 0; i < usable.size(); ++i) {
    const DriftRow& row = rows[usable[i]];
    obs.y(i) = row.drift_mm;
    for (size_t j = 0; j < cols.size(); ++j) {
      obs.x(i, j) = row.temperature[cols[j]] - row.datum_temperature[cols[j]];
    }
    obs.group.push_back(row.run);
    obs.source.push_back(usable[i]);
  }
  return obs;
}

}  // namespace thermocomp
