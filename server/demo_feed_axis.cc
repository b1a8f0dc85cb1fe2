#include "server/demo_feed_axis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "sim/screw_axis.h"

namespace thermocomp {
namespace {

constexpr char kAxis[] = "X";
constexpr uint64_t kSeed = 3;
constexpr double kHours = 72;
// The cold reference first, then ten checks six and a half hours apart:
// the screw's duty (work in different strokes, pauses) puts each at
// another thermal state, warming, warm or cooling.
constexpr double kCheckHours[] = {0, 5, 11.5, 18, 24.5, 31, 37.5, 44, 50.5, 57, 63.5};

ScrewSimOptions Options() {
  ScrewSimOptions o;
  o.seed = kSeed;
  o.arrangement = BearingArrangement::kFixedFloating;
  o.length_mm = 1000;
  o.travel_min_mm = 50;
  o.travel_max_mm = 950;
  o.sensors = 5;
  o.hours = kHours;
  o.check_every_h = 1.0 / 60;  // a record every minute: the sensors' samples
  o.target_spacing_mm = 50;
  return o;
}

// The screw's own pitch error and the nut's backlash, the same in every
// check: the cold reference carries them, so the thermal error (a check
// minus the reference) does not.
double PitchErrorUm(double x_mm) {
  return 3.0 * std::sin(x_mm / 140.0) + 0.004 * x_mm;
}
constexpr double kBacklashUm = 1.2;
constexpr double kLaserNoiseUm = 0.3;

Status AddSensors(App& app, const std::string& machine, const ScrewAxis& axis) {
  MachineDefinition d;
  d.name = machine;
  for (const auto& s : axis.sensors) {
    char where[80];
    std::snprintf(where, sizeof where, "X ball screw, %.0f mm from the locating bearing", s.x_mm);
    // Unfiltered: the screw's temperatures are read as they are.
    d.sensors.push_back({0, s.name, where, 1.0});
  }
  FieldErrors errors;
  auto r = app.machines().Register(d, "demo", &errors);
  return r.ok() ? Status::Ok() : r.status();
}

// Every minute's sample of every screw sensor, a day per batch.
Status ArchiveTemperatures(App& app, const std::string& machine, const ScrewSimRecording& rec,
                           int64_t start_ms, size_t* stored) {
  std::vector<TemperatureInput> batch;
  for (size_t i = 0; i < rec.checks.size(); ++i) {
    const int64_t ts = start_ms + static_cast<int64_t>(i) * kMinuteMs;
    for (size_t k = 0; k < rec.axis.sensors.size(); ++k) {
      batch.push_back({rec.axis.sensors[k].name, ts, rec.checks[i].temperature_c[k]});
    }
    if (batch.size() >= 1440 * rec.axis.sensors.size() || i + 1 == rec.checks.size()) {
      IngestResult r = app.ingest().AddTemperatures(machine, batch, "demo");
      if (!r.status.ok()) return r.status;
      *stored += static_cast<size_t>(r.accepted);
      batch.clear();
    }
  }
  return Status::Ok();
}

// A laser check at record i: five runs each way over the targets, each
// reading pitch, backlash, the thermal error then, and the laser's noise.
PositioningInput LaserCheck(const ScrewSimRecording& rec, size_t i, int64_t ts_ms,
                            std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, kLaserNoiseUm);
  PositioningInput p;
  p.axis = kAxis;
  p.ts_ms = ts_ms;
  p.compensation_active = false;
  p.air_temperature_c = 20.0;
  double sum = 0;
  for (double t : rec.checks[i].temperature_c) sum += t;
  p.machine_temperature_c =
      std::round(sum / static_cast<double>(rec.checks[i].temperature_c.size()) * 100) / 100;
  p.note = i == 0 ? "X ball screw, cold reference" : "X ball screw, thermal state";
  p.data.targets_mm = rec.checks[i].position_mm;
  for (int run = 0; run < 10; ++run) {
    PositioningRun r{run % 2 == 0 ? 1 : -1, {}};
    for (size_t k = 0; k < p.data.targets_mm.size(); ++k) {
      r.deviations_um.push_back(PitchErrorUm(p.data.targets_mm[k]) + rec.true_error_um[i][k] +
                                r.direction * kBacklashUm / 2 + noise(rng));
    }
    p.data.runs.push_back(std::move(r));
  }
  return p;
}

// The screw as a user configures it (PUT .../axes/X/screw): the sensors
// where they sit, read at the cold reference check, and alpha as first
// guessed (the fit identifies it).
nlohmann::json ScrewConfig(const ScrewSimRecording& rec, int64_t reference_check_id) {
  nlohmann::json sensors = nlohmann::json::array();
  for (size_t k = 0; k < rec.axis.sensors.size(); ++k) {
    sensors.push_back({{"name", rec.axis.sensors[k].name},
                       {"x_mm", rec.axis.sensors[k].x_mm},
                       {"reference_c", std::round(rec.checks[0].temperature_c[k] * 100) / 100}});
  }
  return {{"arrangement", BearingArrangementName(rec.axis.arrangement)},
          {"bearing_distance_mm", rec.axis.bearing_distance_mm},
          {"zero_mm", 0.0},
          {"direction", 1},
          {"alpha_um_per_m_k", rec.axis.alpha_um_per_m_k},
          {"sensors", sensors},
          {"reference_check_id", reference_check_id}};
}

// " screw v1 active (held-out max 68.8 -> 2.4 um); neural v2 candidate (...); <decision>"
std::string FitSummary(const StatusOr<FeedFitReport>& report) {
  if (!report.ok()) return "feed-model fit: " + report.status().message();
  std::string out = "feed models:";
  for (const FeedTypeResult& t : report->types) {
    char buf[200];
    if (!t.fitted) {
      std::snprintf(buf, sizeof buf, " %s not fitted (%s);", t.type.c_str(), t.error.c_str());
    } else {
      std::snprintf(buf, sizeof buf, " %s v%d %s (held-out max %.1f -> %.1f um);", t.type.c_str(),
                    t.version, t.status.c_str(), t.held_out.max_before_um, t.held_out.max_after_um);
    }
    out += buf;
  }
  return out + " " + report->decision;
}

}  // namespace

Status DemoFeedAxis(App& app, const std::string& machine, std::string* summary) {
  auto found = app.machines().Find(machine);
  if (!found) return Status::NotFound("no machine " + machine);
  if (!found->FindAxis(kAxis)) return Status::NotFound(machine + " has no axis X");
  const ScrewSimRecording rec = SimulateScrewAxis(Options());
  // The three days end at the last whole minute: every sample is in the past.
  const int64_t end_ms = app.clock().NowMs() / kMinuteMs * kMinuteMs;
  const int64_t start_ms = end_ms - static_cast<int64_t>(kHours) * 3600000;

  if (Status s = AddSensors(app, machine, rec.axis); !s.ok()) return s;
  size_t samples = 0;
  if (Status s = ArchiveTemperatures(app, machine, rec, start_ms, &samples); !s.ok()) return s;

  std::mt19937_64 rng(kSeed);
  double largest = 0;
  int checks = 0;
  int64_t reference_id = 0;
  for (double hour : kCheckHours) {
    const auto i = static_cast<size_t>(std::lround(hour * 60));
    for (double e : rec.true_error_um[i]) largest = std::max(largest, std::fabs(e));
    const PositioningInput p =
        LaserCheck(rec, i, start_ms + static_cast<int64_t>(i) * kMinuteMs, rng);
    bool created = false;
    auto r = app.checks().AddPositioningCheck(machine, p, "demo", &created);
    if (!r.ok()) return r.status();
    if (checks++ == 0) reference_id = r->id;
  }

  FieldErrors errors;
  auto put =
      app.feed_axes().PutConfig(machine, kAxis, ScrewConfig(rec, reference_id), "demo", &errors);
  if (!put.ok()) {
    std::string why = put.status().message();
    for (const auto& e : errors) why += "; " + e.field + ": " + e.message;
    return Status::InvalidArgument("screw configuration of X: " + why);
  }
  const std::string fit = FitSummary(app.feed_fit().Fit(machine, kAxis, "demo"));

  if (summary) {
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "ball-screw axis %s/%s: %zu sensors, %zu samples over %.0f h from %s, %d "
                  "positioning checks (thermal error up to %.1f um); ",
                  machine.c_str(), kAxis, rec.axis.sensors.size(), samples, kHours,
                  FormatRfc3339(start_ms).c_str(), checks, largest);
    *summary = buf + fit;
  }
  return Status::Ok();
}

}  // namespace thermocomp
