// CheckService: column checks on the reference artifact and ISO 230-2
// positioning checks (docs/model.md §11). Requests are made by maintenance
// or weekly per machine; a column check answers one (named, or the oldest
// open one), is corrected for the artifact's expansion and evaluated, and a
// machine-zero change beyond the tolerance since the previous check is
// logged as a column_check event (a step the effect search can try).
// Positioning checks are evaluated completely and give pitch tables.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "model/pitch_table.h"
#include "reports/check_codec.h"
#include "reports/check_reports.h"
#include "reports/machine_status.h"
#include "service/config.h"
#include "storage/check_store.h"
#include "storage/storage.h"

namespace thermocomp {

// The longest name an acknowledgement records, in characters.
inline constexpr size_t kMaxAcknowledgerLength = 64;

struct RequestView {
  CheckRequestRecord record;
  std::string state;  // pending | overdue | done
};

class CheckService {
 public:
  CheckService(Storage& storage, const Clock& clock, const Config& config)
      : storage_(storage), clock_(clock), config_(config) {}

  // Validates the definition; returns true when it was new.
  StatusOr<bool> PutArtifact(const std::string& name, const nlohmann::json& definition,
                             const std::string& actor, FieldErrors* errors);
  // The stored definition as it was put; NotFound for an unknown name.
  StatusOr<nlohmann::json> Artifact(const std::string& name);
  StatusOr<int64_t> RequestCheck(const std::string& machine, const std::string& reason,
                                 int64_t due_ms, const std::string& actor);
  // state: empty for all, or pending | overdue | done.
  StatusOr<std::vector<RequestView>> Requests(const std::string& machine, const std::string& state);
  // Acknowledges request `id` of the machine: the line or maintenance has
  // seen it and will run the check. `by` is who (1 to kMaxAcknowledgerLength
  // characters, none a control character), nullopt when not known. The
  // first acknowledgement is kept: acknowledging again returns the request
  // unchanged and audits nothing. NotFound for an unknown machine or a
  // request it does not have; Conflict when the request is done;
  // InvalidArgument with `errors` naming "by", nothing stored, when `by` is
  // not a name.
  StatusOr<RequestView> Acknowledge(const std::string& machine, int64_t id,
                                    const std::optional<std::string>& by, const std::string& actor,
                                    FieldErrors* errors);
  // Creates the weekly request of every machine that had no request or
  // check for check_every_days; returns how many. Called by the scheduler.
  int EnsurePeriodicRequests();

  // The stored result (with "id"); a resent identical check returns the
  // stored one with `created` false.
  StatusOr<ColumnCheckReport> AddColumnCheck(const std::string& machine, const ColumnCheckInput& in,
                                             const std::string& actor, bool* created);
  // History oldest first and the machine-zero trend (um per week, least squares).
  StatusOr<ColumnCheckHistory> ColumnChecks(const std::string& machine);
  StatusOr<ColumnCheckReport> ColumnCheck(const std::string& machine, int64_t id);

  StatusOr<PositioningCheckReport> AddPositioningCheck(const std::string& machine,
                                                       const PositioningInput& in,
                                                       const std::string& actor, bool* created);
  StatusOr<PositioningCheckReport> PositioningCheck(const std::string& machine, int64_t id);
  // The machine's positioning checks, oldest first; of one axis when `axis`
  // is not empty.
  StatusOr<std::vector<PositioningCheckSummary>> PositioningChecks(const std::string& machine,
                                                                   const std::string& axis);
  StatusOr<PitchTable> PitchTableOf(const std::string& machine, int64_t id, std::string* axis);

 private:
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
};

nlohmann::json RequestToJson(const RequestView& v);
// Pending and overdue requests of a machine now.
CheckCounts CountChecks(Session& s, int64_t machine_id, int64_t now_ms);
// The newest column check's machine zero and whether it moved beyond the
// tolerance, for the machine status; none without checks.
std::optional<LastColumnCheck> LatestColumnCheckSummary(Session& s, int64_t machine_id);

}  // namespace thermocomp
