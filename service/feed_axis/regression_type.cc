#include "service/feed_axis/regression_type.h"

#include <cmath>

#include <Eigen/Dense>

namespace thermocomp {
namespace {

struct Input {
  std::string name;
  double reference_c = 0;
};

struct Coefficients {
  double intercept = 0, slope = 0;
  std::vector<double> b, c;
};

class RegressionFeedModel : public FeedModel {
 public:
  RegressionFeedModel(std::vector<Input> inputs, Coefficients k, double rmse, int targets)
      : inputs_(std::move(inputs)), k_(std::move(k)), rmse_(rmse), targets_(targets) {}
  std::string type() const override { return "regression"; }

  std::vector<FeedPrediction> Predict(const FeedTemperatures& t,
                                      const std::vector<double>& position_mm) const override {
    std::vector<FeedPrediction> out(position_mm.size());
    std::vector<double> rise;
    for (const Input& in : inputs_) {
      auto it = t.find(in.name);
      if (it == t.end() || !std::isfinite(it->second)) {
        for (auto& p : out) p = {0, false, "sensor " + in.name + ": no temperature", ""};
        return out;
      }
      rise.push_back(it->second - in.reference_c);
    }
    for (size_t i = 0; i < position_mm.size(); ++i) {
      const double x = position_mm[i];
      double e = k_.intercept + k_.slope * x;
      for (size_t s = 0; s < rise.size(); ++s) e += rise[s] * (k_.b[s] + k_.c[s] * x);
      if (std::isfinite(e)) {
        out[i].error_um = e;
      } else {
        out[i] = {0, false, "position not finite", ""};
      }
    }
    return out;
  }

  nlohmann::json ToJson() const override {
    nlohmann::json inputs = nlohmann::json::array();
    for (const Input& in : inputs_) {
      inputs.push_back({{"name", in.name}, {"reference_c", in.reference_c}});
    }
    return {{"type", "regression"},
            {"inputs", inputs},
            {"intercept_um", k_.intercept},
            {"slope_um_per_mm", k_.slope},
            {"b_um_per_k", k_.b},
            {"c_um_per_k_mm", k_.c},
            {"coefficients", 2 + 2 * inputs_.size()},
            {"training_rmse_um", rmse_},
            {"training_targets", targets_}};
  }

 private:
  std::vector<Input> inputs_;
  Coefficients k_;
  double rmse_ = 0;
  int targets_ = 0;
};

}  // namespace

StatusOr<std::shared_ptr<const FeedModel>> RegressionFeedType::Fit(
    const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
    const std::vector<FeedCheck>& training, std::shared_ptr<const FeedModel> /*fallback*/) const {
  std::vector<Input> inputs;
  for (const ScrewSensor& s : axis.sensors) inputs.push_back({s.name, s.reference_c});
  for (const std::string& b : body_sensors) inputs.push_back({b, 0.0});
  const int p = 2 + 2 * static_cast<int>(inputs.size());
  int n = 0;
  for (const FeedCheck& c : training) n += static_cast<int>(c.position_mm.size());
  if (n <= p) {
    return Status::Unprocessable("too few targets for the regression: " + std::to_string(n) +
                                 " for " + std::to_string(p) + " coefficients");
  }
  Eigen::MatrixXd x(n, p);
  Eigen::VectorXd y(n);
  int r = 0;
  for (const FeedCheck& c : training) {
    for (size_t k = 0; k < c.position_mm.size(); ++k, ++r) {
      const double pos = c.position_mm[k];
      x(r, 0) = 1;
      x(r, 1) = pos;
      for (size_t s = 0; s < inputs.size(); ++s) {
        auto it = c.temperature_c.find(inputs[s].name);
        if (it == c.temperature_c.end()) {
          return Status::Unprocessable("check " + std::to_string(c.check_id) + ": sensor " +
                                       inputs[s].name + " has no temperature");
        }
        const double rise = it->second - inputs[s].reference_c;
        x(r, 2 + 2 * static_cast<int>(s)) = rise;
        x(r, 3 + 2 * static_cast<int>(s)) = rise * pos;
      }
      y(r) = c.error_um[k];
    }
  }
  if (!x.allFinite() || !y.allFinite()) return Status::Unprocessable("training data not finite");
  // Columns scaled to unit RMS so that positions in mm and rises in K weigh
  // alike; the minimum-norm solution keeps collinear sensors (neighbours
  // that read alike) bounded instead of failing.
  Eigen::VectorXd scale(p);
  for (int j = 0; j < p; ++j) {
    const double norm = x.col(j).norm() / std::sqrt(static_cast<double>(n));
    scale(j) = norm > 0 ? norm : 1.0;
  }
  const Eigen::MatrixXd xs = x * scale.cwiseInverse().asDiagonal();
  const Eigen::VectorXd beta = xs.completeOrthogonalDecomposition().solve(y).cwiseQuotient(scale);
  if (!beta.allFinite()) return Status::Unprocessable("the regression is not finite");
  const double rmse = std::sqrt((x * beta - y).squaredNorm() / n);
  Coefficients k;
  k.intercept = beta(0);
  k.slope = beta(1);
  for (size_t s = 0; s < inputs.size(); ++s) {
    k.b.push_back(beta(2 + 2 * static_cast<int>(s)));
    k.c.push_back(beta(3 + 2 * static_cast<int>(s)));
  }
  return std::shared_ptr<const FeedModel>(
      std::make_shared<RegressionFeedModel>(std::move(inputs), std::move(k), rmse, n));
}

StatusOr<std::shared_ptr<const FeedModel>> RegressionFeedType::FromJson(
    const ScrewAxis& /*axis*/, const nlohmann::json& model_json,
    std::shared_ptr<const FeedModel> /*fallback*/) const {
  auto bad = [](const std::string& what) {
    return Status::InvalidArgument("regression model: " + what);
  };
  if (!model_json.is_object() || !model_json.contains("inputs") || !model_json["inputs"].is_array())
    return bad("inputs");
  std::vector<Input> inputs;
  for (const auto& in : model_json["inputs"]) {
    if (!in.is_object() || !in.value("name", nlohmann::json()).is_string() ||
        !in.value("reference_c", nlohmann::json()).is_number()) {
      return bad("inputs");
    }
    inputs.push_back({in["name"].get<std::string>(), in["reference_c"].get<double>()});
  }
  Coefficients k;
  auto number = [&](const char* key, double* out) {
    auto it = model_json.find(key);
    if (it == model_json.end() || !it->is_number() || !std::isfinite(it->get<double>()))
      return false;
    *out = it->get<double>();
    return true;
  };
  auto numbers = [&](const char* key, std::vector<double>* out) {
    auto it = model_json.find(key);
    if (it == model_json.end() || !it->is_array() || it->size() != inputs.size()) return false;
    for (const auto& v : *it) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) return false;
      out->push_back(v.get<double>());
    }
    return true;
  };
  if (!number("intercept_um", &k.intercept)) return bad("intercept_um");
  if (!number("slope_um_per_mm", &k.slope)) return bad("slope_um_per_mm");
  if (!numbers("b_um_per_k", &k.b)) return bad("b_um_per_k");
  if (!numbers("c_um_per_k_mm", &k.c)) return bad("c_um_per_k_mm");
  return std::shared_ptr<const FeedModel>(std::make_shared<RegressionFeedModel>(
      std::move(inputs), std::move(k), model_json.value("training_rmse_um", 0.0),
      model_json.value("training_targets", 0)));
}

}  // namespace thermocomp
