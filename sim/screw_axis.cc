#include "sim/screw_axis.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace thermocomp {
namespace {

constexpr double kDxM = 0.01;            // node spacing: 10 mm
constexpr double kDiffusivity = 1.4e-5;  // steel, k / (rho c), m^2/s
constexpr double kStepS = 2.0;           // explicit scheme: stable below dx^2 / (2 D) = 3.6 s
// Heat capacity of 10 mm of a 40-mm screw: rho c A dx = 7850 * 460 * 1.257e-3 * 0.01 J/K.
constexpr double kNodeCapacity = 45.4;

// The screw's temperature rise over shop air, node by node.
class Rod {
 public:
  Rod(double length_mm, double convection_s)
      : theta_(static_cast<size_t>(std::lround(length_mm / (kDxM * 1e3))) + 1, 0.0),
        next_(theta_.size(), 0.0),
        convection_s_(convection_s) {}

  // One step with `heat_w` per node.
  void Step(const std::vector<double>& heat_w) {
    const size_t n = theta_.size();
    const double k = kDiffusivity * kStepS / (kDxM * kDxM);
    for (size_t i = 0; i < n; ++i) {
      // Insulated ends: the mirror node. An end node holds half a node's
      // steel (its cell is 5 mm long, as the trapezoid integral weighs it),
      // so a bearing's watts warm it twice as fast as an inner node's:
      // with the full capacity half the bearing's heat would be lost.
      const bool end = i == 0 || i + 1 == n;
      const double capacity = end ? 0.5 * kNodeCapacity : kNodeCapacity;
      const double left = theta_[i == 0 ? 1 : i - 1];
      const double right = theta_[i + 1 == n ? n - 2 : i + 1];
      next_[i] = theta_[i] + k * (left - 2 * theta_[i] + right) -
                 kStepS * theta_[i] / convection_s_ + kStepS * heat_w[i] / capacity;
    }
    theta_.swap(next_);
  }

  double At(double x_mm) const {
    const double u = std::clamp(x_mm / (kDxM * 1e3), 0.0, static_cast<double>(theta_.size() - 1));
    const size_t i = std::min(static_cast<size_t>(u), theta_.size() - 2);
    const double w = u - static_cast<double>(i);
    return theta_[i] + w * (theta_[i + 1] - theta_[i]);
  }

  // The fine profile as a ScrewProfile (every node a point), whose exact
  // integral is the rod's trapezoid integral: the truth, at 10 mm.
  ScrewProfile Profile() const {
    std::vector<double> x(theta_.size());
    for (size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i) * kDxM * 1e3;
    return *ScrewProfile::Make(std::move(x), theta_);
  }

  size_t nodes() const { return theta_.size(); }

 private:
  std::vector<double> theta_, next_;
  double convection_s_;
};

struct WorkPeriod {
  double start_h = 0, end_h = 0;
  double stroke_from_mm = 0, stroke_to_mm = 0;
  double nut_w = 0, bearing_w = 0;
};

std::vector<WorkPeriod> Schedule(const ScrewSimOptions& o, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<WorkPeriod> out;
  double t = 0.5;  // the cold check first
  while (t < o.hours) {
    WorkPeriod w;
    w.start_h = t;
    w.end_h = t + 1.0 + 3.0 * unit(rng);
    const double travel = o.travel_max_mm - o.travel_min_mm;
    const double stroke = travel * (0.2 + 0.5 * unit(rng));
    w.stroke_from_mm = o.travel_min_mm + (travel - stroke) * unit(rng);
    w.stroke_to_mm = w.stroke_from_mm + stroke;
    const double speed = 0.3 + 0.7 * unit(rng);  // share of rapid
    w.nut_w = 4.0 + 6.0 * speed;
    w.bearing_w = 1.0 + 3.0 * speed;
    out.push_back(w);
    t = w.end_h + 0.5 + 2.5 * unit(rng);
  }
  return out;
}

}  // namespace

ScrewSimRecording SimulateScrewAxis(const ScrewSimOptions& o) {
  std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ULL + 71);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  ScrewSimRecording rec;
  ScrewAxis& axis = rec.axis;
  axis.arrangement = o.arrangement;
  axis.bearing_distance_mm = o.length_mm;
  axis.alpha_um_per_m_k = 11.5;
  axis.stiffness_ratio = o.arrangement == BearingArrangement::kPreloaded ? 0.25 : 0.0;
  for (int k = 0; k < o.sensors; ++k) {
    const double x = o.sensors == 1 ? 0.0 : o.length_mm * k / (o.sensors - 1);
    axis.sensors.push_back({"Tscrew" + std::to_string(k + 1), x, 20.0});
  }
  ScrewAxis truth = axis;
  truth.alpha_um_per_m_k = o.alpha_um_per_m_k;
  truth.stiffness_ratio = o.arrangement == BearingArrangement::kPreloaded ? o.stiffness_ratio : 0;
  rec.true_alpha_um_per_m_k = truth.alpha_um_per_m_k;
  rec.true_stiffness_ratio = truth.stiffness_ratio;

  Rod rod(o.length_mm, 3600.0 * (0.8 + 0.5 * unit(rng)));
  const std::vector<WorkPeriod> work = Schedule(o, rng);
  std::vector<double> heat(rod.nodes(), 0.0);
  const int steps_per_h = static_cast<int>(3600.0 / kStepS);
  const int total = static_cast<int>(o.hours * steps_per_h);
  const int check_every = std::max(1, static_cast<int>(o.check_every_h * steps_per_h));
  size_t period = 0;
  for (int s = 0; s <= total; ++s) {
    const double hour = static_cast<double>(s) / steps_per_h;
    if (s % check_every == 0) {
      ScrewCheck c;
      std::vector<double> truth_at;
      const ScrewProfile fine = rod.Profile();
      for (double x = o.travel_min_mm; x <= o.travel_max_mm + 1e-9; x += o.target_spacing_mm) {
        const double e = ScrewErrorUm(truth, fine, x);
        c.position_mm.push_back(x);
        truth_at.push_back(e);
        c.error_um.push_back(e + o.laser_noise_um * normal(rng));
      }
      for (const auto& sensor : axis.sensors) {
        c.temperature_c.push_back(20.0 + rod.At(sensor.x_mm) + o.sensor_noise_c * normal(rng));
      }
      rec.checks.push_back(std::move(c));
      rec.true_error_um.push_back(std::move(truth_at));
      rec.check_hour.push_back(hour);
    }
    while (period < work.size() && work[period].end_h <= hour) ++period;
    std::fill(heat.begin(), heat.end(), 0.0);
    if (period < work.size() && work[period].start_h <= hour) {
      const WorkPeriod& w = work[period];
      const size_t from = static_cast<size_t>(w.stroke_from_mm / (kDxM * 1e3));
      const size_t to =
          std::min(rod.nodes() - 1, static_cast<size_t>(w.stroke_to_mm / (kDxM * 1e3)));
      for (size_t i = from; i <= to; ++i) heat[i] += w.nut_w / static_cast<double>(to - from + 1);
      heat.front() += w.bearing_w;
      if (o.arrangement == BearingArrangement::kPreloaded) heat.back() += w.bearing_w;
    }
    rod.Step(heat);
  }
  return rec;
}

}  // namespace thermocomp
