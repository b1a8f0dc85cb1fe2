#include "reports/check_codec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "core/time_format.h"
#include "reports/json_fields.h"
#include "reports/json_text.h"

namespace thermocomp {
namespace {

using nlohmann::json;

// Coordinates and lengths of artifacts and probes: finite and within +-10 m.
constexpr double kMaxMm = 1e4;

std::optional<Vec3> Xyz(JsonFields& f) {
  auto x = f.Number("x", JsonFields::kRequired, -kMaxMm, kMaxMm);
  auto y = f.Number("y", JsonFields::kRequired, -kMaxMm, kMaxMm);
  auto z = f.Number("z", JsonFields::kRequired, -kMaxMm, kMaxMm);
  if (!x || !y || !z) return std::nullopt;
  return Vec3{*x, *y, *z};
}

// An {x, y, z} object at `key` of f.
std::optional<Vec3> XyzField(JsonFields& f, const char* key, JsonFields::Need need) {
  const json* v = f.Object(key, need);
  if (!v) return std::nullopt;
  JsonFields xyz = f.Field(*v, key);
  return Xyz(xyz);
}

char AxisLetter(const std::optional<std::string>& s) {
  if (!s || s->size() != 1) return 0;
  const char c = (*s)[0];
  return c == 'X' || c == 'Y' || c == 'Z' ? c : '\0';
}

void UncertaintyFromFields(JsonFields& u, UncertaintyInputs& ui) {
  std::tuple<const char*, double*, double> fields[] = {
      {"device_um_per_m", &ui.device_um_per_m, 1e3},
      {"misalignment_mm", &ui.misalignment_mm, 1e3},
      {"alpha_um_per_m_c", &ui.alpha_um_per_m_c, 1e3},
      {"temperature_range_c", &ui.temperature_range_c, 100.0},
      {"delta_t_c", &ui.delta_t_c, 100.0},
      {"alpha_range_um_per_m_c", &ui.alpha_range_um_per_m_c, 1e3},
      {"e_ve_um", &ui.e_ve_um, 1e4}};
  for (auto& [key, dest, max] : fields) {
    if (auto v = u.Number(key, JsonFields::kOptional, key == std::string("delta_t_c") ? -max : 0.0,
                          max)) {
      *dest = *v;
      ui.stated = true;
    }
  }
}

}  // namespace

std::optional<Artifact> ArtifactFromJson(const json& j, FieldErrors& errors) {
  Artifact a;
  JsonFields f(j, errors);
  if (!f.IsObject()) return std::nullopt;
  const json* points = f.Array("points");
  if (points && points->empty()) errors.push_back({0, "points", "must not be empty"});
  for (size_t i = 0; points && i < points->size(); ++i) {
    JsonFields p = f.Item((*points)[i], i, "points");
    if (!p.IsObject()) continue;
    auto id = p.String("id", JsonFields::kRequired, 64);
    ArtifactPoint ap;
    if (auto n = XyzField(p, "nominal", JsonFields::kRequired)) ap.nominal = *n;
    if (const json* e = p.Object("expansion", JsonFields::kOptional)) {
      JsonFields ef = p.Field(*e, "expansion");
      double* beta[] = {&ap.expansion.beta_x, &ap.expansion.beta_y, &ap.expansion.beta_z};
      double* b[] = {&ap.expansion.b_x, &ap.expansion.b_y, &ap.expansion.b_z};
      const char* dirs[] = {"x", "y", "z"};
      for (int d = 0; d < 3; ++d) {
        const json* dir = ef.Object(dirs[d], JsonFields::kOptional);
        if (!dir) continue;
        JsonFields df = ef.Field(*dir, dirs[d]);
        if (auto v = df.Number("beta_mm_per_c", JsonFields::kRequired, -1.0, 1.0)) *beta[d] = *v;
        if (auto v = df.Number("b_mm", JsonFields::kRequired, -100.0, 100.0)) *b[d] = *v;
      }
    }
    if (id && !a.points.emplace(*id, ap).second) {
      errors.push_back({i, "points.id", "duplicate point id"});
    }
  }
  if (const json* schemes = f.Array("schemes", JsonFields::kOptional)) {
    for (size_t i = 0; i < schemes->size(); ++i) {
      JsonFields sf = f.Item((*schemes)[i], i, "schemes");
      if (!sf.IsObject()) continue;
      StraightnessScheme sc;
      sc.id = sf.String("id", JsonFields::kRequired, 64).value_or("");
      sc.travel_axis = AxisLetter(sf.String("travel_axis", JsonFields::kRequired, 1));
      sc.deviation_axis = AxisLetter(sf.String("deviation_axis", JsonFields::kRequired, 1));
      sc.reference_point = sf.String("reference_point", JsonFields::kRequired, 64).value_or("");
      if (sc.id.empty() || !sc.travel_axis || !sc.deviation_axis ||
          sc.travel_axis == sc.deviation_axis || !a.points.count(sc.reference_point)) {
        errors.push_back({i, "schemes",
                          "each needs id, travel_axis and deviation_axis (two of X, Y, Z) and a "
                          "reference_point that is one of the points"});
        continue;
      }
      a.schemes.push_back(sc);
    }
  }
  if (auto c = XyzField(f, "table_centre", JsonFields::kOptional)) a.table_centre = *c;
  if (!errors.empty()) return std::nullopt;
  return a;
}

std::optional<ColumnCheckInput> ColumnCheckFromJson(const json& j, FieldErrors& errors) {
  ColumnCheckInput in;
  JsonFields f(j, errors);
  if (!f.IsObject()) return std::nullopt;
  in.request_id = f.Integer("request_id", JsonFields::kOptional, 1, INT64_MAX);
  in.ts_ms = f.Timestamp("ts").value_or(0);
  in.artifact = f.String("artifact", JsonFields::kRequired, 64).value_or("");
  if (auto t = f.Number("artifact_temperature_c", JsonFields::kRequired, -40.0, 150.0)) {
    in.temperature_c = *t;
  }
  if (const json* spheres = f.Array("spheres")) {
    for (size_t i = 0; i < spheres->size(); ++i) {
      JsonFields sf = f.Item((*spheres)[i], i, "spheres");
      if (!sf.IsObject()) continue;
      SphereProbe sp;
      sp.sphere = sf.String("sphere", JsonFields::kRequired, 64).value_or("");
      if (auto b = sf.Number("b_deg", JsonFields::kRequired, -360.0, 360.0)) sp.b_deg = *b;
      if (auto p = Xyz(sf)) sp.position = *p;
      in.spheres.push_back(sp);
    }
  }
  if (const json* points = f.Array("points", JsonFields::kOptional)) {
    for (size_t i = 0; i < points->size(); ++i) {
      JsonFields pf = f.Item((*points)[i], i, "points");
      if (!pf.IsObject()) continue;
      SurfaceProbe sp;
      sp.point = pf.String("id", JsonFields::kRequired, 64).value_or("");
      sp.scheme = pf.String("scheme", JsonFields::kRequired, 64).value_or("");
      if (auto v = Xyz(pf)) sp.position = *v;
      in.points.push_back(sp);
    }
  }
  if (const json* p = f.Object("parallelism", JsonFields::kOptional)) {
    JsonFields pf = f.Field(*p, "parallelism");
    ParallelismProbe pp;
    auto ball = XyzField(pf, "ball", JsonFields::kRequired);
    auto shank = XyzField(pf, "shank", JsonFields::kRequired);
    if (auto h = pf.Number("height_mm", JsonFields::kOptional, 1.0, 1000.0)) pp.height_mm = *h;
    if (ball && shank) {
      pp.ball = *ball;
      pp.shank = *shank;
      in.parallelism = pp;
    }
  }
  if (!errors.empty()) return std::nullopt;
  return in;
}

std::optional<PositioningInput> PositioningFromJson(const json& j, FieldErrors& errors) {
  PositioningInput in;
  JsonFields f(j, errors);
  if (!f.IsObject()) return std::nullopt;
  in.axis = f.String("axis", JsonFields::kRequired, 1).value_or("");
  in.ts_ms = f.Timestamp("ts").value_or(0);
  if (auto targets = f.Numbers("targets_mm", JsonFields::kRequired, kMaxPositioningTargets)) {
    in.data.targets_mm = *targets;
  }
  if (const json* runs = f.Array("runs")) {
    if (runs->size() > kMaxPositioningRuns) {
      errors.push_back({0, "runs", "more than " + std::to_string(kMaxPositioningRuns) + " runs"});
    }
    for (size_t i = 0; i < runs->size() && i < kMaxPositioningRuns; ++i) {
      JsonFields rf = f.Item((*runs)[i], i, "runs");
      if (!rf.IsObject()) continue;
      PositioningRun run;
      const auto dir = rf.String("direction", JsonFields::kRequired, 1);
      if (dir && *dir != "+" && *dir != "-") {
        errors.push_back({i, "runs.direction", "must be \"+\" or \"-\""});
      }
      run.direction = dir == "-" ? -1 : 1;
      if (auto d = rf.Numbers("deviations_um", JsonFields::kRequired, kMaxPositioningTargets)) {
        run.deviations_um = *d;
      }
      in.data.runs.push_back(run);
    }
  }
  in.compensation_active = f.Bool("compensation_active").value_or(false);
  in.machine_temperature_c = f.Number("machine_temperature_c", JsonFields::kOptional, -40, 150);
  in.air_temperature_c = f.Number("air_temperature_c", JsonFields::kOptional, -40, 150);
  in.note = f.String("note", JsonFields::kOptional).value_or("");
  if (const json* u = f.Object("uncertainty", JsonFields::kOptional)) {
    JsonFields uf = f.Field(*u, "uncertainty");
    UncertaintyFromFields(uf, in.uncertainty);
  }
  if (!errors.empty()) return std::nullopt;
  return in;
}

bool PositioningFromCsv(const std::string& body, PositioningData& out, FieldErrors& errors) {
  std::istringstream in(body);
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "target_mm,run,direction,deviation_um") {
    errors.push_back({0, "header", "CSV must start with target_mm,run,direction,deviation_um"});
    return false;
  }
  std::vector<std::string> run_order;
  std::map<std::string, int> direction;
  std::map<std::string, std::map<double, double>> values;
  std::set<double> targets;
  for (size_t row = 0; std::getline(in, line); ++row) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (cells.size() != 4) {
      errors.push_back({row, "row", "expected 4 fields"});
      continue;
    }
    char* end = nullptr;
    const double target = std::strtod(cells[0].c_str(), &end);
    if (end == cells[0].c_str() || *end) errors.push_back({row, "target_mm", "not a number"});
    const double dev = std::strtod(cells[3].c_str(), &end);
    if (end == cells[3].c_str() || *end) errors.push_back({row, "deviation_um", "not a number"});
    if (cells[2] != "+" && cells[2] != "-") {
      errors.push_back({row, "direction", "must be + or -"});
      continue;
    }
    const int dir = cells[2] == "+" ? 1 : -1;
    if (!direction.count(cells[1])) {
      run_order.push_back(cells[1]);
      direction[cells[1]] = dir;
    } else if (direction[cells[1]] != dir) {
      errors.push_back({row, "direction", "run " + cells[1] + " changes direction"});
    }
    if (!values[cells[1]].emplace(target, dev).second) {
      errors.push_back({row, "target_mm", "run " + cells[1] + " has this target twice"});
    }
    targets.insert(target);
  }
  out.targets_mm.assign(targets.begin(), targets.end());
  for (const auto& name : run_order) {
    PositioningRun run{direction[name], {}};
    for (double t : out.targets_mm) {
      auto it = values[name].find(t);
      if (it == values[name].end()) {
        errors.push_back({0, "run", "run " + name + " lacks target " + std::to_string(t)});
        break;
      }
      run.deviations_um.push_back(it->second);
    }
    out.runs.push_back(run);
  }
  return errors.empty();
}

const std::set<std::string>& PositioningQueryParameters() {
  static const std::set<std::string> names = {"axis",
                                              "ts",
                                              "compensation_active",
                                              "machine_temperature_c",
                                              "air_temperature_c",
                                              "note",
                                              "device_um_per_m",
                                              "misalignment_mm",
                                              "alpha_um_per_m_c",
                                              "temperature_range_c",
                                              "delta_t_c",
                                              "alpha_range_um_per_m_c",
                                              "e_ve_um"};
  return names;
}

void PositioningFromQuery(const std::multimap<std::string, std::string>& params,
                          PositioningInput& in, FieldErrors& errors) {
  // The same rules as the JSON body: each parameter as the JSON value it
  // stands for, read by the same field readers.
  json j = json::object();
  std::set<std::string> seen;
  for (const auto& [name, value] : params) {
    if (!PositioningQueryParameters().count(name)) {
      errors.push_back({0, name, "unknown query parameter"});
      continue;
    }
    if (!seen.insert(name).second) {
      errors.push_back({0, name, "given more than once"});
      continue;
    }
    if (name == "axis" || name == "note" || name == "ts") {
      if (!ValidUtf8(value)) {
        errors.push_back({0, name, "must be UTF-8 text"});
        continue;
      }
      j[name] = value;
    } else if (name == "compensation_active") {
      if (value != "true" && value != "false") {
        errors.push_back({0, name, "must be true or false"});
        continue;
      }
      j[name] = value == "true";
    } else {
      double v = 0;
      auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
      if (ec != std::errc() || end != value.data() + value.size() || value.empty()) {
        errors.push_back({0, name, "must be a number"});
        continue;
      }
      (name == "machine_temperature_c" || name == "air_temperature_c" ? j
                                                                      : j["uncertainty"])[name] = v;
    }
  }
  JsonFields f(j, errors);
  in.axis = f.String("axis", JsonFields::kRequired, 1).value_or("");
  in.ts_ms = f.Timestamp("ts").value_or(0);
  in.compensation_active = f.Bool("compensation_active").value_or(false);
  in.machine_temperature_c = f.Number("machine_temperature_c", JsonFields::kOptional, -40, 150);
  in.air_temperature_c = f.Number("air_temperature_c", JsonFields::kOptional, -40, 150);
  in.note = f.String("note", JsonFields::kOptional).value_or("");
  if (j.contains("uncertainty")) {
    JsonFields uf(j["uncertainty"], errors);
    UncertaintyFromFields(uf, in.uncertainty);
  }
}

json PositioningInputToJson(const PositioningInput& in) {
  json runs = json::array();
  for (const auto& r : in.data.runs) {
    runs.push_back(
        {{"direction", r.direction > 0 ? "+" : "-"}, {"deviations_um", r.deviations_um}});
  }
  const UncertaintyInputs& u = in.uncertainty;
  json j = {{"axis", in.axis},
            {"ts", FormatRfc3339(in.ts_ms)},
            {"targets_mm", in.data.targets_mm},
            {"runs", runs},
            {"compensation_active", in.compensation_active}};
  if (u.stated) {
    j["uncertainty"] = {{"device_um_per_m", u.device_um_per_m},
                        {"misalignment_mm", u.misalignment_mm},
                        {"alpha_um_per_m_c", u.alpha_um_per_m_c},
                        {"temperature_range_c", u.temperature_range_c},
                        {"delta_t_c", u.delta_t_c},
                        {"alpha_range_um_per_m_c", u.alpha_range_um_per_m_c},
                        {"e_ve_um", u.e_ve_um}};
  }
  if (in.machine_temperature_c) j["machine_temperature_c"] = *in.machine_temperature_c;
  if (in.air_temperature_c) j["air_temperature_c"] = *in.air_temperature_c;
  if (!in.note.empty()) j["note"] = in.note;
  return j;
}

json EvaluationToJson(const PositioningEvaluation& e) {
  const Iso230Result& r = e.iso;
  json per = json::array();
  for (const auto& p : r.positions) {
    per.push_back({{"target_mm", p.target_mm},
                   {"mean_up_um", p.mean_up_um},
                   {"mean_down_um", p.mean_down_um},
                   {"mean_um", p.mean_um},
                   {"s_up_um", p.s_up_um},
                   {"s_down_um", p.s_down_um},
                   {"reversal_um", p.reversal_um},
                   {"R_up_um", p.r_up_um},
                   {"R_down_um", p.r_down_um},
                   {"R_um", p.r_um},
                   {"U_um", p.u_um},
                   {"Ps_um", p.ps_um}});
  }
  const PositioningUncertainty& U = e.uncertainty;
  return {{"iso230_2",
           {{"A_um", r.A_um},
            {"A_up_um", r.A_up_um},
            {"A_down_um", r.A_down_um},
            {"E_um", r.E_um},
            {"E_up_um", r.E_up_um},
            {"E_down_um", r.E_down_um},
            {"M_um", r.M_um},
            {"R_um", r.R_um},
            {"R_up_um", r.R_up_um},
            {"R_down_um", r.R_down_um},
            {"B_um", r.B_um},
            {"B_mean_um", r.B_mean_um},
            {"runs_per_direction", r.runs_per_direction},
            {"per_position", per}}},
          {"vdi3441",
           {{"P_um", e.vdi.P_um},
            {"Pa_um", e.vdi.Pa_um},
            {"Ps_max_um", e.vdi.Ps_max_um},
            {"U_max_um", e.vdi.U_max_um},
            {"U_mean_um", e.vdi.U_mean_um}}},
          {"uncertainty_um",
           {{"stated", U.stated},
            {"A", U.A_um},
            {"E", U.E_um},
            {"M", U.M_um},
            {"R", U.R_um},
            {"R_up_down", U.R_up_down_um},
            {"B", U.B_um},
            {"components",
             {{"length_m", U.length_m},
              {"device", U.device_um},
              {"misalignment", U.misalignment_um},
              {"machine_M", U.machine_m_um},
              {"machine_E", U.machine_e_um},
              {"eve", U.eve_um}}}}}};
}

json ColumnResultToJson(const ColumnCheckResult& r) {
  json straightness = json::object();
  json details = json::object();
  json slopes = json::object();
  for (const auto& s : r.straightness) {
    straightness[s.scheme] = s.straightness_um;
    details[s.scheme] = s.relative_um;
    slopes[s.scheme] = s.slope_um_per_m;
  }
  json out = {
      {"machine_zero_mm",
       {{"X", r.machine_zero_mm.x}, {"Y", r.machine_zero_mm.y}, {"Z", r.machine_zero_mm.z}}},
      {"circle", {{"radius_mm", r.circle_radius_mm}, {"residual_um", r.circle_residual_um}}},
      {"straightness_um", straightness},
      {"straightness_reference", "least-squares straight line (ISO 230-1)"},
      {"straightness_points_um", details},
      {"straightness_line_slope_um_per_m", slopes}};
  if (r.parallelism_um_per_100mm) {
    out["spindle_z_parallelism_um_per_100mm"] = {{"X", r.parallelism_um_per_100mm->first},
                                                 {"Y", r.parallelism_um_per_100mm->second}};
  }
  return out;
}

}  // namespace thermocomp
