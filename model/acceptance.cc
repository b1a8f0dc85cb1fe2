#include "model/acceptance.h"

#include <cstdio>

namespace thermocomp {
namespace {

std::string Format(const char* fmt, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace

std::string AcceptanceVerdict::Summary() const {
  if (passed) return "passed acceptance";
  std::string s;
  for (const auto& r : reasons) s += (s.empty() ? "" : "; ") + r;
  return s;
}

AcceptanceVerdict CheckAcceptance(const LinearFit& fit, const AcceptanceRules& rules,
                                  std::optional<double> validation_r2) {
  AcceptanceVerdict v;
  auto fail = [&](std::string why) {
    v.passed = false;
    v.reasons.push_back(std::move(why));
  };
  if (fit.k == 0) fail("no significant term left");
  if (!(fit.r2 > rules.min_r2)) fail(Format("R2 %.4f not above %.2f", fit.r2, rules.min_r2));
  if (!(fit.adj_r2 > rules.min_adj_r2)) {
    fail(Format("adjusted R2 %.4f not above %.2f", fit.adj_r2, rules.min_adj_r2));
  }
  const int terms = fit.k + 1;
  if (fit.n < rules.min_observations_per_term * terms) {
    fail(Format("%.0f observations for %.0f terms", fit.n, terms) + " (need " +
         std::to_string(rules.min_observations_per_term) + " per term)");
  }
  if (!validation_r2) {
    fail("no held-out runs to validate on");
  } else if (rules.min_validation_r2 && !(*validation_r2 >= *rules.min_validation_r2)) {
    fail(Format("held-out R2 %.4f below %.2f", *validation_r2, *rules.min_validation_r2));
  }
  return v;
}

}  // namespace thermocomp
