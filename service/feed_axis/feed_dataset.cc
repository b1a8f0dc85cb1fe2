#include "service/feed_axis/feed_dataset.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include <nlohmann/json.hpp>

#include "model/positioning_check.h"
#include "reports/check_codec.h"

namespace thermocomp {
namespace {

constexpr double kStuckSpreadK = 0.01;  // a sensor that moves less is stuck...
constexpr double kWarmSpreadK = 1.0;    // ...while another moves more than this
constexpr double kTargetToleranceMm = 1e-6;

struct Candidate {
  int64_t id = 0, ts_ms = 0;
  bool compensation_active = false;
  std::vector<double> targets_mm, mean_um;
  std::map<std::string, double> temperature_c;
};

std::string Fixed(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

bool SameTargets(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::fabs(a[i] - b[i]) > kTargetToleranceMm) return false;
  }
  return true;
}

}  // namespace

StatusOr<FeedDataset> BuildFeedDataset(Session& session, const MachineRecord& machine,
                                       const std::string& axis_name, const FeedDatasetSpec& spec,
                                       const FeedDatasetOptions& options) {
  FeedDataset out;
  // Every sensor the configuration names, screw sensors first.
  struct Sensor {
    std::string name;
    bool screw = true;
    const SensorRecord* record = nullptr;
  };
  std::vector<Sensor> sensors;
  for (const ScrewSensor& s : spec.axis.sensors) {
    sensors.push_back({s.name, true, machine.FindSensor(s.name)});
  }
  for (const std::string& b : spec.body_sensors) {
    sensors.push_back({b, false, machine.FindSensor(b)});
  }

  // The axis' checks, read and evaluated.
  std::vector<Candidate> all;
  SampleStore& samples = session.samples();
  for (const PositioningCheckRecord& rec : session.checks().PositioningChecks(machine.id)) {
    if (rec.axis != axis_name) continue;
    Candidate c;
    c.id = rec.id;
    c.ts_ms = rec.ts_ms;
    FieldErrors errors;
    std::optional<PositioningInput> input;
    try {
      input = PositioningFromJson(nlohmann::json::parse(rec.input_json), errors);
    } catch (const nlohmann::json::exception&) {
    }
    auto evaluation = input ? EvaluatePositioning(input->data, input->uncertainty)
                            : StatusOr<PositioningEvaluation>(Status::Internal("unreadable"));
    if (!evaluation.ok()) {
      out.skipped.push_back({rec.id, "the stored check is unreadable"});
      continue;
    }
    c.compensation_active = input->compensation_active;
    for (const PositionStats& p : evaluation->iso.positions) {
      c.targets_mm.push_back(p.target_mm);
      c.mean_um.push_back(p.mean_um);
    }
    for (const Sensor& s : sensors) {
      if (!s.record) continue;
      auto row = samples.AtOrBefore(s.record->id, c.ts_ms);
      if (row && c.ts_ms - row->ts_ms <= options.stale_after_ms && std::isfinite(row->filtered)) {
        c.temperature_c[s.name] = row->filtered;
      }
    }
    all.push_back(std::move(c));
  }

  // The cold reference.
  const Candidate* reference = nullptr;
  if (spec.reference_check_id) {
    for (const Candidate& c : all) {
      if (c.id == *spec.reference_check_id) reference = &c;
    }
    if (!reference) {
      return Status::NotFound("reference_check_id: " + std::to_string(*spec.reference_check_id) +
                              " is not a positioning check of axis " + axis_name);
    }
  } else {
    for (const Candidate& c : all) {
      if (!c.compensation_active) {
        reference = &c;
        break;
      }
    }
    if (!reference) {
      return Status::Unprocessable("no positioning check of axis " + axis_name +
                                   " taken with compensation off to be the cold reference");
    }
  }
  out.reference_check_id = reference->id;

  // The checks that can be compared with it.
  std::vector<const Candidate*> used;
  for (const Candidate& c : all) {
    if (&c == reference) continue;
    if (c.compensation_active) {
      out.skipped.push_back({c.id, "taken with compensation active"});
    } else if (!SameTargets(c.targets_mm, reference->targets_mm)) {
      out.skipped.push_back({c.id, "its targets differ from the reference check's"});
    } else {
      used.push_back(&c);
    }
  }

  // Sensors judged over those checks.
  double warmest_spread = 0;
  auto spread = [&](const std::string& name, double* lo, double* hi, int* present) {
    *lo = std::numeric_limits<double>::infinity();
    *hi = -std::numeric_limits<double>::infinity();
    *present = 0;
    for (const Candidate* c : used) {
      auto it = c->temperature_c.find(name);
      if (it == c->temperature_c.end()) continue;
      ++*present;
      *lo = std::min(*lo, it->second);
      *hi = std::max(*hi, it->second);
    }
  };
  for (const Sensor& s : sensors) {
    double lo, hi;
    int present;
    spread(s.name, &lo, &hi, &present);
    if (s.screw && present > 0) warmest_spread = std::max(warmest_spread, hi - lo);
  }
  std::vector<std::string> kept, dropped_with_values;
  for (const Sensor& s : sensors) {
    double lo, hi;
    int present;
    spread(s.name, &lo, &hi, &present);
    std::string why;
    bool has_values = false;
    if (!s.record) {
      why = "not a sensor of the machine";
    } else if (used.empty()) {
      // Nothing to judge the sensor by; the refit refuses too few checks.
    } else if (present == 0) {
      why = "no data at the checks";
    } else if (2 * present < static_cast<int>(used.size())) {
      why = "no data at " + std::to_string(used.size() - present) + " of " +
            std::to_string(used.size()) + " checks";
    } else if (lo < options.plausible_min_c || hi > options.plausible_max_c) {
      why = "out of range: " + Fixed(lo < options.plausible_min_c ? lo : hi) + " degC at a check";
      has_values = present == static_cast<int>(used.size());
    } else if (used.size() >= 2 && hi - lo <= kStuckSpreadK && warmest_spread > kWarmSpreadK) {
      why = "stuck at " + Fixed(lo) + " degC while the screw warmed by " + Fixed(warmest_spread) +
            " K";
      has_values = present == static_cast<int>(used.size());
    }
    if (why.empty()) {
      kept.push_back(s.name);
    } else {
      out.dropped.push_back({s.name, s.screw, why});
      if (s.screw && has_values) dropped_with_values.push_back(s.name);
    }
  }
  auto is_kept = [&](const std::string& n) {
    return std::find(kept.begin(), kept.end(), n) != kept.end();
  };

  // The axis as fitted: the kept screw sensors, referenced to the
  // reference check's temperatures.
  auto with_sensors = [&](auto keep) {
    ScrewAxis a = spec.axis;
    a.sensors.clear();
    for (ScrewSensor s : spec.axis.sensors) {
      if (!keep(s.name)) continue;
      if (auto it = reference->temperature_c.find(s.name); it != reference->temperature_c.end()) {
        s.reference_c = it->second;
      }
      a.sensors.push_back(s);
    }
    return a;
  };
  out.axis = with_sensors(is_kept);
  if (out.axis.sensors.empty()) {
    return Status::Unprocessable(
        "no screw sensor of axis " + axis_name + " has data at its checks: " +
        (out.dropped.empty() ? std::string("none configured")
                             : out.dropped.front().name + " " + out.dropped.front().why));
  }
  for (const std::string& b : spec.body_sensors) {
    if (is_kept(b)) out.body_sensors.push_back(b);
  }
  if (!dropped_with_values.empty() &&
      dropped_with_values.size() ==
          static_cast<size_t>(std::count_if(out.dropped.begin(), out.dropped.end(),
                                            [](const FeedDroppedSensor& d) { return d.screw; }))) {
    out.axis_with_dropped = with_sensors([&](const std::string& n) {
      return is_kept(n) || std::find(dropped_with_values.begin(), dropped_with_values.end(), n) !=
                               dropped_with_values.end();
    });
  }

  for (const Candidate* c : used) {
    std::string missing;
    for (const std::string& n : kept) {
      if (!c->temperature_c.count(n)) {
        missing = n;
        break;
      }
    }
    if (!missing.empty()) {
      out.skipped.push_back({c->id, "no temperature of sensor " + missing + " within " +
                                        std::to_string(options.stale_after_ms / 1000) +
                                        " s before it"});
      continue;
    }
    FeedCheck f;
    f.check_id = c->id;
    f.ts_ms = c->ts_ms;
    f.position_mm = c->targets_mm;
    for (size_t i = 0; i < c->mean_um.size(); ++i) {
      f.error_um.push_back(c->mean_um[i] - reference->mean_um[i]);
    }
    f.temperature_c = c->temperature_c;
    out.checks.push_back(std::move(f));
  }
  std::stable_sort(out.checks.begin(), out.checks.end(),
                   [](const FeedCheck& a, const FeedCheck& b) { return a.ts_ms < b.ts_ms; });
  return out;
}

}  // namespace thermocomp
