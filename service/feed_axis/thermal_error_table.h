// ThermalErrorTableService: each feed axis' thermal error now, as a table
// over its travel, and over time (docs/api.md, "Thermal error table").
//
// The active feed model (storage/feed_model_store.h) is rebuilt through its
// type; every other type falls back to the physical ("screw") model of the
// newest screw-type version that was not rejected. It is evaluated with the
// configured sensors' latest filtered temperatures on a grid over the
// travel: `spacing_mm` if asked, else the configured table_spacing_mm, else
// the reference check's targets (plus the travel's ends), else 10 mm.
//
// What is served keeps the rules of the compensation line
// (service/served_correction.h), per point: within the axis' clamp
// (AxisRecord::clamp_mm, the one in force now), moving towards the model's
// value at no more than compensation.max_rate_um_per_min at any point, held
// for hold_s when nothing valid replaces it, then ramped to 0. The rate
// state is kept on the axis' own grid; a table on another spacing serves
// the model's value plus the lag interpolated from it, so no grid steps.
// The best straight line (least squares over the axis' grid, for controls
// taking offset + slope) follows the same rules as a CorrectionLine
// (MoveToward, ClampOverTravel), so it never steps either. An axis first
// served after a start begins at the model's value. Every value is finite.
// Thread-safe.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "model/correction_line.h"
#include "service/config.h"
#include "service/served_correction.h"
#include "storage/storage.h"

namespace thermocomp {

struct FeedAxisConfig;  // service/feed_axis/feed_axis_config.h
class FeedModel;        // service/feed_axis/feed_model.h

struct ThermalErrorPoint {
  double position_mm = 0;
  // The model's thermal error here (µm, the axis is off by this; 0 where
  // the model gave no valid value).
  double error_um = 0;
  // What the control adds (µm): −error_um, except where the clamp limits it
  // or it is moving at the rate limit, held or ramped to 0.
  double correction_um = 0;
  bool valid = false;  // the model's own value from live inputs
};

// correction(P) = offset_um + slope_um_per_m·1e-3·(P − reference_position_mm).
struct ThermalErrorLine {
  double offset_um = 0;
  double slope_um_per_m = 0;
  double reference_position_mm = 0;
  double max_residual_um = 0;  // max |table correction − line| over the grid
  double rms_residual_um = 0;
};

struct ThermalErrorSensor {
  std::string name;
  std::optional<double> temperature_c;  // latest filtered value
  std::optional<int64_t> ts_ms;
  bool stale = false;
};

struct ThermalErrorTable {
  std::string machine, axis;
  int64_t computed_at_ms = 0;
  std::optional<int> model_version;
  std::string model_type;  // "" without an active model
  std::string fallback;    // "screw" when a guard made the physical model answer
  std::string grid;        // "spacing" | "reference_check" | "default"
  double spacing_mm = 0;   // 0 for the reference check's targets
  Travel travel;
  double reference_position_mm = 0;
  double clamp_mm = 0;
  std::vector<ThermalErrorSensor> sensors;
  std::vector<ThermalErrorPoint> points;
  ThermalErrorLine line;
  double max_abs_error_um = 0;                   // of the model's valid values over the grid
  std::optional<double> interpolation_bound_um;  // unknown with < 2 screw sensors
  bool valid = false, stale = false, clamped = false;
  ServedState state = ServedState::kOff;
  std::string reason;  // why not valid, or what the fallback replaced
  std::optional<double> input_age_s;

  // The bits of CompensationStatusBit.
  int StatusWord() const;
};

struct ThermalErrorHistoryPoint {
  int64_t ts_ms = 0;
  std::vector<double> error_um;  // at each of the history's positions; 0 when not valid
  double max_abs_error_um = 0;   // over the axis' grid
  bool valid = false;
  std::string fallback;
  std::string reason;
};

struct ThermalErrorHistory {
  std::string machine, axis;
  std::optional<int> model_version;
  std::string model_type;
  int64_t from_ms = 0, to_ms = 0;
  std::vector<double> positions_mm;
  std::vector<ThermalErrorHistoryPoint> points;
  std::string reason;  // why there are no points
};

class ThermalErrorTableService {
 public:
  static constexpr double kMinSpacingMm = 1, kMaxSpacingMm = 1000;
  static constexpr size_t kMaxPoints = 10000;
  static constexpr size_t kMaxHistoryPoints = 2000;
  static constexpr size_t kMaxHistoryPositions = 20;

  ThermalErrorTableService(Storage& storage, const Clock& clock, const Config& config);

  // NotFound for an unknown machine or axis; InvalidArgument naming
  // spacing_mm when it is outside 1..1000 mm or gives more than 10 000
  // points. An axis without a configuration or an active model is a table
  // with valid false and the reason (as the compensation serves it "off").
  StatusOr<ThermalErrorTable> Table(const std::string& machine, const std::string& axis,
                                    std::optional<double> spacing_mm = std::nullopt);

  // The error at `positions_mm` (default: the travel's ends) and max |error|
  // over the travel at up to `max_points` times spread evenly over
  // [from, to], from the archived filtered temperatures at each time (a
  // sensor without a sample within stale_after_s before it makes that time
  // not valid). InvalidArgument naming positions for positions outside the
  // travel or more than 20 of them.
  StatusOr<ThermalErrorHistory> History(const std::string& machine, const std::string& axis,
                                        int64_t from_ms, int64_t to_ms,
                                        std::vector<double> positions_mm, size_t max_points);

  // The machine's axes with a screw configuration; none for an unknown one.
  std::vector<std::string> ConfiguredAxes(const std::string& machine);

 private:
  // The model of one axis as the table and the history evaluate it
  // (thermal_error_table.cc, thermal_error_history.cc).
  struct AxisModel {
    std::optional<MachineRecord> machine;
    const AxisRecord* axis = nullptr;
    std::shared_ptr<const FeedAxisConfig> config;  // none when missing or unreadable
    Travel travel;
    std::shared_ptr<const FeedModel> model;
    std::optional<int> version;
    std::string type;
    std::string reason;                // why there is no model to evaluate
    std::vector<std::string> sensors;  // screw sensors, then body sensors
  };
  StatusOr<AxisModel> Load(Session& session, const std::string& machine, const std::string& axis);
  // min, min + s, ..., max (the last step may be shorter).
  static std::vector<double> SpacedGrid(const Travel& t, double spacing_mm);
  struct Rated {  // what was served last on the axis' own grid, and its line
    std::vector<double> position_mm, correction_um;
    CorrectionLine line;
    int64_t at_ms = 0;
    std::optional<int64_t> invalid_since_ms;
  };
  struct Serving {
    std::vector<double> correction_um;
    CorrectionLine line;
    ServedState state = ServedState::kOff;
    bool clamped = false;
  };
  // Moves the axis' served table on its own grid to `now` towards `target`
  // (valid or not) and returns it.
  Serving ServeGrid(const std::string& key, const std::vector<double>& position_mm,
                    const std::vector<double>& target_um, const CorrectionLine& target_line,
                    bool valid, double reference_mm, const Travel& travel, double clamp_um,
                    int64_t now_ms);
  // When each input last received a sample, as this server saw it.
  int64_t ArrivalOf(const std::string& key, int64_t last_ts_ms, int64_t now_mono_ms);

  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  std::mutex mutex_;
  std::map<std::string, Rated> rated_;  // by "machine/axis"
  std::map<std::string, int64_t> arrival_ts_, arrival_mono_;
};

}  // namespace thermocomp
