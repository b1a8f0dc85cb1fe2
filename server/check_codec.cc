#include "server/check_codec.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "server/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

std::optional<int64_t> Ts(const json& j) {
  if (j.is_number_integer()) return j.get<int64_t>();
  if (j.is_string()) return ParseRfc3339(j.get<std::string>());
  return std::nullopt;
}

// A number at j[key]; records an error (field path `where.key`) otherwise.
std::optional<double> Number(const json& j, const char* key, const std::string& where,
                             std::vector<FieldError>& errors, size_t index, bool required = true) {
  if (!j.contains(key)) {
    if (required) errors.push_back({index, where + key, "required number"});
    return std::nullopt;
  }
  if (!j[key].is_number() || !std::isfinite(j[key].get<double>())) {
    errors.push_back({index, where + key, "must be a finite number"});
    return std::nullopt;
  }
  return j[key].get<double>();
}

std::optional<Vec3> Xyz(const json& j, const std::string& where, std::vector<FieldError>& errors,
                        size_t index) {
  if (!j.is_object()) {
    errors.push_back({index, where, "must be an object {x, y, z}"});
    return std::nullopt;
  }
  auto x = Number(j, "x", where + ".", errors, index);
  auto y = Number(j, "y", where + ".", errors, index);
  auto z = Number(j, "z", where + ".", errors, index);
  if (!x || !y || !z) return std::nullopt;
  return Vec3{*x, *y, *z};
}

char AxisLetter(const json& j) {
  if (!j.is_string() || j.get<std::string>().size() != 1) return 0;
  const char c = j.get<std::string>()[0];
  return c == 'X' || c == 'Y' || c == 'Z' ? c : 0;
}

}  // namespace

std::optional<Artifact> ArtifactFromJson(const json& j, std::vector<FieldError>& errors) {
  Artifact a;
  if (!j.is_object() || !j.contains("points") || !j["points"].is_array() || j["points"].empty()) {
    errors.push_back({0, "points", "required: a non-empty array of artifact points"});
    return std::nullopt;
  }
  for (size_t i = 0; i < j["points"].size(); ++i) {
    const json& p = j["points"][i];
    if (!p.is_object() || !p.contains("id") || !p["id"].is_string()) {
      errors.push_back({i, "points.id", "required string"});
      continue;
    }
    ArtifactPoint ap;
    if (auto n = Xyz(p.value("nominal", json()), "points.nominal", errors, i)) ap.nominal = *n;
    if (p.contains("expansion")) {
      const json& e = p["expansion"];
      double* beta[] = {&ap.expansion.beta_x, &ap.expansion.beta_y, &ap.expansion.beta_z};
      double* b[] = {&ap.expansion.b_x, &ap.expansion.b_y, &ap.expansion.b_z};
      const char* dirs[] = {"x", "y", "z"};
      for (int d = 0; d < 3; ++d) {
        if (!e.is_object() || !e.contains(dirs[d])) continue;
        const std::string where = std::string("points.expansion.") + dirs[d] + ".";
        if (auto v = Number(e[dirs[d]], "beta_mm_per_c", where, errors, i)) *beta[d] = *v;
        if (auto v = Number(e[dirs[d]], "b_mm", where, errors, i)) *b[d] = *v;
      }
    }
    if (!a.points.emplace(p["id"].get<std::string>(), ap).second) {
      errors.push_back({i, "points.id", "duplicate point id"});
    }
  }
  if (j.contains("schemes")) {
    for (size_t i = 0; i < j["schemes"].size(); ++i) {
      const json& s = j["schemes"][i];
      StraightnessScheme sc;
      sc.id = s.value("id", "");
      sc.travel_axis = AxisLetter(s.value("travel_axis", json()));
      sc.deviation_axis = AxisLetter(s.value("deviation_axis", json()));
      sc.reference_point = s.value("reference_point", "");
      if (sc.id.empty() || !sc.travel_axis || !sc.deviation_axis ||
          !a.points.count(sc.reference_point)) {
        errors.push_back({i, "schemes",
                          "each needs id, travel_axis and deviation_axis (X, Y or Z) and a "
                          "reference_point that is one of the points"});
        continue;
      }
      a.schemes.push_back(sc);
    }
  }
  if (j.contains("table_centre")) {
    if (auto c = Xyz(j["table_centre"], "table_centre", errors, 0)) a.table_centre = *c;
  }
  if (!errors.empty()) return std::nullopt;
  return a;
}

std::optional<ColumnCheckInput> ColumnCheckFromJson(const json& j,
                                                    std::vector<FieldError>& errors) {
  ColumnCheckInput in;
  if (!j.is_object()) {
    errors.push_back({0, "body", "must be a JSON object"});
    return std::nullopt;
  }
  if (j.contains("request_id")) {
    if (!j["request_id"].is_number_integer()) {
      errors.push_back({0, "request_id", "must be an integer"});
    } else {
      in.request_id = j["request_id"].get<int64_t>();
    }
  }
  if (auto ts = Ts(j.value("ts", json()))) {
    in.ts_ms = *ts;
  } else {
    errors.push_back({0, "ts", "must be RFC 3339 UTC or integer Unix milliseconds"});
  }
  in.artifact = j.value("artifact", "");
  if (in.artifact.empty()) errors.push_back({0, "artifact", "required string"});
  if (auto t = Number(j, "artifact_temperature_c", "", errors, 0)) in.temperature_c = *t;
  if (!j.contains("spheres") || !j["spheres"].is_array()) {
    errors.push_back({0, "spheres", "required array of {sphere, b_deg, x, y, z}"});
  } else {
    for (size_t i = 0; i < j["spheres"].size(); ++i) {
      const json& s = j["spheres"][i];
      SphereProbe sp;
      sp.sphere = s.value("sphere", "");
      if (sp.sphere.empty()) errors.push_back({i, "spheres.sphere", "required string"});
      if (auto b = Number(s, "b_deg", "spheres.", errors, i)) sp.b_deg = *b;
      if (auto p = Xyz(s, "spheres", errors, i)) sp.position = *p;
      in.spheres.push_back(sp);
    }
  }
  if (j.contains("points")) {
    for (size_t i = 0; i < j["points"].size(); ++i) {
      const json& p = j["points"][i];
      SurfaceProbe sp;
      sp.point = p.value("id", "");
      sp.scheme = p.value("scheme", "");
      if (sp.point.empty() || sp.scheme.empty()) {
        errors.push_back({i, "points", "each needs id and scheme"});
      }
      if (auto v = Xyz(p, "points", errors, i)) sp.position = *v;
      in.points.push_back(sp);
    }
  }
  if (j.contains("parallelism")) {
    const json& p = j["parallelism"];
    ParallelismProbe pp;
    auto ball = Xyz(p.value("ball", json()), "parallelism.ball", errors, 0);
    auto shank = Xyz(p.value("shank", json()), "parallelism.shank", errors, 0);
    if (auto h = Number(p, "height_mm", "parallelism.", errors, 0, false)) pp.height_mm = *h;
    if (ball && shank) {
      pp.ball = *ball;
      pp.shank = *shank;
      in.parallelism = pp;
    }
  }
  if (!errors.empty()) return std::nullopt;
  return in;
}

std::optional<PositioningInput> PositioningFromJson(const json& j,
                                                    std::vector<FieldError>& errors) {
  PositioningInput in;
  if (!j.is_object()) {
    errors.push_back({0, "body", "must be a JSON object"});
    return std::nullopt;
  }
  in.axis = j.value("axis", "");
  if (in.axis.empty()) errors.push_back({0, "axis", "required string"});
  if (auto ts = Ts(j.value("ts", json()))) {
    in.ts_ms = *ts;
  } else {
    errors.push_back({0, "ts", "must be RFC 3339 UTC or integer Unix milliseconds"});
  }
  if (!j.contains("targets_mm") || !j["targets_mm"].is_array()) {
    errors.push_back({0, "targets_mm", "required array of numbers"});
  } else {
    for (const auto& t : j["targets_mm"]) {
      if (!t.is_number()) {
        errors.push_back({0, "targets_mm", "must hold numbers only"});
        break;
      }
      in.data.targets_mm.push_back(t.get<double>());
    }
  }
  if (!j.contains("runs") || !j["runs"].is_array()) {
    errors.push_back({0, "runs", "required array of {direction, deviations_um}"});
  } else {
    for (size_t i = 0; i < j["runs"].size(); ++i) {
      const json& r = j["runs"][i];
      PositioningRun run;
      const std::string dir = r.value("direction", "");
      if (dir != "+" && dir != "-")
        errors.push_back({i, "runs.direction", "must be \"+\" or \"-\""});
      run.direction = dir == "-" ? -1 : 1;
      if (!r.contains("deviations_um") || !r["deviations_um"].is_array()) {
        errors.push_back({i, "runs.deviations_um", "required array of numbers"});
      } else {
        for (const auto& v : r["deviations_um"]) {
          if (!v.is_number()) {
            errors.push_back({i, "runs.deviations_um", "must hold numbers only"});
            break;
          }
          run.deviations_um.push_back(v.get<double>());
        }
      }
      in.data.runs.push_back(run);
    }
  }
  in.compensation_active = j.value("compensation_active", false);
  if (j.contains("machine_temperature_c") && j["machine_temperature_c"].is_number())
    in.machine_temperature_c = j["machine_temperature_c"].get<double>();
  if (j.contains("air_temperature_c") && j["air_temperature_c"].is_number())
    in.air_temperature_c = j["air_temperature_c"].get<double>();
  if (j.contains("note") && j["note"].is_string()) in.note = j["note"].get<std::string>();
  if (j.contains("uncertainty")) {
    const json& u = j["uncertainty"];
    UncertaintyInputs& ui = in.uncertainty;
    const std::string w = "uncertainty.";
    std::pair<const char*, double*> fields[] = {
        {"device_um_per_m", &ui.device_um_per_m},
        {"misalignment_mm", &ui.misalignment_mm},
        {"alpha_um_per_m_c", &ui.alpha_um_per_m_c},
        {"temperature_range_c", &ui.temperature_range_c},
        {"delta_t_c", &ui.delta_t_c},
        {"alpha_range_um_per_m_c", &ui.alpha_range_um_per_m_c},
        {"e_ve_um", &ui.e_ve_um}};
    for (auto& [key, dest] : fields) {
      if (auto v = Number(u, key, w, errors, 0, false)) *dest = *v;
    }
  }
  if (!errors.empty()) return std::nullopt;
  return in;
}

bool PositioningFromCsv(const std::string& body, PositioningData& out,
                        std::vector<FieldError>& errors) {
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
            {"compensation_active", in.compensation_active},
            {"uncertainty",
             {{"device_um_per_m", u.device_um_per_m},
              {"misalignment_mm", u.misalignment_mm},
              {"alpha_um_per_m_c", u.alpha_um_per_m_c},
              {"temperature_range_c", u.temperature_range_c},
              {"delta_t_c", u.delta_t_c},
              {"alpha_range_um_per_m_c", u.alpha_range_um_per_m_c},
              {"e_ve_um", u.e_ve_um}}}};
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
           {{"A", U.A_um},
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
  for (const auto& s : r.straightness) {
    straightness[s.scheme] = s.straightness_um;
    details[s.scheme] = s.relative_um;
  }
  json out = {
      {"machine_zero_mm",
       {{"X", r.machine_zero_mm.x}, {"Y", r.machine_zero_mm.y}, {"Z", r.machine_zero_mm.z}}},
      {"circle", {{"radius_mm", r.circle_radius_mm}, {"residual_um", r.circle_residual_um}}},
      {"straightness_um", straightness},
      {"straightness_points_um", details}};
  if (r.parallelism_um_per_100mm) {
    out["spindle_z_parallelism_um_per_100mm"] = {{"X", r.parallelism_um_per_100mm->first},
                                                 {"Y", r.parallelism_um_per_100mm->second}};
  }
  return out;
}

}  // namespace thermocomp
