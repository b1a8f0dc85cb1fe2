// TemperatureResampler: turns an MTConnect agent's on-change Temperature
// observations into samples on thermocomp's grid (every 60 s on the UTC
// minute). An item's value holds from its observation's time until the
// next one; each grid point gets the value held at it (the last observation
// at or before it). A grid point is emitted once it is known: when the next
// observation comes, or when the agent has reported everything up to it
// (AdvanceTo). UNAVAILABLE stops an item's points until a value comes back.
// A grid point is never emitted twice for an item, even across Forget()
// (an agent restart, a buffer wrap), so a re-read yields nothing new and
// the archive's (sensor, time) key never sees two values.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

inline constexpr int64_t kGridMs = 60000;
// At most this many grid points are filled from one held value at a time
// (one day): a value the agent has held for a year is not a year of rows.
inline constexpr int64_t kMaxHeldPoints = 1440;

struct GridSample {
  std::string data_item_id;
  int64_t ts_ms = 0;
  double value = 0;
};

class TemperatureResampler {
 public:
  // One observation, in sequence order; no value is UNAVAILABLE. Appends the
  // grid points the previous value held for before `ts_ms`. True when the
  // item became unavailable with this observation (a gap starts).
  bool Observe(const std::string& item, int64_t ts_ms, std::optional<double> value,
               std::vector<GridSample>* out);
  // The agent has reported every change up to `ts_ms` (inclusive): appends
  // the held values' grid points up to it.
  void AdvanceTo(int64_t ts_ms, std::vector<GridSample>* out);
  // Forgets the held values (they may have changed unseen), keeping which
  // grid points were emitted.
  void Forget();
  // Nothing at or before `ts_ms` is emitted for `item` (what the archive
  // already holds).
  void SetEmittedThrough(const std::string& item, int64_t ts_ms);
  std::optional<int64_t> EmittedThrough(const std::string& item) const;

 private:
  struct Held {
    bool held = false;  // a value is known (else unknown or UNAVAILABLE)
    double value = 0;
    int64_t since_ms = 0;
    std::optional<int64_t> emitted_through;
  };
  // Appends the grid points in [max(since, emitted+1), until_ms] for `h`.
  static void Emit(const std::string& item, Held& h, int64_t until_ms,
                   std::vector<GridSample>* out);
  std::map<std::string, Held> items_;
};

}  // namespace thermocomp
