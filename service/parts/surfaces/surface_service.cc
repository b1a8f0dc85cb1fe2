#include "service/parts/surfaces/surface_service.h"
#include "storage/parts/surface_store.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "reports/parts/surface_report_codec.h"
#include "service/machine_lookup.h"

namespace thermocomp {
namespace {

SurfacePoint FromRecord(const SurfaceNominalRecord& r) {
  return {r.point, r.x_mm, r.y_mm, r.z_mm, r.i, r.j, r.k};
}

SurfaceNominalRecord ToRecord(const SurfacePoint& p) {
  return {p.id, p.x_mm, p.y_mm, p.z_mm, p.i, p.j, p.k};
}

// Largest coordinate difference between the file's nominal and `program`.
double MaxOff(const std::vector<SurfacePoint>& file, const std::vector<size_t>& index,
              const std::vector<SurfacePoint>& program) {
  double off = 0;
  for (size_t r = 0; r < file.size(); ++r) {
    const SurfacePoint& a = file[r];
    const SurfacePoint& b = program[index[r]];
    off = std::max(
        {off, std::abs(a.x_mm - b.x_mm), std::abs(a.y_mm - b.y_mm), std::abs(a.z_mm - b.z_mm)});
  }
  return off;
}

struct StoredPart {
  int64_t id = 0;
  std::vector<SurfacePoint> nominal;
  std::vector<SurfaceIteration> iterations;
};

// The stored part in full; Internal when a stored report no longer reads.
StatusOr<StoredPart> LoadPart(Session& session, const SurfacePartRecord& record) {
  StoredPart part;
  part.id = record.id;
  for (const SurfaceNominalRecord& r : session.surfaces().Nominal(record.id)) {
    part.nominal.push_back(FromRecord(r));
  }
  for (const SurfaceIterationRecord& r : session.surfaces().Iterations(record.id)) {
    auto it = SurfaceIterationFromJson(nlohmann::json::parse(r.report_json, nullptr, false));
    if (!it.ok()) return Status::Internal("stored surface iteration: " + it.status().message());
    part.iterations.push_back(std::move(it).value());
  }
  return part;
}

StatusOr<StoredPart> FindPart(Session& session, int64_t machine_id, const std::string& machine,
                              const std::string& name) {
  auto record = session.surfaces().FindPart(machine_id, name);
  if (!record) return Status::NotFound("no surface part '" + name + "' on " + machine);
  return LoadPart(session, *record);
}

}  // namespace

std::vector<std::vector<SurfacePoint>> SurfacePrograms(const std::vector<SurfacePoint>& nominal,
                                                       const std::vector<SurfaceIteration>& its) {
  std::vector<std::vector<SurfacePoint>> programs;
  programs.reserve(its.size() + 1);
  programs.push_back(nominal);
  for (const SurfaceIteration& it : its) programs.push_back(Mirror(programs.back(), it.d_mm));
  return programs;
}

SurfaceService::SurfaceService(Storage& storage, const Clock& clock, const Config& config)
    : storage_(storage), clock_(clock), config_(config) {}

StatusOr<SurfaceIteration> SurfaceService::AddMeasurement(const std::string& machine_name,
                                                          const std::string& part_name,
                                                          const std::vector<CmmPoint>& points,
                                                          const std::string& actor,
                                                          FieldErrors* errors) {
  FieldErrors e;
  auto refuse = [&](Status s) -> Status {
    if (errors) *errors = e;
    return s;
  };
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  if (points.empty()) {
    e.push_back({1, "row", "no points"});
    return refuse(Status::Unprocessable("a measurement needs points"));
  }
  // The file's points with unit normals, ids once each.
  std::vector<SurfacePoint> file;
  file.reserve(points.size());
  std::unordered_map<std::string, size_t> file_row;
  for (const CmmPoint& p : points) {
    auto unit = NormalisedPoint(p.nominal);
    if (!unit) {
      e.push_back({p.row, "i", "zero-length normal or not of unit length (within 0.01)"});
    }
    if (!file_row.emplace(p.nominal.id, p.row).second) {
      e.push_back({p.row, "point", "point '" + p.nominal.id + "' twice in the file"});
    }
    file.push_back(unit.value_or(p.nominal));
  }
  if (!e.empty()) return refuse(Status::InvalidArgument("invalid measurement"));

  std::optional<StoredPart> part;
  if (auto record = session->surfaces().FindPart(machine->id, part_name)) {
    auto loaded = LoadPart(*session, *record);
    if (!loaded.ok()) return loaded.status();
    part = std::move(loaded).value();
  }
  SurfaceIteration it;
  it.iteration = part ? static_cast<int>(part->iterations.size()) : 0;
  it.measured_ms = clock_.NowMs();
  it.actor = actor;
  it.input = points.front().dev_mm ? "deviation" : "measured";
  if (it.iteration >= kMaxSurfaceIterations) {
    return Status::Unprocessable("part '" + part_name + "' already has " +
                                 std::to_string(kMaxSurfaceIterations) + " iterations");
  }
  // Where each file row's point is in the original's order.
  std::vector<size_t> index(points.size());
  const std::vector<SurfacePoint>& original = part ? part->nominal : file;
  if (part) {
    if (points.size() != original.size()) {
      e.push_back({0, "point",
                   std::to_string(points.size()) + " points, the part's original has " +
                       std::to_string(original.size())});
    }
    std::unordered_map<std::string, size_t> where;
    for (size_t p = 0; p < original.size(); ++p) where.emplace(original[p].id, p);
    for (size_t r = 0; r < points.size(); ++r) {
      auto found = where.find(points[r].nominal.id);
      if (found == where.end()) {
        e.push_back({points[r].row, "point",
                     "point '" + points[r].nominal.id + "' is not a point of the original"});
      } else {
        index[r] = found->second;
      }
    }
    if (!e.empty()) return refuse(Status::Unprocessable("the points do not match the original"));
  } else {
    for (size_t r = 0; r < points.size(); ++r) index[r] = r;
  }

  it.d_mm.assign(original.size(), 0.0);
  std::vector<std::optional<double>> allowance(original.size());
  for (size_t r = 0; r < points.size(); ++r) {
    it.d_mm[index[r]] = DeviationAlongNormal(points[r], file[r], original[index[r]]);
    allowance[index[r]] = points[r].allowance_mm;
  }
  for (size_t r = 0; r < points.size(); ++r) {
    if (!std::isfinite(it.d_mm[index[r]])) {
      e.push_back({points[r].row, "point", "the deviation overflows (coordinates too large)"});
    }
  }
  if (!e.empty()) return refuse(Status::Unprocessable("invalid measurement"));
  it.stats = Summarise(it.d_mm);
  it.allowance = SummariseAllowance(allowance);
  if (it.allowance && !it.allowance->uniform) {
    it.allowance_not_uniform = true;
    it.flags.push_back(
        "allowance_mm spreads by " +
        std::to_string(static_cast<int>(std::lround(100 * it.allowance->spread_share))) +
        " % of its mean");
  }
  it.nominal_columns = "original";
  if (part) {
    const auto programs = SurfacePrograms(part->nominal, part->iterations);
    if (MaxOff(file, index, original) > kNominalMatchMm) {
      it.nominal_columns =
          MaxOff(file, index, programs.back()) <= kNominalMatchMm ? "program" : "other";
    }
    const SurfaceIteration& previous = part->iterations.back();
    it.before = previous.stats;
    std::vector<double> shift(original.size());
    for (size_t p = 0; p < original.size(); ++p) {
      const SurfacePoint& a = programs[programs.size() - 2][p];
      const SurfacePoint& b = programs.back()[p];
      shift[p] = (b.x_mm - a.x_mm) * original[p].i + (b.y_mm - a.y_mm) * original[p].j +
                 (b.z_mm - a.z_mm) * original[p].k;
    }
    it.repeat = CheckRepeat(previous.d_mm, it.d_mm, shift);
    if (!it.repeat->repeated) {
      it.allowance_not_uniform = true;
      it.flags.push_back(std::to_string(it.repeat->not_repeating) +
                         " points changed by more than the correction predicted");
    }
  }

  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  int64_t part_id = part ? part->id : 0;
  if (!part) {
    std::vector<SurfaceNominalRecord> records;
    records.reserve(original.size());
    for (const SurfacePoint& p : original) records.push_back(ToRecord(p));
    auto created = session->surfaces().CreatePart(machine->id, part_name, it.measured_ms, records);
    if (!created.ok()) return created.status();
    part_id = *created;
  }
  const std::string text = SurfaceIterationToJson(it, true).dump();
  if (Status s =
          session->surfaces().AddIteration(part_id, it.iteration, it.measured_ms,
                                           it.stats.mean_abs_mm, it.allowance_not_uniform, text);
      !s.ok()) {
    return s;
  }
  if (Status s = session->log().Audit(it.measured_ms, actor, "surface-measurement", machine_name,
                                      static_cast<int64_t>(points.size()),
                                      part_name + " iteration " + std::to_string(it.iteration));
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return it;
}

StatusOr<std::vector<SurfacePartSummary>> SurfaceService::Parts(const std::string& machine_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  std::vector<SurfacePartSummary> out;
  for (const SurfacePartRecord& r : session->surfaces().Parts(machine->id)) {
    out.push_back({r.name, r.created_ms, static_cast<size_t>(r.points), r.iterations,
                   r.latest_mean_abs_mm, r.latest_flagged});
  }
  return out;
}

StatusOr<SurfacePartReport> SurfaceService::Part(const std::string& machine_name,
                                                 const std::string& part_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  auto part = FindPart(*session, machine->id, machine_name, part_name);
  if (!part.ok()) return part.status();
  return SurfacePartReport{machine_name, part_name, std::move(part->nominal),
                           std::move(part->iterations)};
}

StatusOr<SurfaceProgram> SurfaceService::Corrected(const std::string& machine_name,
                                                   const std::string& part_name,
                                                   std::optional<int> iteration) {
  auto report = Part(machine_name, part_name);
  if (!report.ok()) return report.status();
  const int last = static_cast<int>(report->iterations.size()) - 1;
  const int n = iteration.value_or(last);
  if (n < 0 || n > last) {
    return Status::NotFound("part '" + part_name + "' has no iteration " + std::to_string(n) +
                            " (measured: 0.." + std::to_string(last) + ")");
  }
  report->iterations.resize(static_cast<size_t>(n) + 1);
  return SurfaceProgram{n, SurfacePrograms(report->nominal, report->iterations).back()};
}

}  // namespace thermocomp
