// AppliedCompensationService: what each machine's control reports it has
// applied of the served compensation (docs/api.md, "Compensation out"): a
// PLC, directly or through the OPC UA face, names the axis and its own
// sequence number after writing the values into the CNC. A report of the
// sequence the axis' newest record already holds is a retry: nothing is
// stored and the stored record is returned. Each new record and its audit
// line are one transaction.
// The newest record per axis is kept in memory (loaded once per machine,
// an index seek per axis, and replaced by every write), because every
// compensation read shows it: a read costs no query, whatever the history.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "core/status.h"
#include "storage/applied_store.h"
#include "storage/storage.h"

namespace thermocomp {

// The largest sequence taken: 2^53 - 1, the largest integer a JSON reader
// using doubles (the OPC UA face's JavaScript) keeps exactly.
inline constexpr int64_t kMaxAppliedSequence = (int64_t{1} << 53) - 1;
// The bound of each stated value (|v|), far beyond any clamp.
inline constexpr double kMaxAppliedValue = 1000;

struct AppliedInput {
  std::string axis;
  int64_t sequence = 0;
  std::optional<double> offset_mm, slope_um_per_m, offset_at_probe_mm;
  std::string via = "http";  // [a-z0-9_-]{1,32}
};

struct AppliedResult {
  std::string axis;
  AppliedRecord record;
  bool created = false;  // false: a retry of the newest record
};

// The newest record of each axis that has one, by axis id.
using AppliedByAxis = std::map<int64_t, AppliedRecord>;

class AppliedCompensationService {
 public:
  AppliedCompensationService(Storage& storage, const Clock& clock)
      : storage_(storage), clock_(clock) {}

  // Validates `in` (a bad field is InvalidArgument, an axis the machine
  // does not declare Unprocessable, each named in `errors`) and stores it
  // unless it repeats the axis' newest sequence. NotFound for an unknown
  // machine.
  StatusOr<AppliedResult> Record(const std::string& machine, const AppliedInput& in,
                                 const std::string& actor, FieldErrors* errors);
  // The newest record per axis; NotFound for an unknown machine. The same
  // pointer while nothing is recorded for the machine, so a caller may
  // cache what it derives from it by pointer.
  StatusOr<std::shared_ptr<const AppliedByAxis>> Newest(const std::string& machine);
  // An axis' records newest first, at most `limit`.
  StatusOr<std::vector<AppliedRecord>> History(const std::string& machine, const std::string& axis,
                                               int limit);

 private:
  Storage& storage_;
  const Clock& clock_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const AppliedByAxis>> newest_;  // per machine
};

// Why `via` is not a valid source name, or "".
std::string AppliedViaError(const std::string& via);

}  // namespace thermocomp
