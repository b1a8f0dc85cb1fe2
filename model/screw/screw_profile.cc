#include "model/screw/screw_profile.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {

StatusOr<ScrewProfile> ScrewProfile::Make(std::vector<double> x_mm, std::vector<double> theta_k) {
  if (x_mm.empty()) return Status::InvalidArgument("a screw profile needs at least one sensor");
  if (x_mm.size() != theta_k.size()) {
    return Status::InvalidArgument("screw profile: one temperature per sensor position");
  }
  for (size_t i = 0; i < x_mm.size(); ++i) {
    if (!std::isfinite(x_mm[i]) || !std::isfinite(theta_k[i])) {
      return Status::InvalidArgument("screw profile: positions and temperatures must be finite");
    }
    if (i > 0 && !(x_mm[i] > x_mm[i - 1])) {
      return Status::InvalidArgument("screw profile: sensor positions must increase");
    }
  }
  return ScrewProfile(std::move(x_mm), std::move(theta_k));
}

ScrewProfile::ScrewProfile(std::vector<double> x, std::vector<double> t)
    : x_(std::move(x)), theta_(std::move(t)), cumulative_(x_.size(), 0.0) {
  for (size_t i = 1; i < x_.size(); ++i) {
    cumulative_[i] = cumulative_[i - 1] + 0.5 * (theta_[i - 1] + theta_[i]) * (x_[i] - x_[i - 1]);
  }
}

double ScrewProfile::Theta(double x_mm) const {
  if (x_.empty()) return 0;
  if (x_mm <= x_.front()) return theta_.front();
  if (x_mm >= x_.back()) return theta_.back();
  const size_t i =
      std::upper_bound(x_.begin(), x_.end(), x_mm) - x_.begin();  // x_[i-1] < x <= x_[i]
  const double w = (x_mm - x_[i - 1]) / (x_[i] - x_[i - 1]);
  return theta_[i - 1] + w * (theta_[i] - theta_[i - 1]);
}

double ScrewProfile::FromFirst(double x_mm) const {
  if (x_.empty()) return 0;
  if (x_mm <= x_.front()) return theta_.front() * (x_mm - x_.front());
  if (x_mm >= x_.back()) return cumulative_.back() + theta_.back() * (x_mm - x_.back());
  const size_t i = std::upper_bound(x_.begin(), x_.end(), x_mm) - x_.begin();
  return cumulative_[i - 1] + 0.5 * (theta_[i - 1] + Theta(x_mm)) * (x_mm - x_[i - 1]);
}

double ScrewProfile::Integral(double x_mm) const {
  return FromFirst(x_mm) - FromFirst(0.0);
}

double ScrewProfile::MaxCurvature() const {
  double most = 0;
  for (size_t i = 1; i + 1 < x_.size(); ++i) {
    const double left = (theta_[i] - theta_[i - 1]) / (x_[i] - x_[i - 1]);
    const double right = (theta_[i + 1] - theta_[i]) / (x_[i + 1] - x_[i]);
    most = std::max(most, std::fabs(2.0 * (right - left) / (x_[i + 1] - x_[i - 1])));
  }
  return most;
}

}  // namespace thermocomp
