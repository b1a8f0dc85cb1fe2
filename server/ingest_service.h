// IngestService: validates and stores temperatures and probe points. Every
// source (HTTP, CSV import, DDS) goes through here, so the rules are the
// same everywhere. A batch is all-or-nothing: one transaction, committed
// before the caller acknowledges anything.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "model/status.h"
#include "server/clock.h"
#include "server/probe_temperature_cache.h"
#include "storage/database.h"
#include "storage/records.h"

namespace thermocomp {

struct TemperatureInput {
  std::string sensor;
  int64_t ts_ms = 0;
  double value = 0;
};

struct ProbePointInput {
  std::string run;
  int k = 0;
  int64_t ts_ms = 0;
  std::map<std::string, AxisValue> axes;       // positions and deviations by axis
  std::map<std::string, double> temperatures;  // optional filtered snapshot
};

// One rejected item of a batch: where, which field, why.
struct FieldError {
  size_t index = 0;
  std::string field;
  std::string message;
};

struct IngestResult {
  Status status;
  std::vector<FieldError> errors;
  int accepted = 0;
  int duplicates = 0;
};

// Limits shared by every ingest path.
constexpr double kMinTemperatureC = -40.0;
constexpr double kMaxTemperatureC = 150.0;
constexpr int64_t kEarliestTsMs = 946684800000;  // 2000-01-01T00:00:00Z
constexpr int64_t kMaxFutureMs = 24 * 3600 * 1000;
constexpr double kMaxAbsDeviationMm = 10.0;

bool ValidIdentifier(const std::string& id);  // [A-Za-z0-9_.-]{1,64}
bool ValidAxisName(const std::string& axis);  // X Y Z A B C U V W

class IngestService {
 public:
  using Listener = std::function<void(const std::string& machine)>;
  IngestService(Database& db, const Clock& clock, ProbeTemperatureCache* cache = nullptr)
      : db_(db), clock_(clock), cache_(cache) {}

  IngestResult AddTemperatures(const std::string& machine,
                               const std::vector<TemperatureInput>& samples,
                               const std::string& actor);
  IngestResult AddProbePoints(const std::string& machine,
                              const std::vector<ProbePointInput>& points, const std::string& actor);
  // Called after a commit that changed the machine's data.
  void SetListener(Listener listener) { listener_ = std::move(listener); }

 private:
  Status CheckTs(int64_t ts_ms) const;
  Database& db_;
  const Clock& clock_;
  ProbeTemperatureCache* cache_;
  Listener listener_;
};

}  // namespace thermocomp
