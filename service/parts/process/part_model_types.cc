#include "service/parts/process/part_model_types.h"

#include <cmath>

#include "model/neural/thermal_network.h"
#include "model/parts/process_quadratic.h"
#include "service/feed_axis/neural_type.h"

namespace thermocomp {
namespace {

// "input 2 does not vary" -> "input vc_m_min does not vary".
std::string NameInput(std::string message, const std::vector<std::string>& inputs) {
  for (size_t i = 0; i < inputs.size(); ++i) {
    const std::string index = "input " + std::to_string(i) + " ";
    if (message.rfind(index, 0) == 0) {
      return "input " + inputs[i] + message.substr(index.size() - 1);
    }
  }
  return message;
}

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

class QuadraticPartModel : public PartModel {
 public:
  QuadraticPartModel(std::string target, std::vector<PartInputRange> ranges, QuadraticFit fit)
      : PartModel(std::move(target), std::move(ranges)), fit_(std::move(fit)) {}
  std::string type() const override { return "quadratic"; }
  double training_rmse() const override { return fit_.training_rmse; }
  void Describe(PartTypeResult& r) const override {
    const std::vector<std::string> names = inputs();
    for (const QuadraticTerm& t : fit_.terms) r.terms.push_back(QuadraticTermName(t, names));
  }

 protected:
  double Evaluate(const Eigen::VectorXd& x) const override { return fit_.Predict(x); }
  nlohmann::json Body() const override {
    const std::vector<std::string> names = inputs();
    nlohmann::json terms = nlohmann::json::array();
    for (size_t k = 0; k < fit_.terms.size(); ++k) {
      terms.push_back({{"name", QuadraticTermName(fit_.terms[k], names)},
                       {"a", fit_.terms[k].a},
                       {"b", fit_.terms[k].b},
                       {"coefficient", fit_.coefficients[k]},
                       {"standard_error", fit_.standard_errors[k]}});
    }
    return {{"center", fit_.center},
            {"scale", fit_.scale},
            {"terms", std::move(terms)},
            {"residual_rms", fit_.residual_rms},
            {"training_rmse", fit_.training_rmse},
            {"training_rows", fit_.rows}};
  }

 private:
  QuadraticFit fit_;
};

class NeuralPartModel : public PartModel {
 public:
  NeuralPartModel(std::string target, std::vector<PartInputRange> ranges, ThermalNetwork net,
                  int rows)
      : PartModel(std::move(target), std::move(ranges)), net_(std::move(net)), rows_(rows) {}
  std::string type() const override { return "neural"; }
  double training_rmse() const override { return net_.training_rmse(); }
  void Describe(PartTypeResult& r) const override {
    r.hidden_units = net_.Parameters().hidden;
    r.effective_parameters = net_.effective_parameters();
  }

 protected:
  double Evaluate(const Eigen::VectorXd& x) const override { return net_.Predict(x); }
  nlohmann::json Body() const override {
    nlohmann::json j = NetworkToJson(net_);
    j["training_rows"] = rows_;
    return j;
  }

 private:
  ThermalNetwork net_;
  int rows_ = 0;
};

}  // namespace

StatusOr<std::shared_ptr<const PartModel>> QuadraticPartType::Fit(
    const PartTrainingSet& set, const PartFitOptions& options) const {
  StatusOr<QuadraticFit> fit = FitQuadraticBackward(set.x, set.y, options.t_min);
  if (!fit.ok()) return Status::Unprocessable(NameInput(fit.status().message(), set.inputs));
  return std::shared_ptr<const PartModel>(
      std::make_shared<QuadraticPartModel>(set.target, TrainedRanges(set), std::move(fit).value()));
}

StatusOr<std::shared_ptr<const PartModel>> QuadraticPartType::FromJson(
    const nlohmann::json& model_json) const {
  const nlohmann::json& j = model_json;
  auto header = ReadPartModelHeader(j);
  if (!header.ok()) return header.status();
  QuadraticFit fit;
  auto center = Numbers(j, "center"), scale = Numbers(j, "scale");
  const size_t d = header->ranges.size();
  if (!center || !scale || center->size() != d || scale->size() != d) {
    return Status::InvalidArgument("quadratic model: center and scale per input needed");
  }
  for (double s : *scale) {
    if (!(s > 0) || !std::isfinite(s)) return Status::InvalidArgument("quadratic model: scale");
  }
  fit.center = *center;
  fit.scale = *scale;
  auto terms = j.find("terms");
  if (terms == j.end() || !terms->is_array() || terms->empty()) {
    return Status::InvalidArgument("quadratic model: terms needed");
  }
  for (const nlohmann::json& t : *terms) {
    if (!t.is_object() || !t.value("a", nlohmann::json()).is_number_integer() ||
        !t.value("b", nlohmann::json()).is_number_integer() ||
        !t.value("coefficient", nlohmann::json()).is_number()) {
      return Status::InvalidArgument("quadratic model: a term needs a, b and coefficient");
    }
    const int a = t["a"].get<int>(), b = t["b"].get<int>();
    const int n = static_cast<int>(d);
    if (a < -1 || a >= n || b < -1 || b >= n || (a < 0 && b >= 0) || (b >= 0 && b < a)) {
      return Status::InvalidArgument("quadratic model: a term's inputs are out of range");
    }
    fit.terms.push_back({a, b});
    fit.coefficients.push_back(t["coefficient"].get<double>());
    fit.standard_errors.push_back(t.value("standard_error", 0.0));
  }
  fit.residual_rms = j.value("residual_rms", 0.0);
  fit.training_rmse = j.value("training_rmse", 0.0);
  fit.rows = j.value("training_rows", 0);
  return std::shared_ptr<const PartModel>(std::make_shared<QuadraticPartModel>(
      header->target, std::move(header->ranges), std::move(fit)));
}

StatusOr<std::shared_ptr<const PartModel>> NeuralPartType::Fit(
    const PartTrainingSet& set, const PartFitOptions& options) const {
  NetworkOptions o;
  o.hidden = options.neural_hidden;
  o.restarts = options.neural_restarts;
  o.seed = options.seed;
  o.range_margin = 0;  // the guard is the trained range itself (PartModel)
  auto net = ThermalNetwork::Train(set.x, set.y, o);
  if (!net.ok()) return Status::Unprocessable(NameInput(net.status().message(), set.inputs));
  return std::shared_ptr<const PartModel>(std::make_shared<NeuralPartModel>(
      set.target, TrainedRanges(set), std::move(net).value(), static_cast<int>(set.x.rows())));
}

StatusOr<std::shared_ptr<const PartModel>> NeuralPartType::FromJson(
    const nlohmann::json& model_json) const {
  const nlohmann::json& j = model_json;
  auto header = ReadPartModelHeader(j);
  if (!header.ok()) return header.status();
  auto net = NetworkFromJson(j);
  if (!net.ok()) return net.status();
  if (static_cast<size_t>(net->inputs()) != header->ranges.size()) {
    return Status::InvalidArgument("neural model: inputs do not match the network");
  }
  return std::shared_ptr<const PartModel>(
      std::make_shared<NeuralPartModel>(header->target, std::move(header->ranges),
                                        std::move(net).value(), j.value("training_rows", 0)));
}

}  // namespace thermocomp
