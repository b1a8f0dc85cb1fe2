// Shared by the plate tests: a simulated plate's machine history put into a
// real App (temperatures through ingest, the served log through the store,
// as the compensation service would have logged it), and plain-loop
// statistics written here, independent of model/parts/plate_stats.cc.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "service/app.h"
#include "sim/parts/plate_sim.h"
#include "sim/virtual_machine.h"

namespace thermocomp::testing {

inline void LoadPlateHistory(App& app, const std::string& machine, const SimulatedPlate& plate) {
  if (!app.machines().Find(machine)) {
    FieldErrors errors;
    ASSERT_TRUE(app.machines().Register(VirtualMachine::Definition(machine), "test", &errors).ok());
  }
  ASSERT_TRUE(app.ingest().AddTemperatures(machine, plate.samples, "test").status.ok());
  const std::unique_ptr<Session> session = app.storage().Open();
  auto m = session->machines().Find(machine);
  ASSERT_TRUE(m.has_value());
  const AxisRecord* y = m->FindAxis("Y");
  ASSERT_NE(y, nullptr);
  Transaction tx(*session);
  ASSERT_TRUE(tx.status().ok());
  for (const auto& row : plate.served)
    ASSERT_TRUE(session->log().AppendCompensation(y->id, row).ok());
  ASSERT_TRUE(tx.Commit().ok());
}

// S with n - 1 and R = max - min, by plain loops.
inline double LoopS(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}
inline double LoopR(const std::vector<double>& v) {
  double lo = v[0], hi = v[0];
  for (double x : v) {
    lo = x < lo ? x : lo;
    hi = x > hi ? x : hi;
  }
  return hi - lo;
}

}  // namespace thermocomp::testing
