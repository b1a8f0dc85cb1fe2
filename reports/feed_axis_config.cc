#include "reports/feed_axis_config.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "reports/json_fields.h"

namespace thermocomp {
namespace {

// Bounds that keep a configuration, and the tables made from it, small: a
// screw with more sensors than this is a typo, and 1 mm steps over a 20 m
// screw are 20 000 table points.
constexpr size_t kMaxSensors = 64;
constexpr size_t kMaxTypes = 16;
constexpr double kMinSpacingMm = 1;
constexpr double kMaxSpacingMm = 20000;
constexpr size_t kMaxNameLength = 64;

std::string Indexed(const std::string& list, size_t i) {
  return list + "[" + std::to_string(i) + "]";
}

// ValidateScrewAxis names a sensor's field "screw.sensors.x_mm" with the
// sensor's index beside it; the API names it "screw.sensors[1].x_mm".
std::string ApiField(const FieldError& e) {
  const std::string prefix = "screw.sensors.";
  if (e.field.rfind(prefix, 0) != 0) return e.field;
  return Indexed("screw.sensors", e.index) + "." + e.field.substr(prefix.size());
}

void ReadSensors(JsonFields& f, FeedAxisConfig& c) {
  const nlohmann::json* list = f.Array("sensors");
  if (!list) return;
  if (list->size() > kMaxSensors) {
    f.Error("screw.sensors", "at most " + std::to_string(kMaxSensors) + " screw sensors");
    return;
  }
  for (size_t i = 0; i < list->size(); ++i) {
    JsonFields s = f.Item((*list)[i], 0, Indexed("screw.sensors", i) + ".");
    if (!s.IsObject()) continue;
    ScrewSensor sensor;
    sensor.name = s.String("name", JsonFields::kRequired, kMaxNameLength).value_or("");
    // A NaN or infinity cannot pass: JsonFields::Number wants it finite.
    sensor.x_mm = s.Number("x_mm").value_or(0);
    sensor.reference_c = s.Number("reference_c", JsonFields::kOptional).value_or(20);
    c.screw.sensors.push_back(std::move(sensor));
  }
}

void ReadStiffness(JsonFields& f, FeedAxisConfig& c) {
  const bool ratio = f.Has("stiffness_ratio");
  const bool bearing = f.Has("bearing_stiffness_n_per_um");
  const bool screw = f.Has("screw_stiffness_n_per_um");
  if (c.screw.arrangement != BearingArrangement::kPreloaded) {
    for (const char* key :
         {"stiffness_ratio", "bearing_stiffness_n_per_um", "screw_stiffness_n_per_um"}) {
      if (f.Has(key)) f.Error(std::string("screw.") + key, "only for a preloaded screw");
    }
    return;
  }
  if (ratio && (bearing || screw)) {
    f.Error("screw.stiffness_ratio",
            "give either stiffness_ratio or both stiffnesses (bearing_stiffness_n_per_um, "
            "screw_stiffness_n_per_um), not both");
    return;
  }
  if (ratio) {
    // The range [0, 0.5] is ValidateScrewAxis's to state.
    c.screw.stiffness_ratio = f.Number("stiffness_ratio").value_or(NAN);
    return;
  }
  if (!bearing && !screw) {
    f.Error("screw.stiffness_ratio",
            "required for a preloaded screw (or bearing_stiffness_n_per_um and "
            "screw_stiffness_n_per_um)");
    return;
  }
  constexpr double kMaxStiffness = 1e6;  // N/µm; a real bearing is 100-2000
  auto kl = f.Number("bearing_stiffness_n_per_um", JsonFields::kRequired, 0, kMaxStiffness);
  auto ks = f.Number("screw_stiffness_n_per_um", JsonFields::kRequired, 0, kMaxStiffness);
  if (kl && *kl <= 0) f.Error("screw.bearing_stiffness_n_per_um", "must be above 0");
  if (ks && *ks <= 0) f.Error("screw.screw_stiffness_n_per_um", "must be above 0");
  if (kl && ks && *kl > 0 && *ks > 0) {
    c.bearing_stiffness_n_per_um = kl;
    c.screw_stiffness_n_per_um = ks;
    c.screw.stiffness_ratio = StiffnessRatio(*kl, *ks);
  } else {
    c.screw.stiffness_ratio = 0;  // already reported; keeps ValidateScrewAxis quiet about it
  }
}

void ReadTypes(JsonFields& f, const std::vector<std::string>& known_types, FeedAxisConfig& c) {
  const nlohmann::json* list = f.Array("types", JsonFields::kOptional);
  if (!list) return;
  if (list->empty() || list->size() > kMaxTypes) {
    f.Error("screw.types",
            "list one to " + std::to_string(kMaxTypes) + " model types, or leave it out for all");
    return;
  }
  std::set<std::string> seen;
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string field = Indexed("screw.types", i);
    const nlohmann::json& t = (*list)[i];
    if (!t.is_string() || std::find(known_types.begin(), known_types.end(), t.get<std::string>()) ==
                              known_types.end()) {
      std::string known;
      for (const std::string& type : known_types) known += (known.empty() ? "" : ", ") + type;
      f.Error(field, "must be a model type: " + known);
    } else if (!seen.insert(t.get<std::string>()).second) {
      f.Error(field, "listed twice");
    } else {
      c.types.push_back(t.get<std::string>());
    }
  }
}

void ReadBodySensors(JsonFields& f, FeedAxisConfig& c) {
  const nlohmann::json* list = f.Array("body_sensors", JsonFields::kOptional);
  if (!list) return;
  if (list->size() > kMaxSensors) {
    f.Error("screw.body_sensors", "at most " + std::to_string(kMaxSensors) + " body sensors");
    return;
  }
  for (size_t i = 0; i < list->size(); ++i) {
    const nlohmann::json& n = (*list)[i];
    if (!n.is_string() || n.get_ref<const std::string&>().empty() ||
        n.get_ref<const std::string&>().size() > kMaxNameLength) {
      f.Error(Indexed("screw.body_sensors", i), "must name a sensor");
      continue;
    }
    c.body_sensors.push_back(n.get<std::string>());
  }
}

// A sensor named twice would be one temperature counted as two inputs.
void CheckNamesOnce(const FeedAxisConfig& c, FieldErrors& errors) {
  std::set<std::string> seen;
  for (size_t i = 0; i < c.screw.sensors.size(); ++i) {
    const std::string& name = c.screw.sensors[i].name;
    if (!name.empty() && !seen.insert(name).second) {
      errors.push_back(
          {0, Indexed("screw.sensors", i) + ".name", "sensor " + name + " listed twice"});
    }
  }
  for (size_t i = 0; i < c.body_sensors.size(); ++i) {
    if (!seen.insert(c.body_sensors[i]).second) {
      errors.push_back(
          {0, Indexed("screw.body_sensors", i), "sensor " + c.body_sensors[i] + " listed twice"});
    }
  }
}

}  // namespace

std::vector<std::string> FeedAxisConfig::SensorNames() const {
  std::vector<std::string> out;
  for (const ScrewSensor& s : screw.sensors) out.push_back(s.name);
  out.insert(out.end(), body_sensors.begin(), body_sensors.end());
  return out;
}

StatusOr<FeedAxisConfig> FeedAxisConfigFromJson(const nlohmann::json& j,
                                                const std::vector<std::string>& known_types,
                                                FieldErrors* errors) {
  FieldErrors e;
  FeedAxisConfig c;
  JsonFields f(j, e, 0, "screw.");
  if (!j.is_object()) {
    e.push_back({0, "screw", "must be a JSON object"});
  } else {
    if (auto a = f.String("arrangement", JsonFields::kRequired, 32)) {
      if (!ParseBearingArrangement(*a, &c.screw.arrangement)) {
        f.Error("screw.arrangement", "must be \"fixed_floating\" or \"preloaded\"");
      }
    }
    // Read as numbers here; their ranges are ValidateScrewAxis's, which names
    // the same fields. A value that is not a finite number is reported here
    // and replaced by NaN, which ValidateScrewAxis would report again: the
    // duplicates are dropped below.
    c.screw.bearing_distance_mm = f.Number("bearing_distance_mm").value_or(NAN);
    c.screw.zero_mm = f.Number("zero_mm", JsonFields::kOptional).value_or(0);
    if (f.Has("zero_mm") && !j["zero_mm"].is_number()) c.screw.zero_mm = NAN;
    c.screw.direction = static_cast<int>(
        f.Integer("direction", JsonFields::kOptional, -1, 1).value_or(f.Has("direction") ? 0 : 1));
    c.screw.alpha_um_per_m_k = f.Number("alpha_um_per_m_k", JsonFields::kOptional).value_or(11.5);
    if (f.Has("alpha_um_per_m_k") && !j["alpha_um_per_m_k"].is_number()) {
      c.screw.alpha_um_per_m_k = NAN;
    }
    ReadStiffness(f, c);
    ReadSensors(f, c);
    ReadBodySensors(f, c);
    ReadTypes(f, known_types, c);
    c.reference_check_id = f.Integer("reference_check_id", JsonFields::kOptional, 1, INT64_MAX);
    c.table_spacing_mm =
        f.Number("table_spacing_mm", JsonFields::kOptional, kMinSpacingMm, kMaxSpacingMm);
    std::set<std::string> named;
    for (const FieldError& err : e) named.insert(err.field);
    for (const FieldError& err : ValidateScrewAxis(c.screw)) {
      const std::string field = ApiField(err);
      if (named.insert(field).second) e.push_back({0, field, err.message});
    }
    CheckNamesOnce(c, e);
  }
  if (!e.empty()) {
    if (errors) *errors = e;
    return Status::InvalidArgument("invalid screw configuration");
  }
  return c;
}

nlohmann::json FeedAxisConfigToJson(const FeedAxisConfig& c) {
  nlohmann::json j = {{"arrangement", BearingArrangementName(c.screw.arrangement)},
                      {"bearing_distance_mm", c.screw.bearing_distance_mm},
                      {"zero_mm", c.screw.zero_mm},
                      {"direction", c.screw.direction},
                      {"alpha_um_per_m_k", c.screw.alpha_um_per_m_k}};
  if (c.screw.arrangement == BearingArrangement::kPreloaded) {
    if (c.bearing_stiffness_n_per_um && c.screw_stiffness_n_per_um) {
      j["bearing_stiffness_n_per_um"] = *c.bearing_stiffness_n_per_um;
      j["screw_stiffness_n_per_um"] = *c.screw_stiffness_n_per_um;
    } else {
      j["stiffness_ratio"] = c.screw.stiffness_ratio;
    }
  }
  nlohmann::json sensors = nlohmann::json::array();
  for (const ScrewSensor& s : c.screw.sensors) {
    sensors.push_back({{"name", s.name}, {"x_mm", s.x_mm}, {"reference_c", s.reference_c}});
  }
  j["sensors"] = std::move(sensors);
  j["body_sensors"] = c.body_sensors;
  if (c.reference_check_id) j["reference_check_id"] = *c.reference_check_id;
  if (c.table_spacing_mm) j["table_spacing_mm"] = *c.table_spacing_mm;
  if (!c.types.empty()) j["types"] = c.types;
  return j;
}

}  // namespace thermocomp
