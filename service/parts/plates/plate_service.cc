#include "service/parts/plates/plate_service.h"
#include "storage/parts/plate_store.h"

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include <nlohmann/json.hpp>

#include "reports/json_text.h"
#include "reports/parts/plate_report_codec.h"
#include "service/drift_dataset.h"

namespace thermocomp {
namespace {

constexpr double kUmPerMm = 1000.0;

std::optional<double> Um(const std::optional<double>& mm) {
  if (!mm) return std::nullopt;
  return *mm * kUmPerMm;
}

// Every content rule of a hole, then the pairs; errors name the data row.
void CheckHoles(const std::vector<PlateHoleInput>& holes, int64_t now_ms, FieldErrors& errors) {
  std::map<std::string, size_t> seen;  // hole id -> row
  struct PairRows {
    std::vector<size_t> on, off;
  };
  std::map<int, PairRows> pairs;
  int64_t first = 0, last = 0;
  for (size_t i = 0; i < holes.size(); ++i) {
    const PlateHoleInput& h = holes[i];
    const size_t row = i + 1;
    if (h.hole.empty() || h.hole.size() > 64 || !ValidUtf8(h.hole)) {
      errors.push_back({row, "hole", "must be 1-64 bytes of UTF-8"});
    } else if (auto [it, added] = seen.emplace(h.hole, row); !added) {
      errors.push_back(
          {row, "hole",
           "duplicate hole '" + h.hole + "' (row " + std::to_string(it->second) + ")"});
    }
    if (h.pair < 1) errors.push_back({row, "pair", "must be 1 or more"});
    for (auto [field, v] :
         {std::pair{"nominal_x_mm", h.nominal_x_mm}, std::pair{"nominal_y_mm", h.nominal_y_mm}}) {
      if (!std::isfinite(v) || std::abs(v) > kMaxPlateNominalMm)
        errors.push_back({row, field, "must be finite, within +-10000 mm"});
    }
    for (auto [field, v] : {std::pair{"dev_x_mm", h.dev_x_mm}, std::pair{"dev_y_mm", h.dev_y_mm}}) {
      if (!std::isfinite(v) || std::abs(v) > kMaxPlateDeviationMm)
        errors.push_back({row, field, "must be finite, within +-1 mm (deviations are in mm)"});
    }
    if (h.bored_ms > now_ms + kPlateMaxFutureMs) {
      errors.push_back({row, "bored_at", "is in the future"});
    }
    first = i == 0 ? h.bored_ms : std::min(first, h.bored_ms);
    last = i == 0 ? h.bored_ms : std::max(last, h.bored_ms);
    (h.compensated ? pairs[h.pair].on : pairs[h.pair].off).push_back(row);
  }
  if (last - first > kMaxPlateSpanMs) {
    errors.push_back({0, "bored_at", "the plate's bore times span more than 7 days"});
  }
  for (const auto& [pair, rows] : pairs) {
    if (pair < 1) continue;
    const std::string name = "pair " + std::to_string(pair);
    if (rows.on.empty() || rows.off.empty()) {
      const size_t row = rows.on.empty() ? rows.off.front() : rows.on.front();
      errors.push_back({row, "compensation",
                        name + " has no " + (rows.on.empty() ? "on" : "off") +
                            " hole: each pair needs one of each"});
    }
    if (rows.on.size() > 1) {
      errors.push_back({rows.on[1], "compensation", name + " has a second on hole"});
    }
    if (rows.off.size() > 1) {
      errors.push_back({rows.off[1], "compensation", name + " has a second off hole"});
    }
  }
}

std::string FirstErrors(const FieldErrors& errors) {
  const FieldError& e = errors.front();
  std::string detail = "row " + std::to_string(e.index) + ", " + e.field + ": " + e.message;
  if (errors.total() > 1) detail += " (and " + std::to_string(errors.total() - 1) + " more)";
  return detail;
}

}  // namespace

bool ValidPlateName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

PlateService::PlateService(Storage& storage, const Clock& clock, const Config& config)
    : storage_(storage), clock_(clock), config_(config) {}

StatusOr<PlateReport> PlateService::ReportOf(const std::string& machine, const PlateRecord& p) {
  const bool along_y = p.axis != "X";
  std::vector<PlateHoleValue> values;
  values.reserve(p.holes.size());
  for (const auto& h : p.holes) {
    values.push_back({h.pair, h.nominal_y_mm, (along_y ? h.dev_y_mm : h.dev_x_mm) * kUmPerMm,
                      h.compensated, h.bored_ms});
  }
  auto stats = ComputePlateStatistics(values);
  if (!stats.ok()) return stats.status();
  PlateReport r;
  r.machine = machine;
  r.plate = p.name;
  r.axis = p.axis;
  r.created_ms = p.created_ms;
  r.actor = p.actor;
  r.stats = std::move(stats).value();
  const int64_t t0 = r.stats.first_bored_ms;
  if (r.stats.pay_off_ms)
    r.pay_off_minutes = static_cast<double>(*r.stats.pay_off_ms - t0) / 60000.0;
  r.holes.reserve(p.holes.size());
  for (const auto& h : p.holes) {
    PlateReportHole o;
    o.hole = h.hole;
    o.pair = h.pair;
    o.nominal_x_mm = h.nominal_x_mm;
    o.nominal_y_mm = h.nominal_y_mm;
    o.dev_x_um = h.dev_x_mm * kUmPerMm;
    o.dev_y_um = h.dev_y_mm * kUmPerMm;
    o.compensated = h.compensated;
    o.bored_ms = h.bored_ms;
    o.minutes = static_cast<double>(h.bored_ms - t0) / 60000.0;
    o.served_offset_um = Um(h.served_offset_mm);
    o.predicted_drift_um = Um(h.predicted_drift_mm);
    o.model_version = h.model_version;
    o.temperatures = h.temperatures;
    if (!h.served_offset_mm) ++r.holes_without_served;
    r.holes.push_back(std::move(o));
  }
  return r;
}

StatusOr<PlateReport> PlateService::Import(const PlateImport& in, FieldErrors* errors) {
  FieldErrors local;
  FieldErrors& errs = errors ? *errors : local;
  if (!ValidPlateName(in.plate)) {
    errs.push_back({0, "plate", "must be 1-64 of A-Z a-z 0-9 _ . -"});
    return Status::InvalidArgument("plate: must be 1-64 of A-Z a-z 0-9 _ . -");
  }
  if (in.axis != "X" && in.axis != "Y") {
    errs.push_back({0, "axis", "must be X or Y (the deviations the CMM file holds)"});
    return Status::InvalidArgument("axis: must be X or Y");
  }
  if (in.holes.size() > kMaxPlateHoles) {
    return Status::TooLarge("a plate has at most " + std::to_string(kMaxPlateHoles) + " holes");
  }
  if (in.holes.size() < 2) {
    errs.push_back({0, "body", "a plate needs at least one pair (two holes)"});
    return Status::Unprocessable("a plate needs at least one pair (two holes)");
  }
  CheckHoles(in.holes, clock_.NowMs(), errs);
  if (!errs.empty()) return Status::Unprocessable(FirstErrors(errs));

  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(in.machine);
  if (!machine) return Status::NotFound("unknown machine '" + in.machine + "'");
  const AxisRecord* axis = machine->FindAxis(in.axis);
  if (!axis) return Status::NotFound("machine '" + in.machine + "' has no axis " + in.axis);

  PlateRecord p;
  p.name = in.plate;
  p.axis = in.axis;
  p.created_ms = clock_.NowMs();
  p.actor = in.actor;
  p.holes.reserve(in.holes.size());
  for (const auto& h : in.holes) {
    PlateHoleRecord rec;
    rec.hole = h.hole;
    rec.pair = h.pair;
    rec.nominal_x_mm = h.nominal_x_mm;
    rec.nominal_y_mm = h.nominal_y_mm;
    rec.dev_x_mm = h.dev_x_mm;
    rec.dev_y_mm = h.dev_y_mm;
    rec.compensated = h.compensated;
    rec.bored_ms = h.bored_ms;
    if (auto served = ServedAt(session->log(), axis->id, h.bored_ms)) {
      rec.served_offset_mm = served->offset_mm;
      if (std::isfinite(served->predicted_drift_mm))
        rec.predicted_drift_mm = served->predicted_drift_mm;
      rec.model_version = served->model_version;
    }
    for (const auto& sensor : machine->sensors) {
      auto sample = session->samples().AtOrBefore(sensor.id, h.bored_ms);
      if (sample && h.bored_ms - sample->ts_ms <= kPlateTemperatureMaxAgeMs &&
          std::isfinite(sample->filtered)) {
        rec.temperatures[sensor.name] = sample->filtered;
      }
    }
    p.holes.push_back(std::move(rec));
  }
  std::stable_sort(p.holes.begin(), p.holes.end(),
                   [](const PlateHoleRecord& a, const PlateHoleRecord& b) {
                     return a.bored_ms != b.bored_ms ? a.bored_ms < b.bored_ms : a.hole < b.hole;
                   });
  auto report = ReportOf(in.machine, p);
  if (!report.ok()) return Status::Unprocessable(report.status().message());
  p.summary_json = JsonText(PlateSummaryToJson(SummaryOf(*report)));

  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  if (Status s = session->plates().Insert(machine->id, p); !s.ok()) return s;
  if (Status s = session->log().Audit(p.created_ms, in.actor, "import-plate", in.machine,
                                      static_cast<int64_t>(p.holes.size()), in.plate);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return report;
}

StatusOr<std::vector<PlateSummary>> PlateService::List(const std::string& machine) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto m = session->machines().Find(machine);
  if (!m) return Status::NotFound("unknown machine '" + machine + "'");
  std::vector<PlateSummary> out;
  const auto plates = session->plates().List(m->id);
  out.reserve(plates.size());
  for (const auto& p : plates) {
    auto parsed = nlohmann::json::parse(p.summary_json, nullptr, false);
    auto summary = PlateSummaryFromJson(parsed);
    if (!summary.ok())
      return Status::Internal("plate '" + p.name + "': " + summary.status().message());
    out.push_back(std::move(summary).value());
  }
  return out;
}

StatusOr<PlateReport> PlateService::Report(const std::string& machine, const std::string& plate) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto m = session->machines().Find(machine);
  if (!m) return Status::NotFound("unknown machine '" + machine + "'");
  auto p = session->plates().Find(m->id, plate);
  if (!p) return Status::NotFound("machine '" + machine + "' has no plate '" + plate + "'");
  return ReportOf(machine, *p);
}

}  // namespace thermocomp
