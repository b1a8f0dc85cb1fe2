// About 500 lines: one detector (hourly means, the regression on the other
// sensors, the onset scans of each fault form, the step's raw check and
// the attribution) whose parts all read one Design; the contract and the
// method are in sensor_faults.h.
#include "model/sensor_faults.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/time_format.h"
#include "core/time_units.h"

namespace thermocomp {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
// An hour is kept when it holds this share of the sensor's usual count:
// a logging gap shortens it, it does not move its mean much.
constexpr double kMinHourShare = 0.25;
// A regressor sensor must be known on this share of the hours.
constexpr double kMinSensorCoverage = 0.8;

// Hourly means of every sensor over the window.
struct Hourly {
  int64_t from_ms = 0;
  int bins = 0;
  std::vector<std::vector<double>> mean;  // per sensor; NaN: too few samples
};

std::vector<double> HourlyMeans(const TimeSeries& raw, int64_t from, int bins) {
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  const auto begin = std::lower_bound(raw.ts_ms.begin(), raw.ts_ms.end(), from);
  for (size_t i = begin - raw.ts_ms.begin(); i < raw.ts_ms.size(); ++i) {
    const int64_t b = (raw.ts_ms[i] - from) / kHourMs;
    if (b >= bins) break;
    sum[b] += raw.value[i];
    count[b] += 1;
  }
  std::vector<double> positive;
  for (double c : count) {
    if (c > 0) positive.push_back(c);
  }
  std::vector<double> mean(bins, kNan);
  if (positive.empty()) return mean;
  std::nth_element(positive.begin(), positive.begin() + positive.size() / 2, positive.end());
  const double need = std::max(1.0, kMinHourShare * positive[positive.size() / 2]);
  for (int b = 0; b < bins; ++b) {
    if (count[b] >= need) mean[b] = sum[b] / count[b];
  }
  return mean;
}

Hourly Resample(const TermInputs& in, int64_t from, int64_t to) {
  Hourly h;
  h.from_ms = from;
  h.bins = static_cast<int>((to - from) / kHourMs) + 1;
  for (size_t s = 0; s < in.sensors.size(); ++s) {
    h.mean.push_back(s < in.sensor_raw.size() ? HourlyMeans(in.sensor_raw[s], from, h.bins)
                                              : std::vector<double>(h.bins, kNan));
  }
  return h;
}

// First-order lag on the hourly grid; an unknown hour holds the state.
std::vector<double> HourlyLag(const std::vector<double>& x, double tau_h) {
  const double a = 1.0 - std::exp(-1.0 / tau_h);
  std::vector<double> y(x.size(), kNan);
  double state = kNan;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isnan(x[i])) state = std::isnan(state) ? x[i] : state + a * (x[i] - state);
    y[i] = state;
  }
  return y;
}

double Coverage(const std::vector<double>& x) {
  if (x.empty()) return 0.0;
  return static_cast<double>(
             std::count_if(x.begin(), x.end(), [](double v) { return !std::isnan(v); })) /
         static_cast<double>(x.size());
}

// One sensor regressed on the others: the rows, the residual, the
// orthonormal basis of the regressors, the residual's long-run variance.
struct Design {
  std::vector<int> bin;     // per row
  Eigen::VectorXd day;      // per row, days since the window's start
  Eigen::VectorXd contact;  // per row, air minus the sensor (0 without air)
  Eigen::MatrixXd q;
  Eigen::VectorXd e;
  double lrv = 0;  // per row
};

// Variance of a row's share of a sum over many rows, from daily block
// sums: what hour-to-day correlated wander adds is counted.
double LongRunVariance(const Eigen::VectorXd& e, const std::vector<int>& bin) {
  double total = 0, block = 0;
  int current = -1;
  for (int i = 0; i < e.size(); ++i) {
    const int day = bin[i] / 24;
    if (day != current) {
      total += block * block;
      block = 0;
      current = day;
    }
    block += e[i];
  }
  total += block * block;
  return e.size() > 0 ? total / static_cast<double>(e.size()) : 0.0;
}

std::optional<Design> BuildDesign(const Hourly& h, int target, const std::vector<bool>& left_out,
                                  int air, const SensorFaultOptions& o) {
  std::vector<std::vector<double>> columns;
  for (int j = 0; j < static_cast<int>(h.mean.size()); ++j) {
    if (j == target || left_out[j] || Coverage(h.mean[j]) < kMinSensorCoverage) continue;
    columns.push_back(h.mean[j]);
    for (double tau : o.lags_h) columns.push_back(HourlyLag(h.mean[j], tau));
  }
  const std::vector<double>& y = h.mean[target];
  Design d;
  for (int b = 0; b < h.bins; ++b) {
    bool known = !std::isnan(y[b]);
    for (const auto& c : columns) known = known && !std::isnan(c[b]);
    if (known) d.bin.push_back(b);
  }
  const int n = static_cast<int>(d.bin.size());
  const int p = static_cast<int>(columns.size()) + 1;
  if (n < p + 72) return std::nullopt;
  Eigen::MatrixXd x(n, p);
  Eigen::VectorXd yv(n);
  d.day.resize(n);
  d.contact = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    const int b = d.bin[i];
    yv[i] = y[b];
    d.day[i] = b / 24.0;
    x(i, 0) = 1.0;
    for (int c = 1; c < p; ++c) x(i, c) = columns[c - 1][b];
    if (air >= 0 && air != target && !std::isnan(h.mean[air][b]))
      d.contact[i] = h.mean[air][b] - y[b];
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  d.q = qr.householderQ() * Eigen::MatrixXd::Identity(n, qr.rank());
  d.e = yv - d.q * (d.q.transpose() * yv);
  d.lrv = LongRunVariance(d.e, d.bin);
  if (!(d.lrv > 0)) return std::nullopt;
  return d;
}

enum class Kind { kStep, kDrift, kLostContact };

const char* KindName(Kind k) {
  return k == Kind::kStep ? "step" : k == Kind::kDrift ? "drift" : "lost_contact";
}

// The fault column at onset row k: a_i g(day_i - day_k) from row k on,
// a_i = 1 or the air contrast; g = 1 (step), the days since the onset
// (drift, and a lost contact with tau 0), or 1 - exp(-days / tau) (a lost
// contact whose share of the air settles with tau).
Eigen::VectorXd FaultColumn(const Design& d, Kind kind, int k, double tau = 0) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(d.e.size());
  for (int i = k; i < f.size(); ++i) {
    const double a = kind == Kind::kLostContact ? d.contact[i] : 1.0;
    const double days = d.day[i] - d.day[k];
    f[i] = kind == Kind::kStep ? a : tau > 0 ? a * -std::expm1(-days / tau) : a * days;
  }
  return f;
}

struct Onset {
  int row = -1;
  double t = 0;
};

bool Triable(const Design& d, int k, const SensorFaultOptions& o) {
  const double t = d.day[k];
  return t <= d.day[d.day.size() - 1] - o.min_days_after && t >= d.day[0] + o.min_days_before;
}

// The t of a fault column from its sums over the onset's suffix: f'e,
// f'f and |Q'f|^2; a lost contact's only when positive (FitAt says why).
void Consider(int k, double fe, double ff, double qf2, double lrv, bool contact, Onset* best) {
  const double rr = ff - qf2;
  if (!(rr > 1e-9 * ff) || rr <= 0) return;
  const double tv = fe / std::sqrt(rr * lrv);
  if (contact && tv <= 0) return;
  if (std::fabs(tv) > std::fabs(best->t)) *best = {k, tv};
}

// The onset row with the largest |t| of the fault column, every row at
// least min_days_before after the first and min_days_after before the
// last tried. Suffix sums: f'e, Q'f and f'f for every onset in one pass.
Onset ScanOnsets(const Design& d, Kind kind, const SensorFaultOptions& o) {
  const int n = static_cast<int>(d.e.size());
  const int p = static_cast<int>(d.q.cols());
  const bool linear = kind != Kind::kStep;
  Eigen::VectorXd s0 = Eigen::VectorXd::Zero(p), s1 = Eigen::VectorXd::Zero(p);
  double e0 = 0, e1 = 0, f0 = 0, f1 = 0, f2 = 0;
  Onset best;
  for (int k = n - 1; k >= 0; --k) {
    const double a = kind == Kind::kLostContact ? d.contact[k] : 1.0, t = d.day[k];
    s0 += a * d.q.row(k).transpose();
    s1 += a * t * d.q.row(k).transpose();
    e0 += a * d.e[k];
    e1 += a * t * d.e[k];
    f0 += a * a;
    f1 += a * a * t;
    f2 += a * a * t * t;
    if (!Triable(d, k, o)) continue;
    Consider(k, linear ? e1 - t * e0 : e0, linear ? f2 - 2 * t * f1 + t * t * f0 : f0,
             linear ? (s1 - t * s0).squaredNorm() : s0.squaredNorm(), d.lrv,
             kind == Kind::kLostContact, &best);
  }
  return best;
}

// The same for a lost contact settling with tau: with E_i = exp(-(day_i -
// day_k) / tau) the column is a_i (1 - E_i), and the sums over E_i and
// E_i^2 follow from the next row's by one factor each (no exp of a
// growing day count, which would overflow over a year).
// Without `contrast` (a_i = 1): an offset that settles with tau.
Onset ScanSettlingContacts(const Design& d, double tau, const SensorFaultOptions& o,
                           bool contrast = true) {
  const int n = static_cast<int>(d.e.size());
  const int p = static_cast<int>(d.q.cols());
  Eigen::VectorXd sq = Eigen::VectorXd::Zero(p), sqe = Eigen::VectorXd::Zero(p);
  double se = 0, see = 0, f0 = 0, fe1 = 0, fe2 = 0;
  Onset best;
  for (int k = n - 1; k >= 0; --k) {
    const double a = contrast ? d.contact[k] : 1.0;
    const double r = k + 1 < n ? std::exp(-(d.day[k + 1] - d.day[k]) / tau) : 0.0;
    sq += a * d.q.row(k).transpose();
    sqe = a * d.q.row(k).transpose() + r * sqe;
    se += a * d.e[k];
    see = a * d.e[k] + r * see;
    f0 += a * a;
    fe1 = a * a + r * fe1;
    fe2 = a * a + r * r * fe2;
    if (!Triable(d, k, o)) continue;
    Consider(k, se - see, f0 - 2 * fe1 + fe2, (sq - sqe).squaredNorm(), d.lrv, contrast, &best);
  }
  return best;
}

struct Fit {
  Kind kind = Kind::kDrift;
  int row = -1;
  double t = 0;       // on the residual with the fault fitted
  double size_c = 0;  // the departure over the newest day
  bool persists = false;
  double tau_days = 0;  // a settling lost contact's; 0: a ramp (or no contact)
};

// The joint fit at one onset: its t on the residual left with the fault
// fitted, the size at the end, and whether every third after the onset
// keeps persist_share of the fitted departure.
Fit FitAt(const Design& d, Kind kind, int k, const SensorFaultOptions& o, double tau = 0) {
  Fit fit{kind, k};
  fit.tau_days = tau;
  const Eigen::VectorXd f = FaultColumn(d, kind, k, tau);
  const Eigen::VectorXd r = f - d.q * (d.q.transpose() * f);
  const double rr = r.squaredNorm();
  if (!(rr > 0)) return fit;
  const double gamma = r.dot(d.e) / rr;
  // A loose sensor reads T + w (A - T), a share w of the air between none
  // and all of it; against the reading's own contrast A - y = (1 - w)(A -
  // T) the fitted share is w / (1 - w), any positive number, and as the
  // column's share of the air is positive, so is gamma. A negative one is
  // not a loose sensor: the residual's own wander, on both sides of the
  // regression through y, pulls the fit that way.
  if (kind == Kind::kLostContact && !(gamma > 0)) return fit;
  const Eigen::VectorXd rest = d.e - gamma * r;
  const double lrv = LongRunVariance(rest, d.bin);
  if (!(lrv > 0)) return fit;
  fit.t = gamma * std::sqrt(rr / lrv);
  const int n = static_cast<int>(f.size());
  const Eigen::VectorXd departure = rest + gamma * r;
  fit.persists = true;
  for (int part = 0; part < 3; ++part) {
    const int lo = k + (n - k) * part / 3, hi = k + (n - k) * (part + 1) / 3;
    double fitted = 0, seen = 0;
    for (int i = lo; i < hi; ++i) {
      fitted += gamma * r[i];
      seen += departure[i];
    }
    if (!(seen / fitted >= o.persist_share)) fit.persists = false;
  }
  int last = n - 1, count = 0;
  double sum = 0;
  for (; last >= k && d.day[last] > d.day[n - 1] - 1.0; --last, ++count) sum += gamma * f[last];
  fit.size_c = count > 0 ? sum / count : 0.0;
  return fit;
}

struct Jump {
  int64_t ts_ms = 0;
  double size_c = 0;
  double spreads = 0;
};

// Level at ts of a straight line fitted to samples [lo, hi) (ts minutes
// relative to ts, so the sums stay exact).
double LineAt(const TimeSeries& s, size_t lo, size_t hi, int64_t ts) {
  double st = 0, sx = 0, stt = 0, stx = 0;
  const double m = static_cast<double>(hi - lo);
  for (size_t i = lo; i < hi; ++i) {
    const double t = static_cast<double>(s.ts_ms[i] - ts) / kMinuteMs;
    st += t;
    sx += s.value[i];
    stt += t * t;
    stx += t * s.value[i];
  }
  const double var = stt - st * st / m;
  const double slope = var > 0 ? (stx - st * sx / m) / var : 0.0;
  return sx / m - slope * st / m;
}

// The largest jump of the raw level in [from, to] where no logging gap
// is, in degC and in robust spreads of the sensor's jumps at every sample.
std::optional<Jump> LargestJump(const TimeSeries& s, int64_t from, int64_t to, int w) {
  const size_t lo = std::lower_bound(s.ts_ms.begin(), s.ts_ms.end(), from) - s.ts_ms.begin();
  const size_t hi = std::upper_bound(s.ts_ms.begin(), s.ts_ms.end(), to) - s.ts_ms.begin();
  if (hi < lo + 4 * w) return std::nullopt;
  std::vector<int64_t> gaps;
  for (size_t i = lo + 1; i < hi; ++i) gaps.push_back(s.ts_ms[i] - s.ts_ms[i - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  // At most one sample missing: across a gap the level moves legitimately.
  const double span = (2.0 * w + 0.5) * static_cast<double>(gaps[gaps.size() / 2]);
  std::vector<double> jumps;
  Jump best;
  for (size_t i = lo + w; i + w <= hi; ++i) {
    if (static_cast<double>(s.ts_ms[i + w - 1] - s.ts_ms[i - w]) > span) continue;
    const double j = LineAt(s, i, i + w, s.ts_ms[i]) - LineAt(s, i - w, i, s.ts_ms[i]);
    jumps.push_back(std::fabs(j));
    if (std::fabs(j) > std::fabs(best.size_c)) best = {s.ts_ms[i], j, 0};
  }
  if (jumps.size() < 100) return std::nullopt;
  std::nth_element(jumps.begin(), jumps.begin() + jumps.size() / 2, jumps.end());
  // |N(0, s)| has median 0.674 s.
  const double spread = jumps[jumps.size() / 2] / 0.674;
  best.spreads = spread > 0 ? std::fabs(best.size_c) / spread : 1e9;
  return best;
}

// A tried sensor's fault, if it has one.
struct Finding {
  int sensor = -1;
  Kind kind = Kind::kDrift;
  int64_t onset_ms = 0;
  double size_c = 0;
  double score = 0;     // how far past its bar, to take the strongest first
  double tau_days = 0;  // a lost contact's settling; 0: a ramp, or another kind
};

int RowAtOrAfter(const Design& d, const Hourly& h, int64_t ts) {
  const int bin = static_cast<int>((ts - h.from_ms + kHourMs - 1) / kHourMs);
  return static_cast<int>(std::lower_bound(d.bin.begin(), d.bin.end(), bin) - d.bin.begin());
}

// The sensor's largest raw jump in [from, to] when it is large enough to
// be a step.
std::optional<Jump> StepJump(const TermInputs& in, int s, int64_t from, int64_t to,
                             const SensorFaultOptions& o) {
  auto jump = LargestJump(in.sensor_raw[s], from, to, o.step_window);
  if (!jump || std::fabs(jump->size_c) < o.step_min_c || jump->spreads < o.step_min_spreads) {
    return std::nullopt;
  }
  return jump;
}

std::optional<Finding> StepFinding(const TermInputs& in, const Hourly& h, const Design& d, int s,
                                   int64_t to, const SensorFaultOptions& o) {
  const auto jump = StepJump(in, s, h.from_ms, to, o);
  if (!jump) return std::nullopt;
  const int k = RowAtOrAfter(d, h, jump->ts_ms);
  if (k <= 0 || k >= static_cast<int>(d.bin.size()) ||
      d.day[k] > d.day[d.day.size() - 1] - o.min_days_after) {
    return std::nullopt;
  }
  const Fit fit = FitAt(d, Kind::kStep, k, o);
  if (fit.t * jump->size_c <= 0 || std::fabs(fit.t) < o.step_confirm_t || !fit.persists) {
    return std::nullopt;
  }
  return Finding{s, Kind::kStep, jump->ts_ms, fit.size_c, 1e3 + jump->spreads};
}

// The drift or lost contact that explains the departure best: onsets by
// the largest gain, then judged on the residual left with each fitted (a
// fault inflates the residual's spread it would be judged against).
std::optional<Finding> SlowFinding(const Hourly& h, const Design& d, int s, bool has_air,
                                   const SensorFaultOptions& o, double* evidence) {
  const Onset drift_onset = ScanOnsets(d, Kind::kDrift, o);
  if (drift_onset.row < 0) return std::nullopt;
  Fit fit = FitAt(d, Kind::kDrift, drift_onset.row, o);
  if (has_air) {
    // The share of the air a loose sensor reads grows and settles; how
    // fast is the mounting's: a ramp and settling times from hours to days
    // are tried, the best fit taken.
    Fit contact;
    const auto consider = [&](const Onset& onset, double tau) {
      if (onset.row < 0) return;
      const Fit f = FitAt(d, Kind::kLostContact, onset.row, o, tau);
      if (std::fabs(f.t) > std::fabs(contact.t)) contact = f;
    };
    consider(ScanOnsets(d, Kind::kLostContact, o), 0);
    for (double tau : o.contact_settling_days) consider(ScanSettlingContacts(d, tau, o), tau);
    // A loose sensor warmed by a heat no other sensor sees (family A's
    // column base over its Y drive) moves by an offset toward the air that
    // settles: its contrast to the air carries that heat's swings, which
    // the residual holds too, so the contrast forms fit worse than a drift
    // begun days early, and the plain settling offset does not. Only fast
    // settling: a slow one borrows an earlier onset, and the ramp covers
    // slow approaches.
    for (double tau : o.contact_settling_days) {
      if (tau > o.offset_settling_max_days) continue;
      const Onset onset = ScanSettlingContacts(d, tau, o, false);
      if (onset.row < 0) continue;
      Fit f = FitAt(d, Kind::kDrift, onset.row, o, tau);
      const double toward = d.contact.tail(d.contact.size() - onset.row).sum();
      if (!(f.size_c * toward > 0)) continue;  // away from the air: no loose sensor
      f.kind = Kind::kLostContact;
      if (std::fabs(f.t) > std::fabs(contact.t)) contact = f;
    }
    if (std::fabs(contact.t) >= std::fabs(fit.t) + o.contact_margin_t) fit = contact;
  }
  *evidence = std::max(*evidence, std::fabs(fit.t) / o.min_t);
  if (std::fabs(fit.t) < o.min_t || !fit.persists) return std::nullopt;
  return Finding{s,
                 fit.kind,
                 h.from_ms + d.bin[fit.row] * kHourMs,
                 fit.size_c,
                 std::fabs(fit.t) / o.min_t,
                 fit.kind == Kind::kLostContact ? fit.tau_days : 0.0};
}

int AirSensor(const TermInputs& in, const SensorFaultOptions& o) {
  if (!o.air_sensor.empty()) return in.SensorIndex(o.air_sensor);
  for (size_t s = 0; s < in.sensors.size(); ++s) {
    std::string name = in.sensors[s];
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const char* word : {"air", "env", "amb", "room", "hall", "shop"}) {
      if (name.find(word) != std::string::npos) return static_cast<int>(s);
    }
  }
  return -1;
}

std::string Reason(const TermInputs& in, const Finding& f, int air) {
  char size[64];
  std::snprintf(size, sizeof size, "%+.2f degC", f.size_c);
  const std::string& name = in.sensors[f.sensor];
  const std::string since = FormatRfc3339(f.onset_ms);
  switch (f.kind) {
    case Kind::kStep:
      return name + "'s reading stepped by " + size + " at " + since +
             " while the other sensors did not: check this sensor (connector, cable, "
             "its measuring channel).";
    case Kind::kDrift:
      return name + "'s reading drifts away from what the other sensors say about it since " +
             since + ", " + size + " by the end: check this sensor and its calibration.";
    case Kind::kLostContact:
      return name + "'s reading moves toward the air (" + in.sensors[air] + ") since " + since +
             ", " + size +
             " by the end: the sensor may have lost contact with the structure; "
             "check its mounting.";
  }
  return "";
}

struct Examination {
  std::vector<Finding> found;
  double evidence = 0;  // the largest slow-fault |t| / min_t, found or not
};

// Whether drifts and lost contacts are looked for over [from_ms, to_ms].
bool LooksForSlowFaults(int64_t from_ms, int64_t to_ms, const SensorFaultOptions& o) {
  return !o.steps_only && static_cast<double>(to_ms - from_ms) >= o.slow_min_days * kDayMs;
}

// Every sensor's fault with the `left_out` sensors left out of every
// prediction. Undeclared sensors are examined too, so that a fault of
// theirs is left out of the others' prediction instead of spoiling it.
Examination Examine(const TermInputs& in, const Hourly& h, const std::vector<bool>& left_out,
                    int air, int64_t to, const SensorFaultOptions& o) {
  Examination x;
  const bool slow = LooksForSlowFaults(h.from_ms, to, o);
  for (int s = 0; s < static_cast<int>(in.sensors.size()); ++s) {
    if (left_out[s] || Coverage(h.mean[s]) < kMinSensorCoverage) continue;
    const auto design = BuildDesign(h, s, left_out, air, o);
    if (!design) continue;
    auto finding = StepFinding(in, h, *design, s, to, o);
    if (!finding && slow)
      finding = SlowFinding(h, *design, s, air >= 0 && air != s, o, &x.evidence);
    if (finding) x.found.push_back(*finding);
  }
  return x;
}

// The finding whose sensor is the faulty one: a fault also shows in the
// prediction of every sensor that reads the faulty one, and leaving out
// the faulty sensor clears them all, while leaving out another does not.
// So the sensor whose leaving out leaves the fewest findings, then the
// least evidence of one (two sensors that only predict each other both
// clear, but the faulty one still departs from the rest).
Finding Attribute(const TermInputs& in, const Hourly& h, const std::vector<bool>& left_out, int air,
                  int64_t to, const std::vector<Finding>& found, const SensorFaultOptions& o) {
  if (found.size() == 1) return found[0];
  Finding pick;
  std::pair<size_t, double> least{SIZE_MAX, 0.0};
  for (const Finding& f : found) {
    std::vector<bool> without = left_out;
    without[f.sensor] = true;
    const Examination x = Examine(in, h, without, air, to, o);
    const std::pair<size_t, double> remaining{x.found.size(), x.evidence};
    if (remaining < least) {
      least = remaining;
      pick = f;
    }
  }
  return pick;
}

}  // namespace

std::vector<EffectTerm> FaultTerms(const SensorFault& fault) {
  if (fault.kind != "lost_contact" || fault.settled_ms <= 0 || fault.air.empty()) return {};
  return {EffectTerm::SensitivityChange(fault.sensor, fault.settled_ms, "sensor_fault"),
          EffectTerm::SensitivityChange(fault.air, fault.settled_ms, "sensor_fault")};
}

std::vector<std::string> FaultKindsLookedFor(int64_t from_ms, int64_t to_ms,
                                             const SensorFaultOptions& options) {
  if (!LooksForSlowFaults(from_ms, to_ms, options)) return {"step"};
  return {"step", "drift", "lost_contact"};
}

std::vector<SensorFault> FindSensorFaults(const TermInputs& inputs,
                                          const std::vector<std::string>& declared, int64_t from_ms,
                                          int64_t to_ms, const SensorFaultOptions& options) {
  std::vector<SensorFault> faults;
  if (to_ms <= from_ms) return faults;
  // Steps alone: nothing to report without a declared sensor's raw jump
  // (a year's hourly regressions are most of the check's time).
  if (!LooksForSlowFaults(from_ms, to_ms, options)) {
    bool any = false;
    for (const std::string& name : declared) {
      const int s = inputs.SensorIndex(name);
      any = any || (s >= 0 && s < static_cast<int>(inputs.sensor_raw.size()) &&
                    StepJump(inputs, s, from_ms, to_ms, options).has_value());
    }
    if (!any) return faults;
  }
  const Hourly hourly = Resample(inputs, from_ms, to_ms);
  const int air = AirSensor(inputs, options);
  std::vector<bool> left_out(inputs.sensors.size(), false);
  for (size_t round = 0; round < inputs.sensors.size(); ++round) {
    const auto found = Examine(inputs, hourly, left_out, air, to_ms, options).found;
    if (found.empty()) break;
    const Finding best = Attribute(inputs, hourly, left_out, air, to_ms, found, options);
    left_out[best.sensor] = true;
    const std::string& name = inputs.sensors[best.sensor];
    if (std::find(declared.begin(), declared.end(), name) == declared.end()) continue;
    SensorFault f;
    f.sensor = name;
    f.kind = KindName(best.kind);
    f.onset_ms = best.onset_ms;
    f.size_c = best.size_c;
    f.reason = Reason(inputs, best, air);
    if (best.kind == Kind::kLostContact && best.tau_days > 0) {
      f.settled_ms =
          best.onset_ms + static_cast<int64_t>(options.settled_taus * best.tau_days * 24 * kHourMs);
      f.air = inputs.sensors[air];
    }
    faults.push_back(std::move(f));
  }
  return faults;
}

}  // namespace thermocomp
