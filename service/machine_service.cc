#include "service/machine_service.h"

#include "service/check_service.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/time_format.h"
#include "model/ewma_filter.h"
#include "storage/analysis_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {

namespace {

const std::set<std::string> kControllers = {"sinumerik", "beckhoff", "heidenhain", "fanuc",
                                            "linuxcnc"};

// Controller names: lower-case letters, digits and _.- (okuma, mazak_m, pc).
bool ValidControllerName(const std::string& c) {
  if (c.empty() || c.size() > 32) return false;
  return std::all_of(c.begin(), c.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '.' ||
           ch == '-';
  });
}

// A definition that would leave the machine with more sensors than allowed.
Status TooManySensors(size_t sensors, size_t max, FieldErrors* errors) {
  if (errors) {
    *errors = {{0, "sensors",
                "a machine has at most " + std::to_string(max) +
                    " sensors (limits.max_sensors_per_machine); this definition would give it " +
                    std::to_string(sensors)}};
  }
  return Status::InvalidArgument("too many sensors");
}

// What a definition set, for its audit line: which parts of what the
// machine's control receives (axes' inputs, clamp, reference and travel;
// sensors and their filters; the control) it changed, and on which axes.
std::string DefinitionSummary(const MachineDefinition& d, bool created) {
  std::string out = created ? "created" : "updated";
  auto names = [](const auto& items) {
    std::string list;
    for (const auto& item : items) list += (list.empty() ? "" : ",") + item.name;
    return list;
  };
  if (!d.axes.empty()) out += "; axes " + names(d.axes);
  if (!d.sensors.empty()) out += "; sensors " + names(d.sensors);
  if (d.controller) out += "; controller " + *d.controller;
  if (d.control_axes) out += "; control_axes";
  if (d.automatic_checks)
    out += *d.automatic_checks ? "; automatic_checks on" : "; automatic_checks off";
  if (d.display_name) out += "; display_name";
  if (out.size() > 500) {
    // Resized, not substr + "...": GCC 12 warns falsely on that (PR 105651).
    out.resize(497);
    out.append("...");
  }
  return out;
}

}  // namespace

bool KnownController(const std::string& controller) {
  return kControllers.count(controller) > 0;
}

MachineDefinition MachineDefinition::Of(const MachineRecord& m) {
  return {m.name,    m.display_name, m.controller, m.control_axes, m.automatic_checks,
          m.sensors, m.axes};
}

StatusOr<bool> MachineService::Register(const MachineDefinition& machine, const std::string& actor,
                                        FieldErrors* errors) {
  // Refused before any of it is looked at: a definition's sensors cost
  // work and memory here and in every later read of the machine.
  const auto max_sensors = static_cast<size_t>(std::max(1, max_sensors_per_machine_.load()));
  if (machine.sensors.size() > max_sensors) {
    return TooManySensors(machine.sensors.size(), max_sensors, errors);
  }
  FieldErrors e;
  if (!ValidIdentifier(machine.name))
    e.push_back({0, "machine", "must match [A-Za-z0-9_.-]{1,64}"});
  if (machine.controller && !ValidControllerName(*machine.controller)) {
    e.push_back({0, "controller",
                 "must be a control's name of lower-case letters, digits and _.- (the five with "
                 "native formats: sinumerik, beckhoff, heidenhain, fanuc, linuxcnc; or any "
                 "other, e.g. okuma, or none)"});
  }
  std::set<std::string> sensors;
  for (size_t i = 0; i < machine.sensors.size(); ++i) {
    const auto& s = machine.sensors[i];
    if (!ValidIdentifier(s.name)) e.push_back({i, "sensors.id", "must match [A-Za-z0-9_.-]{1,64}"});
    if (!sensors.insert(s.name).second)
      e.push_back({i, "sensors.id", "duplicate sensor " + s.name});
    if (!EwmaFilter::ValidAlpha(s.ewma_alpha)) {
      e.push_back({i, "sensors.ewma_alpha", "must be in (0, 1]"});
    }
  }
  std::optional<MachineRecord> existing;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    existing = session->machines().Find(machine.name);
  }
  // The stored machine with what the definition gives applied.
  MachineRecord m = existing.value_or(MachineRecord{});
  m.name = machine.name;
  if (machine.display_name) m.display_name = *machine.display_name;
  if (machine.controller) m.controller = *machine.controller;
  if (machine.control_axes) m.control_axes = *machine.control_axes;
  if (machine.automatic_checks) m.automatic_checks = *machine.automatic_checks;
  for (const auto& s : m.sensors) sensors.insert(s.name);
  // The stored sensors are kept, so they count with the new ones.
  if (sensors.size() > max_sensors) return TooManySensors(sensors.size(), max_sensors, errors);
  std::set<std::string> axes;
  for (size_t i = 0; i < machine.axes.size(); ++i) {
    const auto& a = machine.axes[i];
    if (!ValidAxisName(a.name))
      e.push_back({i, "axes.id", "must be an axis letter X Y Z A B C U V W"});
    if (!axes.insert(a.name).second) e.push_back({i, "axes.id", "duplicate axis " + a.name});
    if (!std::isfinite(a.clamp_mm) || a.clamp_mm < 0 || a.clamp_mm > 1.0) {
      e.push_back({i, "axes.model.clamp_mm", "must be within 0..1 mm"});
    }
    if (!std::isfinite(a.reference_position_mm) || std::fabs(a.reference_position_mm) > 1e5) {
      e.push_back({i, "axes.reference_position_mm", "must be a finite number within +-100 m"});
    }
    if (a.travel_min_mm.has_value() != a.travel_max_mm.has_value() ||
        (a.travel_min_mm &&
         !(std::isfinite(*a.travel_min_mm) && std::isfinite(*a.travel_max_mm) &&
           std::fabs(*a.travel_min_mm) <= 1e5 && std::fabs(*a.travel_max_mm) <= 1e5 &&
           *a.travel_min_mm < *a.travel_max_mm))) {
      e.push_back({i, "axes.travel_mm", "must be [min, max] in mm within +-100 m, min below max"});
    }
    for (const auto& in : a.inputs) {
      if (!sensors.count(in)) e.push_back({i, "axes.model.inputs", "unknown sensor '" + in + "'"});
    }
  }
  for (const auto& a : m.axes) axes.insert(a.name);
  if (!m.control_axes.empty()) {
    std::set<std::string> seen;
    for (const auto& a : m.control_axes) {
      if (!ValidAxisName(a) || !seen.insert(a).second) {
        e.push_back({0, "control_axes", "must list distinct axis letters X Y Z A B C U V W"});
        break;
      }
    }
    for (const auto& a : axes) {
      if (!seen.count(a)) {
        e.push_back({0, "control_axes", "lacks the machine's axis " + a});
        break;
      }
    }
  }
  if (!e.empty()) {
    if (errors) *errors = e;
    return Status::Unprocessable("invalid machine definition");
  }
  // Sensors and axes: those listed replace the stored ones of the same
  // name, the others are kept.
  for (const auto& s : machine.sensors) {
    auto it = std::find_if(m.sensors.begin(), m.sensors.end(),
                           [&](const SensorRecord& x) { return x.name == s.name; });
    if (it == m.sensors.end())
      m.sensors.push_back(s);
    else
      *it = {it->id, s.name, s.location, s.ewma_alpha};
  }
  for (const auto& a : machine.axes) {
    auto it = std::find_if(m.axes.begin(), m.axes.end(),
                           [&](const AxisRecord& x) { return x.name == a.name; });
    if (it == m.axes.end()) {
      m.axes.push_back(a);
      continue;
    }
    AxisRecord updated{it->id, a.name, a.reference_position_mm, a.inputs, a.clamp_mm};
    // A travel left out of the update keeps the stored one.
    updated.travel_min_mm = a.travel_min_mm ? a.travel_min_mm : it->travel_min_mm;
    updated.travel_max_mm = a.travel_max_mm ? a.travel_max_mm : it->travel_max_mm;
    *it = updated;
  }
  const std::unique_ptr<Session> session = storage_.Open();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  auto created = session->machines().Upsert(m, clock_.NowMs());
  if (!created.ok()) return created.status();
  if (Status s = session->log().Audit(clock_.NowMs(), actor, "machine", m.name, 1,
                                      DefinitionSummary(machine, !existing.has_value()));
      !s.ok())
    return s;
  if (Status s = tx.Commit(); !s.ok()) return s;
  if (cache_ && existing)
    cache_->InvalidateMachine(existing->id);  // the sensor list may have changed
  return *created;
}

std::vector<MachineRecord> MachineService::List() {
  const std::unique_ptr<Session> session = storage_.Open();
  return session->machines().List();
}

std::optional<MachineRecord> MachineService::Find(const std::string& name) {
  const std::unique_ptr<Session> session = storage_.Open();
  return session->machines().Find(name);
}

MachineStatus MachineService::Summary(const MachineRecord& m) {
  const std::unique_ptr<Session> session = storage_.Open();
  SampleStore& samples = session->samples();
  std::optional<int64_t> last;
  for (const auto& s : m.sensors) {
    if (auto fs = samples.LoadFilterState(s.id)) last = std::max(last.value_or(0), fs->last_ts_ms);
  }
  MachineStatus status;
  status.last_sample_ms = last;
  ModelStore& models = session->models();
  for (const auto& a : m.axes) {
    auto rec = models.Active(a.id);
    status.active_models[a.name] = rec ? std::optional<int>(rec->version) : std::nullopt;
  }
  status.checks = CountChecks(*session, m.id, clock_.NowMs());
  status.samples = samples.CountForMachine(m.id);
  status.probe_points = session->probes().CountPoints(m.id);
  status.last_column_check = LatestColumnCheckSummary(*session, m.id);
  return status;
}

void MachineService::SetLimits(const Config& config) {
  max_sensors_per_machine_ = config.max_sensors_per_machine;
}

OverviewPage MachineService::Overview(size_t offset, size_t limit) {
  const std::unique_ptr<Session> session = storage_.Open();
  const int64_t now = clock_.NowMs();
  const std::vector<MachineRecord> all = session->machines().List();  // by name
  OverviewPage page;
  page.total = all.size();
  const size_t from = std::min(offset, all.size());
  const size_t to = from + std::min(limit, all.size() - from);
  std::vector<MachineOverview>& out = page.machines;
  out.reserve(to - from);
  for (size_t i = from; i < to; ++i) {
    const MachineRecord& m = all[i];
    MachineOverview o;
    o.name = m.name;
    o.controller = m.controller;
    for (const auto& s : m.sensors) {
      if (auto fs = session->samples().LoadFilterState(s.id)) {
        o.last_sample_ms = std::max(o.last_sample_ms.value_or(0), fs->last_ts_ms);
      }
    }
    if (auto datum = session->probes().LatestDatum(m.id)) o.last_datum_ms = datum->ts_ms;
    o.checks = CountChecks(*session, m.id, now);
    for (const auto& a : m.axes) {
      AxisOverview axis;
      axis.axis = a.name;
      if (auto active = session->models().Active(a.id)) {
        axis.model_version = active->version;
        axis.model_created_ms = active->created_ms;
      }
      const std::vector<AnalysisRecord> analyses = session->analyses().List(a.id, 1);
      if (!analyses.empty()) {
        const AnalysisRecord& last = analyses.front();
        axis.analysis_id = last.id;
        axis.analysis_ms = last.created_ms;
        axis.analysis_effects = last.effects;
        axis.analysis_version = last.model_version;
        if (last.model_version) {
          if (auto v = session->models().Get(a.id, *last.model_version)) {
            axis.analysis_version_status = v->status;
          }
        }
      }
      o.axes.push_back(std::move(axis));
    }
    out.push_back(std::move(o));
  }
  return page;
}

}  // namespace thermocomp
