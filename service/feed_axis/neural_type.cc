#include "service/feed_axis/neural_type.h"

#include <cmath>
#include <cstdio>

#include "service/feed_axis/screw_type.h"

namespace thermocomp {
namespace {

constexpr const char* kPosition = "position_mm";

class NeuralFeedModel : public FeedModel {
 public:
  NeuralFeedModel(std::vector<std::string> inputs, ThermalNetwork net, int targets,
                  std::shared_ptr<const FeedModel> fallback)
      : inputs_(std::move(inputs)),
        net_(std::move(net)),
        targets_(targets),
        fallback_(std::move(fallback)) {}
  std::string type() const override { return "neural"; }

  std::vector<FeedPrediction> Predict(const FeedTemperatures& t,
                                      const std::vector<double>& position_mm) const override {
    std::vector<FeedPrediction> out(position_mm.size());
    Eigen::VectorXd x(inputs_.size());
    std::string missing;
    for (size_t k = 1; k < inputs_.size() && missing.empty(); ++k) {
      auto it = t.find(inputs_[k]);
      if (it == t.end() || !std::isfinite(it->second)) {
        missing = "sensor " + inputs_[k] + ": no temperature";
      } else {
        x(static_cast<int>(k)) = it->second;
      }
    }
    for (size_t i = 0; i < position_mm.size(); ++i) {
      std::string reason = missing;
      if (reason.empty()) {
        x(0) = position_mm[i];
        if (int k = net_.range().Outside(x); k >= 0) {
          char buf[200];
          std::snprintf(buf, sizeof buf, "input %s = %g outside the trained range [%g, %g]",
                        inputs_[k].c_str(), x(k), net_.range().low[k], net_.range().high[k]);
          reason = buf;
        }
      }
      if (reason.empty()) {
        out[i].error_um = net_.Predict(x);
        continue;
      }
      out[i].reason = reason;
      if (fallback_) {
        const FeedPrediction f = fallback_->Predict(t, {position_mm[i]}).front();
        if (f.valid) {
          out[i].error_um = f.error_um;
          out[i].fallback = fallback_->type();
          continue;
        }
        out[i].reason += "; fallback: " + f.reason;
      }
      out[i].valid = false;
    }
    return out;
  }

  nlohmann::json ToJson() const override {
    nlohmann::json j = NetworkToJson(net_);
    j["type"] = "neural";
    j["inputs"] = inputs_;
    j["training_targets"] = targets_;
    j["fallback"] = fallback_ ? fallback_->ToJson() : nlohmann::json(nullptr);
    return j;
  }

 private:
  std::vector<std::string> inputs_;  // kPosition, then sensor names
  ThermalNetwork net_;
  int targets_ = 0;
  std::shared_ptr<const FeedModel> fallback_;
};

std::optional<std::vector<double>> Numbers(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_array()) return std::nullopt;
  std::vector<double> out;
  for (const auto& v : *it) {
    if (!v.is_number()) return std::nullopt;
    out.push_back(v.get<double>());
  }
  return out;
}

}  // namespace

nlohmann::json NetworkToJson(const ThermalNetwork& net) {
  const NetworkParameters p = net.Parameters();
  return {{"hidden", p.hidden},
          {"weights", p.weights},
          {"center", p.center},
          {"scale", p.scale},
          {"y_center", p.y_center},
          {"y_scale", p.y_scale},
          {"range", {{"low", p.range.low}, {"high", p.range.high}}},
          {"effective_parameters", p.effective_parameters},
          {"training_rmse_um", p.training_rmse}};
}

StatusOr<ThermalNetwork> NetworkFromJson(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("range") || !j["range"].is_object()) {
    return Status::InvalidArgument("network: not an object with a range");
  }
  NetworkParameters p;
  auto w = Numbers(j, "weights"), c = Numbers(j, "center"), s = Numbers(j, "scale");
  auto lo = Numbers(j["range"], "low"), hi = Numbers(j["range"], "high");
  if (!w || !c || !s || !lo || !hi || !j.value("hidden", nlohmann::json()).is_number_integer()) {
    return Status::InvalidArgument("network: hidden, weights, center, scale and range needed");
  }
  p.hidden = j["hidden"].get<int>();
  p.weights = *w;
  p.center = *c;
  p.scale = *s;
  p.range.low = *lo;
  p.range.high = *hi;
  p.y_center = j.value("y_center", NAN);
  p.y_scale = j.value("y_scale", NAN);
  p.effective_parameters = j.value("effective_parameters", 0.0);
  p.training_rmse = j.value("training_rmse_um", 0.0);
  return ThermalNetwork::FromParameters(p);
}

StatusOr<std::shared_ptr<const FeedModel>> NeuralFeedType::Fit(
    const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
    const std::vector<FeedCheck>& training, std::shared_ptr<const FeedModel> fallback) const {
  std::vector<std::string> inputs = {kPosition};
  for (const ScrewSensor& s : axis.sensors) inputs.push_back(s.name);
  for (const std::string& b : body_sensors) inputs.push_back(b);
  int n = 0;
  for (const FeedCheck& c : training) n += static_cast<int>(c.position_mm.size());
  Eigen::MatrixXd x(n, inputs.size());
  Eigen::VectorXd y(n);
  int r = 0;
  for (const FeedCheck& c : training) {
    for (size_t k = 0; k < c.position_mm.size(); ++k, ++r) {
      x(r, 0) = c.position_mm[k];
      for (size_t i = 1; i < inputs.size(); ++i) {
        auto it = c.temperature_c.find(inputs[i]);
        if (it == c.temperature_c.end()) {
          return Status::Unprocessable("check " + std::to_string(c.check_id) + ": sensor " +
                                       inputs[i] + " has no temperature");
        }
        x(r, static_cast<int>(i)) = it->second;
      }
      y(r) = c.error_um[k];
    }
  }
  auto net = ThermalNetwork::Train(x, y, options_);
  if (!net.ok()) {
    // Name the input, not its index.
    std::string message = net.status().message();
    for (size_t i = 0; i < inputs.size(); ++i) {
      const std::string index = "input " + std::to_string(i) + " ";
      if (message.rfind(index, 0) == 0)
        message = "input " + inputs[i] + message.substr(index.size() - 1);
    }
    return Status::Unprocessable(message);
  }
  return std::shared_ptr<const FeedModel>(
      std::make_shared<NeuralFeedModel>(inputs, std::move(net).value(), n, std::move(fallback)));
}

StatusOr<std::shared_ptr<const FeedModel>> NeuralFeedType::FromJson(
    const ScrewAxis& axis, const nlohmann::json& model_json,
    std::shared_ptr<const FeedModel> fallback) const {
  if (!model_json.is_object()) return Status::InvalidArgument("neural model: not an object");
  auto net = NetworkFromJson(model_json);
  if (!net.ok()) return net.status();
  std::vector<std::string> inputs;
  if (auto it = model_json.find("inputs"); it != model_json.end() && it->is_array()) {
    for (const auto& v : *it) {
      if (!v.is_string()) return Status::InvalidArgument("neural model: inputs");
      inputs.push_back(v.get<std::string>());
    }
  }
  if (static_cast<int>(inputs.size()) != net->inputs() || inputs.empty() ||
      inputs[0] != kPosition) {
    return Status::InvalidArgument("neural model: inputs do not match the network");
  }
  if (!fallback) {
    if (auto it = model_json.find("fallback"); it != model_json.end() && it->is_object()) {
      auto stored = ScrewFeedType().FromJson(axis, *it, nullptr);
      if (!stored.ok()) return stored.status();
      fallback = *stored;
    }
  }
  return std::shared_ptr<const FeedModel>(std::make_shared<NeuralFeedModel>(
      inputs, std::move(net).value(), model_json.value("training_targets", 0),
      std::move(fallback)));
}

}  // namespace thermocomp
