#include "model/neural/thermal_network.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <unsupported/Eigen/LevenbergMarquardt>

namespace thermocomp {
namespace {

// Weights per hidden unit j: d input weights, its bias, its output weight;
// then the output bias. `xs` holds scaled inputs, one row per sample.
struct Layout {
  int d = 0, hidden = 0;
  int size() const { return hidden * (d + 2) + 1; }
  int unit(int j) const { return j * (d + 2); }
};

double Forward(const Layout& l, const Eigen::VectorXd& w,
               const Eigen::Ref<const Eigen::RowVectorXd>& x, Eigen::VectorXd* h) {
  double out = w(l.size() - 1);
  for (int j = 0; j < l.hidden; ++j) {
    const int u = l.unit(j);
    const double a = x.dot(w.segment(u, l.d)) + w(u + l.d);
    (*h)(j) = std::tanh(a);
    out += w(u + l.d + 1) * (*h)(j);
  }
  return out;
}

// Residuals [√β·(ŷ − y); √α·w] for Eigen's LevenbergMarquardt, and their
// Jacobian.
struct Regularised : Eigen::DenseFunctor<double> {
  Regularised(const Layout& l, const Eigen::MatrixXd& xs, const Eigen::VectorXd& ys)
      : Eigen::DenseFunctor<double>(l.size(), static_cast<int>(xs.rows()) + l.size()),
        layout(l),
        x(xs),
        y(ys) {}

  int operator()(const Eigen::VectorXd& w, Eigen::VectorXd& r) const {
    const int n = static_cast<int>(x.rows());
    Eigen::VectorXd hidden(layout.hidden);
    for (int i = 0; i < n; ++i) r(i) = sqrt_beta * (Forward(layout, w, x.row(i), &hidden) - y(i));
    r.tail(layout.size()) = sqrt_alpha * w;
    return 0;
  }

  int df(const Eigen::VectorXd& w, Eigen::MatrixXd& jac) const {
    const int n = static_cast<int>(x.rows());
    jac.setZero();
    Eigen::VectorXd hidden(layout.hidden);
    for (int i = 0; i < n; ++i) {
      Forward(layout, w, x.row(i), &hidden);
      for (int j = 0; j < layout.hidden; ++j) {
        const int u = layout.unit(j);
        const double v = w(u + layout.d + 1);
        const double slope = v * (1.0 - hidden(j) * hidden(j));
        jac.row(i).segment(u, layout.d) = sqrt_beta * slope * x.row(i);
        jac(i, u + layout.d) = sqrt_beta * slope;
        jac(i, u + layout.d + 1) = sqrt_beta * hidden(j);
      }
      jac(i, layout.size() - 1) = sqrt_beta;
    }
    jac.bottomRows(layout.size()) =
        sqrt_alpha * Eigen::MatrixXd::Identity(layout.size(), layout.size());
    return 0;
  }

  Layout layout;
  const Eigen::MatrixXd& x;
  const Eigen::VectorXd& y;
  double sqrt_alpha = 0.1, sqrt_beta = 1.0;
};

struct Trained {
  Eigen::VectorXd w;
  double objective = std::numeric_limits<double>::infinity();
  double gamma = 0, sse = 0;
};

// One training from `w`: minimise F, re-estimate α and β from the
// evidence, until γ settles.
Trained TrainFrom(Regularised& f, Eigen::VectorXd w, int rounds) {
  const int n = static_cast<int>(f.x.rows());
  const int size = f.layout.size();
  double alpha = 0.01, beta = 1.0, gamma = size;
  for (int round = 0; round < rounds; ++round) {
    f.sqrt_alpha = std::sqrt(alpha);
    f.sqrt_beta = std::sqrt(beta);
    Eigen::LevenbergMarquardt<Regularised> lm(f);
    lm.setMaxfev(400);
    lm.minimize(w);
    Eigen::VectorXd r(n + size);
    f(w, r);
    const double ed = r.head(n).squaredNorm() / beta;
    const double ew = w.squaredNorm();
    Eigen::MatrixXd jac(n + size, size);
    f.sqrt_alpha = 0;  // the data part of the Hessian alone
    f.df(w, jac);
    const Eigen::MatrixXd data = jac.topRows(n).transpose() * jac.topRows(n) / beta;
    const Eigen::MatrixXd hessian =
        2.0 * beta * data + 2.0 * alpha * Eigen::MatrixXd::Identity(size, size);
    const double next_gamma =
        size - 2.0 * alpha * hessian.ldlt().solve(Eigen::MatrixXd::Identity(size, size)).trace();
    const double settled = std::fabs(next_gamma - gamma);
    gamma = std::clamp(next_gamma, 0.0, static_cast<double>(size));
    alpha = std::max(1e-12, gamma / (2.0 * std::max(ew, 1e-12)));
    beta = std::max(1e-12, (n - gamma) / (2.0 * std::max(ed, 1e-12)));
    if (round > 0 && settled < 0.01) break;
  }
  f.sqrt_alpha = std::sqrt(alpha);
  f.sqrt_beta = std::sqrt(beta);
  Eigen::VectorXd r(n + size);
  f(w, r);
  Trained t;
  t.w = w;
  t.gamma = gamma;
  t.sse = r.head(n).squaredNorm() / beta;
  t.objective = t.sse;  // compared on the data: α and β differ between restarts
  return t;
}

}  // namespace

int NetworkRange::Outside(const Eigen::Ref<const Eigen::VectorXd>& input) const {
  for (int i = 0; i < static_cast<int>(low.size()); ++i) {
    if (i >= input.size() || !std::isfinite(input(i)) || input(i) < low[i] || input(i) > high[i])
      return i;
  }
  return -1;
}

StatusOr<ThermalNetwork> ThermalNetwork::Train(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                               const NetworkOptions& options) {
  const int n = static_cast<int>(x.rows()), d = static_cast<int>(x.cols());
  if (options.hidden < 1 || d < 1)
    return Status::InvalidArgument("a network needs inputs and units");
  const Layout layout{d, options.hidden};
  if (y.size() != n) return Status::InvalidArgument("one output per input row");
  if (n < 2 * layout.size()) {
    return Status::Unprocessable("too few samples for the network: " + std::to_string(n) + " for " +
                                 std::to_string(layout.size()) + " weights");
  }
  if (!x.allFinite() || !y.allFinite()) return Status::Unprocessable("training data not finite");
  ThermalNetwork net;
  net.hidden_ = options.hidden;
  net.center_.resize(d);
  net.scale_.resize(d);
  for (int i = 0; i < d; ++i) {
    const double lo = x.col(i).minCoeff(), hi = x.col(i).maxCoeff();
    if (!(hi > lo)) {
      return Status::Unprocessable("input " + std::to_string(i) + " does not vary in training");
    }
    net.center_(i) = 0.5 * (lo + hi);
    net.scale_(i) = 0.5 * (hi - lo);
    const double margin = options.range_margin * (hi - lo);
    net.range_.low.push_back(lo - margin);
    net.range_.high.push_back(hi + margin);
  }
  net.y_center_ = y.mean();
  const double spread = std::sqrt((y.array() - net.y_center_).square().mean());
  net.y_scale_ = spread > 0 ? spread : 1.0;
  Eigen::MatrixXd xs(n, d);
  for (int i = 0; i < d; ++i) xs.col(i) = (x.col(i).array() - net.center_(i)) / net.scale_(i);
  const Eigen::VectorXd ys = (y.array() - net.y_center_) / net.y_scale_;

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> init(-0.5, 0.5);
  Trained best;
  for (int k = 0; k < std::max(1, options.restarts); ++k) {
    Eigen::VectorXd w(layout.size());
    for (int i = 0; i < w.size(); ++i) w(i) = init(rng);
    Regularised f(layout, xs, ys);
    Trained t = TrainFrom(f, w, options.evidence_rounds);
    if (t.w.allFinite() && t.objective < best.objective) best = t;
  }
  if (!std::isfinite(best.objective)) return Status::Unprocessable("the network did not train");
  net.w_ = best.w;
  net.gamma_ = best.gamma;
  net.rmse_ = std::sqrt(best.sse / n) * net.y_scale_;
  return net;
}

NetworkParameters ThermalNetwork::Parameters() const {
  NetworkParameters p;
  p.hidden = hidden_;
  p.weights.assign(w_.data(), w_.data() + w_.size());
  p.center.assign(center_.data(), center_.data() + center_.size());
  p.scale.assign(scale_.data(), scale_.data() + scale_.size());
  p.y_center = y_center_;
  p.y_scale = y_scale_;
  p.range = range_;
  p.effective_parameters = gamma_;
  p.training_rmse = rmse_;
  return p;
}

StatusOr<ThermalNetwork> ThermalNetwork::FromParameters(const NetworkParameters& p) {
  const int d = static_cast<int>(p.center.size());
  const Layout layout{d, p.hidden};
  if (p.hidden < 1 || d < 1) return Status::InvalidArgument("network: no units or no inputs");
  if (static_cast<int>(p.weights.size()) != layout.size()) {
    return Status::InvalidArgument("network: " + std::to_string(p.weights.size()) +
                                   " weights for " + std::to_string(layout.size()));
  }
  if (p.scale.size() != p.center.size() || p.range.low.size() != p.center.size() ||
      p.range.high.size() != p.center.size()) {
    return Status::InvalidArgument("network: scaling and range must have one value per input");
  }
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!finite(p.weights) || !finite(p.center) || !finite(p.range.low) || !finite(p.range.high) ||
      !std::isfinite(p.y_center) || !(p.y_scale > 0) || !std::isfinite(p.y_scale) ||
      !std::all_of(p.scale.begin(), p.scale.end(),
                   [](double x) { return x > 0 && std::isfinite(x); })) {
    return Status::InvalidArgument("network: a value is not finite or a scale not positive");
  }
  ThermalNetwork net;
  net.hidden_ = p.hidden;
  net.w_ = Eigen::Map<const Eigen::VectorXd>(p.weights.data(), layout.size());
  net.center_ = Eigen::Map<const Eigen::VectorXd>(p.center.data(), d);
  net.scale_ = Eigen::Map<const Eigen::VectorXd>(p.scale.data(), d);
  net.y_center_ = p.y_center;
  net.y_scale_ = p.y_scale;
  net.range_ = p.range;
  net.gamma_ = p.effective_parameters;
  net.rmse_ = p.training_rmse;
  return net;
}

double ThermalNetwork::Predict(const Eigen::Ref<const Eigen::VectorXd>& input) const {
  const Layout layout{inputs(), hidden_};
  const Eigen::RowVectorXd xs = ((input - center_).array() / scale_.array()).matrix().transpose();
  Eigen::VectorXd h(hidden_);
  return y_center_ + y_scale_ * Forward(layout, w_, xs, &h);
}

}  // namespace thermocomp
