#include "model/selection.h"

#include <algorithm>
#include <cstdio>

namespace thermocomp {
namespace {

std::string Threshold(const char* what, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s >= %g", what, v);
  return buf;
}

StatusOr<LinearFit> Fit(const Observations& obs, const std::vector<int>& rows,
                        const std::vector<std::string>& terms) {
  Observations sub = obs.Subset(rows, terms);
  return FitLinear(sub.x, sub.y, sub.names);
}

// Backward elimination; returns the kept terms and appends to `removed`.
StatusOr<std::vector<std::string>> Eliminate(const Observations& obs, const std::vector<int>& rows,
                                             std::vector<std::string> terms,
                                             const SelectionOptions& opt,
                                             std::vector<RemovedTerm>& removed) {
  while (!terms.empty()) {
    auto fit = Fit(obs, rows, terms);
    if (!fit.ok()) return fit.status();
    for (const auto& a : fit->aliased) {
      removed.push_back({a, "aliased (a linear combination of other terms)", 1, 0});
      terms.erase(std::find(terms.begin(), terms.end(), a));
    }
    const auto& stats = fit->terms;  // [0] intercept
    int worst_collinear = -1, worst_p = -1;
    for (size_t j = 1; j < stats.size(); ++j) {
      if (stats[j].vif >= opt.vif_max &&
          (worst_collinear < 0 || stats[j].p > stats[worst_collinear].p)) {
        worst_collinear = static_cast<int>(j);
      }
      if (stats[j].p >= opt.p_max && (worst_p < 0 || stats[j].p > stats[worst_p].p)) {
        worst_p = static_cast<int>(j);
      }
    }
    int drop = worst_collinear >= 0 ? worst_collinear : worst_p;
    if (drop < 0) return terms;
    const TermStats& s = stats[drop];
    removed.push_back(
        {s.name, worst_collinear >= 0 ? Threshold("VIF", opt.vif_max) : Threshold("p", opt.p_max),
         s.p, s.vif});
    terms.erase(std::find(terms.begin(), terms.end(), s.name));
  }
  return terms;
}

}  // namespace

StatusOr<SelectionResult> SelectModel(const Observations& obs, const SelectionOptions& opt) {
  SelectionResult result;
  result.rows = obs.AllRows();
  std::vector<std::string> terms = obs.names;
  for (int round = 0;; ++round) {
    if (opt.eliminate) {
      auto kept = Eliminate(obs, result.rows, terms, opt, result.removed);
      if (!kept.ok()) return kept.status();
      if (round > 0 && *kept == terms) break;
      terms = *kept;
    } else if (round > 0) {
      break;
    }
    // Outlier removal on the current term set.
    while (true) {
      auto fit = Fit(obs, result.rows, terms);
      if (!fit.ok()) return fit.status();
      const Eigen::VectorXd& r = fit->standardized_residuals;
      std::vector<int> over;
      for (int i = 0; i < r.size(); ++i) {
        if (std::fabs(r(i)) > opt.outlier_threshold) over.push_back(i);
      }
      if (over.empty()) break;
      std::stable_sort(over.begin(), over.end(),
                       [&](int a, int b) { return std::fabs(r(a)) > std::fabs(r(b)); });
      over.resize(std::min<size_t>(over.size(), opt.outliers_per_step));
      std::sort(over.begin(), over.end());
      for (auto it = over.rbegin(); it != over.rend(); ++it) {
        result.outlier_rows.push_back(result.rows[*it]);
        result.rows.erase(result.rows.begin() + *it);
      }
      ++result.outlier_steps;
    }
  }
  std::sort(result.outlier_rows.begin(), result.outlier_rows.end());
  result.terms = terms;
  auto fit = Fit(obs, result.rows, terms);
  if (!fit.ok()) return fit.status();
  result.fit = std::move(fit).value();
  return result;
}

}  // namespace thermocomp
