#include "model/parts/process_quadratic.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermocomp {
namespace {

double TermValue(const QuadraticTerm& t, const Eigen::Ref<const Eigen::VectorXd>& xs) {
  if (t.a < 0) return 1.0;
  if (t.b < 0) return xs(t.a);
  return xs(t.a) * xs(t.b);
}

bool Removable(const std::vector<QuadraticTerm>& terms, size_t k) {
  const QuadraticTerm& t = terms[k];
  if (t.a < 0) return false;  // the intercept stays
  if (t.b >= 0) return true;
  for (const QuadraticTerm& o : terms) {
    if (o.b >= 0 && (o.a == t.a || o.b == t.a)) return false;
  }
  return true;
}

}  // namespace

std::vector<QuadraticTerm> QuadraticTerms(int inputs, QuadraticStructure structure) {
  std::vector<QuadraticTerm> terms;
  const auto d = static_cast<size_t>(std::max(0, inputs));
  terms.reserve(1 + 2 * d + d * (d - (d > 0 ? 1 : 0)) / 2);
  terms.push_back({});
  for (int a = 0; a < inputs; ++a) terms.push_back({a, -1});
  if (structure == QuadraticStructure::kLinear) return terms;
  for (int a = 0; a < inputs; ++a) terms.push_back({a, a});
  if (structure == QuadraticStructure::kSquares) return terms;
  for (int a = 0; a < inputs; ++a) {
    for (int b = a + 1; b < inputs; ++b) terms.push_back({a, b});
  }
  return terms;
}

const char* QuadraticStructureName(QuadraticStructure structure) {
  switch (structure) {
    case QuadraticStructure::kLinear:
      return "linear";
    case QuadraticStructure::kSquares:
      return "linear and squares";
    case QuadraticStructure::kFull:
      return "full quadratic";
  }
  return "";
}

QuadraticStructure RichestQuadratic(int inputs, size_t rows, double rows_per_term) {
  for (QuadraticStructure s : {QuadraticStructure::kFull, QuadraticStructure::kSquares}) {
    if (static_cast<double>(rows) >=
        rows_per_term * static_cast<double>(QuadraticTerms(inputs, s).size())) {
      return s;
    }
  }
  return QuadraticStructure::kLinear;
}

std::string QuadraticTermName(const QuadraticTerm& t, const std::vector<std::string>& names) {
  if (t.a < 0) return "1";
  if (t.b < 0) return names[static_cast<size_t>(t.a)];
  if (t.a == t.b) return names[static_cast<size_t>(t.a)] + "^2";
  return names[static_cast<size_t>(t.a)] + "*" + names[static_cast<size_t>(t.b)];
}

double QuadraticFit::Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::VectorXd xs(x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    xs(k) = (x(k) - center[static_cast<size_t>(k)]) / scale[static_cast<size_t>(k)];
  }
  double v = 0;
  for (size_t k = 0; k < terms.size(); ++k) v += coefficients[k] * TermValue(terms[k], xs);
  return v;
}

double QuadraticFit::T(size_t term) const {
  const double se = standard_errors[term];
  return se > 0 && std::isfinite(se) ? coefficients[term] / se : 0.0;
}

StatusOr<QuadraticFit> FitQuadratic(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                    const std::vector<QuadraticTerm>& terms) {
  const Eigen::Index n = x.rows(), d = x.cols();
  const auto p = static_cast<Eigen::Index>(terms.size());
  if (y.size() != n) return Status::InvalidArgument("rows of inputs and target differ");
  if (!x.allFinite() || !y.allFinite()) return Status::Unprocessable("a value is not finite");
  if (n <= p) {
    return Status::Unprocessable("too few records: " + std::to_string(n) + " for " +
                                 std::to_string(p) + " terms (more records than terms needed)");
  }
  QuadraticFit fit;
  fit.terms = terms;
  fit.rows = static_cast<int>(n);
  fit.center.resize(static_cast<size_t>(d));
  fit.scale.resize(static_cast<size_t>(d));
  for (Eigen::Index k = 0; k < d; ++k) {
    const double lo = x.col(k).minCoeff(), hi = x.col(k).maxCoeff();
    if (!(hi > lo)) return Status::Unprocessable("input " + std::to_string(k) + " does not vary");
    fit.center[static_cast<size_t>(k)] = 0.5 * (lo + hi);
    fit.scale[static_cast<size_t>(k)] = 0.5 * (hi - lo);
  }
  Eigen::MatrixXd design(n, p);
  Eigen::VectorXd xs(d);
  for (Eigen::Index r = 0; r < n; ++r) {
    for (Eigen::Index k = 0; k < d; ++k) {
      xs(k) = (x(r, k) - fit.center[static_cast<size_t>(k)]) / fit.scale[static_cast<size_t>(k)];
    }
    for (Eigen::Index c = 0; c < p; ++c)
      design(r, c) = TermValue(terms[static_cast<size_t>(c)], xs);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  qr.setThreshold(1e-10);
  if (qr.rank() < p) {
    return Status::Unprocessable("the records cannot separate the " + std::to_string(p) +
                                 " terms (rank " + std::to_string(qr.rank()) +
                                 "): too few distinct settings");
  }
  const Eigen::VectorXd beta = qr.solve(y);
  const Eigen::VectorXd residual = y - design * beta;
  const double sse = residual.squaredNorm();
  const auto dof = static_cast<double>(n - p);
  const double s2 = sse / dof;
  fit.residual_rms = std::sqrt(s2);
  fit.training_rmse = std::sqrt(sse / static_cast<double>(n));
  const Eigen::MatrixXd cov =
      (design.transpose() * design).ldlt().solve(Eigen::MatrixXd::Identity(p, p)) * s2;
  fit.coefficients.assign(beta.data(), beta.data() + p);
  fit.standard_errors.resize(static_cast<size_t>(p));
  for (Eigen::Index c = 0; c < p; ++c) {
    fit.standard_errors[static_cast<size_t>(c)] = std::sqrt(std::max(0.0, cov(c, c)));
  }
  return fit;
}

StatusOr<QuadraticFit> FitQuadraticBackward(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                            double t_min) {
  const int d = static_cast<int>(x.cols());
  std::vector<QuadraticTerm> terms =
      QuadraticTerms(d, RichestQuadratic(d, static_cast<size_t>(x.rows()), 2.0));
  StatusOr<QuadraticFit> fit = FitQuadratic(x, y, terms);
  while (fit.ok()) {
    size_t weakest = terms.size();
    double weakest_t = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < terms.size(); ++k) {
      if (!Removable(terms, k)) continue;
      const double t = std::fabs(fit->T(k));
      if (t < weakest_t) {
        weakest_t = t;
        weakest = k;
      }
    }
    if (weakest == terms.size() || weakest_t >= t_min) break;
    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(weakest));
    fit = FitQuadratic(x, y, terms);
  }
  return fit;
}

}  // namespace thermocomp
