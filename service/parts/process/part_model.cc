#include "service/parts/process/part_model.h"

#include <cmath>
#include <cstdio>

namespace thermocomp {

std::vector<std::string> PartModel::inputs() const {
  std::vector<std::string> out;
  out.reserve(ranges_.size());
  for (const PartInputRange& r : ranges_) out.push_back(r.name);
  return out;
}

PartPrediction PartModel::Predict(const PartInputs& inputs) const {
  PartPrediction p;
  Eigen::VectorXd x(static_cast<Eigen::Index>(ranges_.size()));
  for (size_t k = 0; k < ranges_.size(); ++k) {
    const PartInputRange& r = ranges_[k];
    auto it = inputs.find(r.name);
    if (it == inputs.end() || !std::isfinite(it->second)) {
      p.missing.push_back(r.name);
      continue;
    }
    x(static_cast<Eigen::Index>(k)) = it->second;
    if (it->second < r.low || it->second > r.high) {
      p.outside.push_back({r.name, it->second, r.low, r.high});
    }
  }
  p.in_range = p.outside.empty();
  if (!p.missing.empty()) {
    p.reason = "input " + p.missing.front() + " not given (the model needs it)";
    return p;
  }
  if (!p.outside.empty()) {
    const PartOutOfRange& o = p.outside.front();
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "input %s = %g outside the trained range [%g, %g]: the model does not "
                  "extrapolate",
                  o.name.c_str(), o.value, o.low, o.high);
    p.reason = buf;
    if (p.outside.size() > 1)
      p.reason += " (and " + std::to_string(p.outside.size() - 1) + " more)";
    return p;
  }
  const double v = Evaluate(x);
  if (!std::isfinite(v)) {
    p.reason = "the model's value is not finite";
    return p;
  }
  p.valid = true;
  p.value = v;
  return p;
}

nlohmann::json PartModel::ToJson() const {
  nlohmann::json ranges = nlohmann::json::array();
  for (const PartInputRange& r : ranges_) {
    ranges.push_back({{"name", r.name}, {"low", r.low}, {"high", r.high}});
  }
  nlohmann::json j = Body();
  j["type"] = type();
  j["target"] = target_;
  j["inputs"] = inputs();
  j["ranges"] = std::move(ranges);
  return j;
}

std::vector<PartInputRange> TrainedRanges(const PartTrainingSet& set) {
  std::vector<PartInputRange> out;
  out.reserve(set.inputs.size());
  for (size_t k = 0; k < set.inputs.size(); ++k) {
    const auto col = set.x.col(static_cast<Eigen::Index>(k));
    out.push_back({set.inputs[k], col.minCoeff(), col.maxCoeff()});
  }
  return out;
}

StatusOr<PartModelHeader> ReadPartModelHeader(const nlohmann::json& j) {
  if (!j.is_object()) return Status::InvalidArgument("part model: not an object");
  PartModelHeader h;
  auto target = j.find("target");
  auto ranges = j.find("ranges");
  if (target == j.end() || !target->is_string() || ranges == j.end() || !ranges->is_array()) {
    return Status::InvalidArgument("part model: target and ranges needed");
  }
  h.target = target->get<std::string>();
  for (const nlohmann::json& r : *ranges) {
    if (!r.is_object() || !r.value("name", nlohmann::json()).is_string() ||
        !r.value("low", nlohmann::json()).is_number() ||
        !r.value("high", nlohmann::json()).is_number()) {
      return Status::InvalidArgument("part model: a range needs name, low and high");
    }
    h.ranges.push_back(
        {r["name"].get<std::string>(), r["low"].get<double>(), r["high"].get<double>()});
  }
  return h;
}

StatusOr<std::shared_ptr<const PartModel>> PartModelFromJson(const nlohmann::json& model_json) {
  if (!model_json.is_object() || !model_json.value("type", nlohmann::json()).is_string()) {
    return Status::InvalidArgument("part model: no type");
  }
  const PartModelType* type = FindPartModelType(model_json["type"].get<std::string>());
  if (!type) return Status::InvalidArgument("part model: unknown type");
  return type->FromJson(model_json);
}

}  // namespace thermocomp
