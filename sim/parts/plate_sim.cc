#include "sim/parts/plate_sim.h"

#include <cstdio>
#include <deque>
#include <map>
#include <random>

#include "core/time_format.h"
#include "core/time_units.h"
#include "sim/virtual_machine.h"

namespace thermocomp {
namespace {

// The declared Y law of the virtual machine on sensed temperatures.
double DeclaredLawMm(const std::map<std::string, double>& t,
                     const std::map<std::string, double>& t0) {
  auto d = [&](const char* s) { return t.at(s) - t0.at(s); };
  return -0.0126 * d("Tcb") + 0.0098 * d("Tbed") - 0.0025 * d("Tco");
}

std::map<std::string, double> ByName(const std::vector<TemperatureInput>& minute) {
  std::map<std::string, double> out;
  for (const auto& s : minute) out[s.sensor] = s.value;
  return out;
}

// A hole's place: pair p (1-based) in level (p-1)/pairs_per_level.
struct Slot {
  double x_on, x_off, y;
};
Slot SlotOf(const PlateSimOptions& o, int pair) {
  const int level = (pair - 1) / o.pairs_per_level;
  const int col = (pair - 1) % o.pairs_per_level;
  const double x = o.first_x_mm + o.pair_pitch_x_mm * col;
  return {x, x + o.hole_pitch_x_mm, o.first_level_y_mm + o.level_pitch_mm * level};
}

}  // namespace

SimulatedPlate SimulatePlate(const PlateSimOptions& o) {
  SimOptions vo;
  vo.machine = "plate";
  vo.seed = o.seed;
  vo.start_ms = o.start_ms;
  VirtualMachine vm(vo);
  std::mt19937_64 rng(o.seed * 7919 + 17);
  std::normal_distribution<double> noise(0.0, o.cmm_noise_mm);

  SimulatedPlate out;
  out.cmm_noise_mm = o.cmm_noise_mm;
  std::deque<std::vector<TemperatureInput>> recent;  // the last history_min minutes
  std::vector<TemperatureInput> minute;
  std::vector<ProbePointInput> points;
  const auto warmup_ms = static_cast<int64_t>(o.warmup_h * 3600000.0);
  bool was_in_run = true;  // a run under way at the start does not count
  // Warm up, then wait for the start of a run.
  while (true) {
    minute.clear();
    points.clear();
    vm.Step(minute, points);
    recent.push_back(minute);
    if (static_cast<int>(recent.size()) > o.history_min) recent.pop_front();
    const bool starts = vm.in_run() && !was_in_run;
    was_in_run = vm.in_run();
    if (starts && vm.now_ms() - o.start_ms >= warmup_ms) break;
  }
  out.plate_start_ms = vm.now_ms();
  for (const auto& m : recent) out.samples.insert(out.samples.end(), m.begin(), m.end());
  const std::map<std::string, double> t0 = ByName(minute);
  const double drift0_y = vm.TrueDriftY();
  const double drift0_x = vm.TrueDriftX();

  const int n_pairs = o.levels * o.pairs_per_level;
  const int64_t end_ms =
      out.plate_start_ms + (static_cast<int64_t>(n_pairs) + 1) * o.pair_interval_min * kMinuteMs;
  int bored = 0;  // pairs bored so far
  for (int64_t elapsed_min = 0;; ++elapsed_min) {
    if (elapsed_min > 0) {
      minute.clear();
      points.clear();
      vm.Step(minute, points);
      out.samples.insert(out.samples.end(), minute.begin(), minute.end());
    }
    const int64_t now = vm.now_ms();
    const double predicted = o.drift_scale * o.model_gain * DeclaredLawMm(ByName(minute), t0);
    CompensationLogRow row;
    row.ts_ms = now;
    row.offset_mm = -predicted;
    row.predicted_drift_mm = predicted;
    row.valid = true;
    row.model_version = o.model_version;
    out.served.push_back(row);
    const double drift_y = o.drift_scale * (vm.TrueDriftY() - drift0_y);
    const double drift_x = o.drift_scale * (vm.TrueDriftX() - drift0_x);
    // A pair every pair_interval_min from the first interval on; its second
    // hole two minutes after the first, bored at that minute's state.
    const int64_t since_pair = elapsed_min - static_cast<int64_t>(bored + 1) * o.pair_interval_min;
    if (bored < n_pairs && (since_pair == 0 || since_pair == 2)) {
      const int pair = o.reverse ? n_pairs - bored : bored + 1;
      const bool first_hole = since_pair == 0;
      // Odd pairs in bore order start with the compensated hole.
      const bool on = (bored % 2 == 0) == first_hole;
      const Slot slot = SlotOf(o, pair);
      PlateSimHole h;
      h.pair = pair;
      h.hole = "P" + std::to_string(pair) + (on ? "-on" : "-off");
      h.compensated = on;
      h.nominal_x_mm = on ? slot.x_on : slot.x_off;
      h.nominal_y_mm = slot.y;
      h.bored_ms = now + 20000;
      h.true_drift_y_mm = drift_y;
      h.predicted_y_mm = predicted;
      h.true_dev_y_mm = on ? drift_y - predicted : drift_y;
      h.dev_y_mm = h.true_dev_y_mm + noise(rng);
      h.dev_x_mm = drift_x + noise(rng);
      out.holes.push_back(h);
      if (!first_hole) ++bored;
    }
    if (now >= end_ms) break;
  }
  return out;
}

std::string SimulatedPlate::Csv() const {
  std::string csv = "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,bored_at\n";
  char buf[256];
  for (const auto& h : holes) {
    std::snprintf(buf, sizeof buf, "%s,%d,%.3f,%.3f,%.6f,%.6f,%s,%s\n", h.hole.c_str(), h.pair,
                  h.nominal_x_mm, h.nominal_y_mm, h.dev_x_mm, h.dev_y_mm,
                  h.compensated ? "on" : "off", FormatRfc3339(h.bored_ms).c_str());
    csv += buf;
  }
  return csv;
}

}  // namespace thermocomp
