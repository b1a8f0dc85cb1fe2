#include "service/feed_axis/thermal_error_table.h"

#include <algorithm>
#include <cmath>

#include "core/time_format.h"
#include "reports/check_codec.h"
#include "service/compensation_service.h"
#include "service/feed_axis/feed_axis_config.h"
#include "service/feed_axis/feed_model.h"
#include "storage/feed_model_store.h"

namespace thermocomp {
namespace {

// Without a configured travel (AxisRecord) the table covers the screw,
// from its locating bearing to the other one.
Travel TravelOf(const AxisRecord& axis, const ScrewAxis* screw) {
  if (axis.travel_min_mm && axis.travel_max_mm) return {*axis.travel_min_mm, *axis.travel_max_mm};
  if (screw && screw->bearing_distance_mm > 0) {
    const double a = screw->zero_mm,
                 b = screw->zero_mm + screw->direction * screw->bearing_distance_mm;
    return {std::min(a, b), std::max(a, b)};
  }
  return {axis.reference_position_mm - 1000.0, axis.reference_position_mm + 1000.0};
}

constexpr double kDefaultSpacingMm = 10.0;

size_t SpacedCount(const Travel& t, double spacing_mm) {
  return static_cast<size_t>(std::floor((t.max_mm - t.min_mm) / spacing_mm + 1e-9)) + 2;
}

// Linear between the grid's points, held beyond its ends.
double Interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  if (x.empty()) return 0;
  if (at <= x.front()) return y.front();
  if (at >= x.back()) return y.back();
  const size_t i = static_cast<size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  const double f = (at - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + f * (y[i] - y[i - 1]);
}

double Toward(double from, double to, double step) {
  return std::fabs(to - from) <= step ? to : from + std::copysign(step, to - from);
}

// The least-squares line of `value_um` over `position_mm` about `ref`, as
// a CorrectionLine (offset in mm).
CorrectionLine FitLine(const std::vector<double>& position_mm, const std::vector<double>& value_um,
                       double ref) {
  const double n = static_cast<double>(position_mm.size());
  if (position_mm.empty()) return {};
  double mx = 0, my = 0;
  for (size_t i = 0; i < position_mm.size(); ++i) {
    mx += position_mm[i] - ref;
    my += value_um[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < position_mm.size(); ++i) {
    const double dx = position_mm[i] - ref - mx;
    sxx += dx * dx;
    sxy += dx * (value_um[i] - my);
  }
  const double b = sxx > 0 ? sxy / sxx : 0.0;  // um per mm
  return {(my - b * mx) * 1e-3, b * 1e3};
}

std::string NoActiveModel(const std::vector<FeedModelRecord>& versions) {
  if (versions.empty()) return "no active feed model: none fitted yet";
  const FeedModelRecord& v = versions.front();
  return "no active feed model: v" + std::to_string(v.version) + " (" + v.type + ") is " +
         v.status + (v.reason.empty() ? "" : " (" + v.reason + ")");
}

// The targets of the reference check: the configured one, else the axis'
// oldest check taken with compensation off.
std::vector<double> ReferenceTargets(Session& session, int64_t machine_id, const std::string& axis,
                                     std::optional<int64_t> reference_check_id) {
  for (const PositioningCheckRecord& r : session.checks().PositioningChecks(machine_id)) {
    if (r.axis != axis || (reference_check_id && r.id != *reference_check_id)) continue;
    FieldErrors errors;
    auto in = PositioningFromJson(nlohmann::json::parse(r.input_json, nullptr, false), errors);
    if (!in || (!reference_check_id && in->compensation_active)) continue;
    return in->data.targets_mm;
  }
  return {};
}

}  // namespace

int ThermalErrorTable::StatusWord() const {
  return (valid ? kStatusValid : 0) | (stale ? kStatusStale : 0) | (clamped ? kStatusClamped : 0) |
         (state == ServedState::kHolding ? kStatusHolding : 0) |
         (state == ServedState::kRamping ? kStatusRamping : 0);
}

ThermalErrorTableService::ThermalErrorTableService(Storage& storage, const Clock& clock,
                                                   const Config& config)
    : storage_(storage), clock_(clock), config_(config) {}

int64_t ThermalErrorTableService::ArrivalOf(const std::string& key, int64_t last_ts_ms,
                                            int64_t now_mono_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto [ts, first] = arrival_ts_.try_emplace(key, last_ts_ms);
  if (first || ts->second != last_ts_ms) {
    ts->second = last_ts_ms;
    arrival_mono_[key] = now_mono_ms;
  }
  return arrival_mono_[key];
}

std::vector<double> ThermalErrorTableService::SpacedGrid(const Travel& t, double spacing_mm) {
  std::vector<double> out;
  const double span = t.max_mm - t.min_mm;
  const auto steps = static_cast<size_t>(std::floor(span / spacing_mm + 1e-9));
  for (size_t i = 0; i <= steps; ++i) out.push_back(t.min_mm + static_cast<double>(i) * spacing_mm);
  if (out.back() < t.max_mm - 1e-9) out.push_back(t.max_mm);
  return out;
}

StatusOr<ThermalErrorTableService::AxisModel> ThermalErrorTableService::Load(
    Session& session, const std::string& machine, const std::string& axis) {
  AxisModel m;
  m.machine = session.machines().Find(machine);
  if (!m.machine) return Status::NotFound("unknown machine '" + machine + "'");
  m.axis = m.machine->FindAxis(axis);
  if (!m.axis) return Status::NotFound("machine '" + machine + "' has no axis " + axis);
  FeedModelStore& feeds = session.feeds();
  auto record = feeds.Config(m.axis->id);
  if (record) {
    FieldErrors errors;
    auto config =
        FeedAxisConfigFromJson(nlohmann::json::parse(record->config_json, nullptr, false), &errors);
    if (config.ok()) {
      m.config = std::make_shared<const FeedAxisConfig>(std::move(config).value());
    } else {
      m.reason = "the screw configuration cannot be read" +
                 (errors.empty() ? "" : ": " + errors[0].field + " " + errors[0].message);
    }
  } else {
    m.reason = "no screw configuration (PUT .../axes/" + axis + "/screw)";
  }
  m.travel = TravelOf(*m.axis, m.config ? &m.config->screw : nullptr);
  if (!m.config) return m;
  m.sensors = m.config->SensorNames();
  auto active = feeds.Active(m.axis->id);
  if (!active) {
    m.reason = NoActiveModel(feeds.List(m.axis->id));
    return m;
  }
  m.version = active->version;
  m.type = active->type;
  const FeedModelType* type = FindFeedModelType(active->type);
  if (!type) {
    m.reason = "active feed model v" + std::to_string(active->version) + " has unknown type '" +
               active->type + "'";
    return m;
  }
  // The physical model answers where another type must not (its guard):
  // the newest screw-type version that was not rejected.
  std::shared_ptr<const FeedModel> fallback;
  if (active->type != "screw") {
    for (const FeedModelRecord& r : feeds.List(m.axis->id)) {
      if (r.type != "screw" || r.status == "rejected") continue;
      auto fb = FindFeedModelType("screw")->FromJson(
          m.config->screw, nlohmann::json::parse(r.model_json, nullptr, false), nullptr);
      if (fb.ok()) fallback = *fb;
      break;
    }
  }
  auto model = type->FromJson(m.config->screw,
                              nlohmann::json::parse(active->model_json, nullptr, false), fallback);
  if (!model.ok()) {
    m.reason = "active feed model v" + std::to_string(active->version) +
               " cannot be read: " + model.status().message();
    return m;
  }
  m.model = *model;
  return m;
}

StatusOr<ThermalErrorTable> ThermalErrorTableService::Table(const std::string& machine,
                                                            const std::string& axis,
                                                            std::optional<double> spacing_mm) {
  if (spacing_mm && !(*spacing_mm >= kMinSpacingMm && *spacing_mm <= kMaxSpacingMm)) {
    return Status::InvalidArgument("spacing_mm: must be from 1 to 1000 mm");
  }
  const std::unique_ptr<Session> session = storage_.Open();
  auto loaded = Load(*session, machine, axis);
  if (!loaded.ok()) return loaded.status();
  AxisModel& m = *loaded;
  ThermalErrorTable t;
  t.machine = machine;
  t.axis = axis;
  t.computed_at_ms = clock_.NowMs();
  t.model_version = m.version;
  t.model_type = m.type;
  t.travel = m.travel;
  t.reference_position_mm = m.axis->reference_position_mm;
  t.clamp_mm = m.axis->clamp_mm;
  t.reason = m.reason;
  const int64_t now_mono = clock_.MonotonicMs();

  // The axis' own grid (what the rate limit follows) and the one asked for.
  std::vector<double> own;
  std::string own_kind = "default";
  double own_spacing = kDefaultSpacingMm;
  if (m.config && m.config->table_spacing_mm) {
    own_kind = "spacing";
    own_spacing = std::max(*m.config->table_spacing_mm,
                           (t.travel.max_mm - t.travel.min_mm) / double(kMaxPoints - 2));
  } else if (m.config) {
    for (double p : ReferenceTargets(*session, m.machine->id, axis, m.config->reference_check_id)) {
      if (p >= t.travel.min_mm && p <= t.travel.max_mm) own.push_back(p);
    }
    if (!own.empty()) {
      own_kind = "reference_check";
      own_spacing = 0;
      own.push_back(t.travel.min_mm);
      own.push_back(t.travel.max_mm);
      std::sort(own.begin(), own.end());
      own.erase(std::unique(own.begin(), own.end()), own.end());
    }
  }
  if (own.empty()) {
    own_spacing =
        std::max(own_spacing, (t.travel.max_mm - t.travel.min_mm) / double(kMaxPoints - 2));
    own = SpacedGrid(t.travel, own_spacing);
  }
  std::vector<double> grid = own;
  t.grid = own_kind;
  t.spacing_mm = own_spacing;
  if (spacing_mm) {
    if (SpacedCount(t.travel, *spacing_mm) > kMaxPoints) {
      return Status::InvalidArgument("spacing_mm: gives more than 10000 points over the travel");
    }
    grid = SpacedGrid(t.travel, *spacing_mm);
    t.grid = "spacing";
    t.spacing_mm = *spacing_mm;
  }

  // The sensors: latest filtered values, fresh and plausible ones used.
  FeedTemperatures temperatures;
  std::vector<std::string> unusable;  // "S: why"
  const int64_t stale_ms = int64_t{config_.stale_after_s} * 1000;
  std::optional<int64_t> oldest_ts, oldest_arrival;
  bool any_stale = false;
  for (const std::string& name : m.sensors) {
    ThermalErrorSensor s;
    s.name = name;
    const SensorRecord* rec = m.machine->FindSensor(name);
    std::optional<FilterState> fs =
        rec ? session->samples().LoadFilterState(rec->id) : std::nullopt;
    if (!fs) {
      unusable.push_back("no samples from sensor " + name);
      t.sensors.push_back(s);
      continue;
    }
    s.temperature_c = fs->state;
    s.ts_ms = fs->last_ts_ms;
    const int64_t arrived =
        ArrivalOf(std::string(machine).append("/").append(name), fs->last_ts_ms, now_mono);
    oldest_ts = std::min(oldest_ts.value_or(fs->last_ts_ms), fs->last_ts_ms);
    oldest_arrival = std::min(oldest_arrival.value_or(arrived), arrived);
    const int64_t by_ts = t.computed_at_ms - fs->last_ts_ms, by_arrival = now_mono - arrived;
    if (by_ts > stale_ms || by_arrival > stale_ms) {
      s.stale = any_stale = true;
      unusable.push_back(by_ts > stale_ms ? "no temperature of " + name + " since " +
                                                FormatRfc3339(fs->last_ts_ms)
                                          : "no sample of " + name + " received for " +
                                                std::to_string(by_arrival / 1000) + " s");
    } else if (fs->last_value < config_.plausible_min_c ||
               fs->last_value > config_.plausible_max_c || !std::isfinite(fs->state)) {
      unusable.push_back("sensor " + name + " implausible: raw value outside plausible range");
    } else if (std::fabs(fs->last_value - fs->state) > config_.max_step_c) {
      unusable.push_back("sensor " + name +
                         " implausible: raw value jumps away from filtered value");
    } else {
      temperatures[name] = fs->state;
    }
    t.sensors.push_back(s);
  }
  if (oldest_ts) {
    const int64_t age = std::max<int64_t>(
        {t.computed_at_ms - *oldest_ts, now_mono - oldest_arrival.value_or(now_mono), 0});
    t.input_age_s = static_cast<double>(age) / 1000.0;
  }

  // The model's values on both grids, from the usable sensors only: a
  // model that does not need a failed sensor still answers.
  auto evaluate = [&](const std::vector<double>& at, std::vector<FeedPrediction>& out) {
    out.assign(at.size(), FeedPrediction{0, false, t.reason, ""});
    if (!m.model) return;
    out = m.model->Predict(temperatures, at);
    if (out.size() != at.size()) out.assign(at.size(), {0, false, "model gave no values", ""});
    for (FeedPrediction& p : out) {
      if (!std::isfinite(p.error_um)) p = {0, false, "prediction is not finite", ""};
    }
  };
  std::vector<FeedPrediction> own_pred, pred;
  evaluate(own, own_pred);
  if (spacing_mm) evaluate(grid, pred);
  const std::vector<FeedPrediction>& shown = spacing_mm ? pred : own_pred;
  bool valid = static_cast<bool>(m.model);
  for (const auto* preds : {&own_pred, &pred}) {
    for (const FeedPrediction& p : *preds) {
      if (!p.valid && valid) {
        valid = false;
        if (t.reason.empty()) t.reason = p.reason.empty() ? "model not valid here" : p.reason;
      }
      if (p.valid && !p.fallback.empty() && t.fallback.empty()) {
        t.fallback = p.fallback;
        if (t.reason.empty()) t.reason = p.reason;
      }
    }
  }
  if (!valid && m.model && !unusable.empty()) {
    t.reason = unusable.front();  // the cause, rather than what it did to the model
    t.stale = any_stale;
  }

  // The targets, within the clamp in force now.
  const double clamp_um = std::fabs(t.clamp_mm) * 1000.0;
  auto targets = [&](const std::vector<FeedPrediction>& p) {
    std::vector<double> c(p.size(), 0.0);
    for (size_t i = 0; i < p.size(); ++i) {
      if (!valid) continue;
      c[i] = std::clamp(-p[i].error_um, -clamp_um, clamp_um);
      if (c[i] != -p[i].error_um) t.clamped = true;
    }
    return c;
  };
  const std::vector<double> own_target = targets(own_pred);
  const std::vector<double> shown_target = spacing_mm ? targets(pred) : own_target;
  CorrectionLine line = FitLine(own, own_target, t.reference_position_mm);
  if (valid && ClampOverTravel(line, t.reference_position_mm, t.travel, t.clamp_mm)) {
    t.clamped = true;
  }

  const Serving s = ServeGrid(machine + "/" + axis, own, own_target, line, valid,
                              t.reference_position_mm, t.travel, clamp_um, now_mono);
  t.valid = valid;
  t.state = s.state;
  t.clamped = valid && (t.clamped || s.clamped);
  t.points.resize(grid.size());
  std::vector<double> lag(own.size());
  for (size_t i = 0; i < own.size(); ++i) lag[i] = s.correction_um[i] - own_target[i];
  for (size_t i = 0; i < grid.size(); ++i) {
    ThermalErrorPoint& p = t.points[i];
    p.position_mm = grid[i];
    p.valid = valid && shown[i].valid;
    p.error_um = shown[i].valid ? shown[i].error_um : 0.0;
    // On the axis' own grid what is served; elsewhere the model's value
    // plus the lag interpolated from it (or what is held, when not valid).
    double c = !spacing_mm ? s.correction_um[i]
               : valid     ? shown_target[i] + Interpolate(own, lag, grid[i])
                           : Interpolate(own, s.correction_um, grid[i]);
    // + 0.0: no correction reads 0, not -0 (the negated error of 0), in
    // every format a control parses.
    p.correction_um = std::clamp(c, -clamp_um, clamp_um) + 0.0;
    if (p.valid) t.max_abs_error_um = std::max(t.max_abs_error_um, std::fabs(p.error_um));
  }
  t.line.reference_position_mm = t.reference_position_mm;
  t.line.offset_um = s.line.offset_mm * 1000.0;
  t.line.slope_um_per_m = s.line.slope_um_per_m;
  double sum2 = 0;
  for (const ThermalErrorPoint& p : t.points) {
    const double r = p.correction_um - s.line.At(t.reference_position_mm, p.position_mm) * 1000.0;
    t.line.max_residual_um = std::max(t.line.max_residual_um, std::fabs(r));
    sum2 += r * r;
  }
  if (!t.points.empty()) t.line.rms_residual_um = std::sqrt(sum2 / double(t.points.size()));
  if (m.config && m.model) {
    std::vector<double> screw_c;
    for (const auto& sensor : m.config->screw.sensors) {
      auto it = temperatures.find(sensor.name);
      if (it == temperatures.end()) break;
      screw_c.push_back(it->second);
    }
    if (screw_c.size() == m.config->screw.sensors.size()) {
      if (auto rise = ScrewRise(m.config->screw, screw_c); rise.ok()) {
        const double bound = ScrewInterpolationBoundUm(m.config->screw, *rise);
        if (std::isfinite(bound)) t.interpolation_bound_um = bound;
      }
    }
  }
  if (t.valid && t.fallback.empty()) t.reason.clear();
  return t;
}

ThermalErrorTableService::Serving ThermalErrorTableService::ServeGrid(
    const std::string& key, const std::vector<double>& position_mm,
    const std::vector<double>& target_um, const CorrectionLine& target_line, bool valid,
    double reference_mm, const Travel& travel, double clamp_um, int64_t now_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  // An axis first served (after a start) begins at the model's value: the
  // control's own limiter (docs/controls.md) covers what it kept.
  auto [it, first] = rated_.try_emplace(key);
  Rated& r = it->second;
  if (first) {
    r.position_mm = position_mm;
    r.correction_um = valid ? target_um : std::vector<double>(position_mm.size(), 0.0);
    r.line = valid ? target_line : CorrectionLine{};
    r.at_ms = now_ms;
  }
  if (r.position_mm != position_mm) {  // the axis' grid changed: carry the values over
    std::vector<double> moved(position_mm.size());
    for (size_t i = 0; i < position_mm.size(); ++i) {
      moved[i] = Interpolate(r.position_mm, r.correction_um, position_mm[i]);
    }
    r.position_mm = position_mm;
    r.correction_um = std::move(moved);
  }
  now_ms = std::max(now_ms, r.at_ms);
  const double rate_um_per_ms = config_.max_rate_um_per_min / 60000.0;
  auto move = [&](const std::vector<double>& to, const CorrectionLine& to_line, int64_t from_ms) {
    const double step = rate_um_per_ms * static_cast<double>(now_ms - from_ms);
    bool reached = true;
    for (size_t i = 0; i < to.size(); ++i) {
      r.correction_um[i] = Toward(r.correction_um[i], to[i], step);
      reached = reached && r.correction_um[i] == to[i];
    }
    r.line = MoveToward(r.line, to_line, reference_mm, travel, step * 1e-3);
    return reached && r.line == to_line;
  };
  Serving out;
  if (valid) {
    r.invalid_since_ms.reset();
    out.state = move(target_um, target_line, r.at_ms) ? ServedState::kValid : ServedState::kRamping;
  } else {
    if (!r.invalid_since_ms) r.invalid_since_ms = now_ms;
    const int64_t hold_end = *r.invalid_since_ms + int64_t{config_.hold_s} * 1000;
    const std::vector<double> zero(position_mm.size(), 0.0);
    if (r.correction_um == zero && r.line == CorrectionLine{}) {
      out.state = ServedState::kOff;
    } else if (now_ms < hold_end) {
      out.state = ServedState::kHolding;
    } else {
      out.state =
          move(zero, {}, std::max(r.at_ms, hold_end)) ? ServedState::kOff : ServedState::kRamping;
    }
  }
  // The clamp in force now bounds what is served at once.
  for (double& c : r.correction_um) {
    const double kept = std::clamp(c, -clamp_um, clamp_um);
    out.clamped = out.clamped || kept != c;
    c = kept;
  }
  out.clamped = ClampOverTravel(r.line, reference_mm, travel, clamp_um * 1e-3) || out.clamped;
  r.at_ms = now_ms;
  out.correction_um = r.correction_um;
  out.line = r.line;
  return out;
}

std::vector<std::string> ThermalErrorTableService::ConfiguredAxes(const std::string& machine) {
  const std::unique_ptr<Session> session = storage_.Open();
  std::vector<std::string> out;
  auto m = session->machines().Find(machine);
  if (!m) return out;
  for (const FeedAxisConfigRecord& r : session->feeds().Configs(m->id)) out.push_back(r.axis);
  return out;
}

}  // namespace thermocomp
