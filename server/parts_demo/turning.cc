// The demo's turned parts (docs/model.md §15): two features of a shaft
// turned on the demo machine over the two weeks of its history, measured
// four times each. Force and geometry stay; the thermal part (the
// workpiece and the machine warming up over each shift, time constant
// about an hour) shrinks to a quarter once the machine's compensation
// changed, at the change the archive holds. The latest part of D40 is the
// issue's hand check: 40.000, 40.030, 40.010, 40.016 mm.
#include <cmath>
#include <random>

#include "core/time_format.h"
#include "core/time_units.h"
#include "model/parts/diameter_decimal.h"
#include "server/parts_demo.h"
#include "service/parts/turning/turning_service.h"

namespace thermocomp {
namespace {

struct DemoFeature {
  const char* name;
  int64_t drawing_nm;
  double force_um;    // radial, from the cutting force
  double thermal_um;  // radial at a warm machine, before compensation
};

// Measured to 1 µm on the diameter, as a gauge reads.
int64_t Gauge(int64_t drawing_nm, double radial_um) {
  return drawing_nm + 1000 * std::llround(2 * radial_um);
}

}  // namespace

Status DemoTurning(App& app, const std::string& machine, std::string* summary) {
  TurningService& turning = app.turning();
  const int64_t now = app.clock().NowMs();
  const int64_t start = now - 14 * kDayMs;
  // Compensation began at the machine's first archived change within the
  // period (the demo's first fit), else halfway.
  int64_t compensated_from = start + 7 * kDayMs;
  if (auto changes = turning.CompensationChanges(machine); changes.ok()) {
    for (const CompensationChange& c : *changes) {
      if (c.ts_ms > start + kDayMs && c.ts_ms < now - kDayMs) {
        compensated_from = c.ts_ms;
        break;
      }
    }
  }
  const DemoFeature features[] = {{"D40", 40000000, 6.0, -9.0}, {"D25", 25000000, 3.5, -6.0}};
  std::mt19937 rng(22);
  std::normal_distribution<double> noise(0.0, 0.8);
  std::vector<TurnedPartInput> parts;
  int serial = 1;
  // A shaft every 90 minutes from 06:00 to 21:00; the thermal part grows
  // over the shift.
  for (int64_t day = start - start % kDayMs; day < now - 2 * kHourMs; day += kDayMs) {
    for (int64_t t = day + 6 * kHourMs; t <= day + 21 * kHourMs; t += 90 * 60000) {
      if (t < start || t > now - 2 * kHourMs) continue;
      const double shift_h = static_cast<double>(t - day - 6 * kHourMs) / kHourMs;
      const double warm = 1.0 - std::exp(-(shift_h + 0.3));
      const double left = t >= compensated_from ? 0.25 : 1.0;
      const double month =
          static_cast<double>(t - start) / (30.0 * kDayMs);  // geometry drifts slowly
      const std::string part = "S" + std::to_string(10000 + serial++);
      for (const DemoFeature& f : features) {
        const double df = f.force_um + noise(rng);
        const double dth = f.thermal_um * warm * left + noise(rng) * 0.5;
        const double dg = 1.5 + 2.0 * month + noise(rng) * 0.5;
        TurnedPartInput in;
        in.row = parts.size() + 1;
        in.part = part;
        in.feature = f.name;
        in.cut_ms = t;
        in.d_des_nm = f.drawing_nm;
        in.d_w_nm = Gauge(f.drawing_nm, df);
        in.d_c_nm = Gauge(f.drawing_nm, df + dth);
        in.d_pp_nm = Gauge(f.drawing_nm, df + dth + dg);
        parts.push_back(std::move(in));
      }
    }
  }
  // The hand check, the newest part of D40 (an hour ago).
  TurnedPartInput hand;
  hand.row = parts.size() + 1;
  hand.part = "S-HAND";
  hand.feature = "D40";
  hand.cut_ms = now - kHourMs;
  hand.d_des_nm = 40000000;
  hand.d_w_nm = 40030000;
  hand.d_c_nm = 40010000;
  hand.d_pp_nm = 40016000;
  parts.push_back(hand);

  FieldErrors errors;
  auto recorded = turning.Record(machine, parts, "demo", &errors);
  if (!recorded.ok()) {
    return Status::Internal(
        "demo turned parts: " + recorded.status().message() +
        (errors.empty() ? "" : ": " + errors.front().field + " " + errors.front().message));
  }
  std::string shares;
  if (auto report = turning.Report(machine, start, now); report.ok()) {
    for (const TurnedFeatureReport& f : report->features) {
      if (f.feature != "D40" || !f.before || !f.after) continue;
      char text[96];
      std::snprintf(text, sizeof text, ", D40 thermal share %.2f before and %.2f after",
                    f.before->thermal_share.value_or(0), f.after->thermal_share.value_or(0));
      shares = text + std::string(" the compensation change of ") + FormatRfc3339(f.change->ts_ms);
    }
  }
  *summary = "turned parts: " + std::to_string(recorded->accepted) + " features of shafts on " +
             machine + shares + "; the newest D40 (S-HAND) is 40.000/40.030/40.010/40.016 mm: " +
             "δf +0.015, δth -0.010, δg +0.003, δtot +0.008 mm (GET /api/v1/machines/" + machine +
             "/turned-parts/report?format=markdown)";
  return Status::Ok();
}

}  // namespace thermocomp
