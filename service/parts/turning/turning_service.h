// TurningService: turned features measured four times (docs/model.md §15,
// docs/api.md "Turned parts"). Records a machine's parts (content rules
// here, whichever face parsed them; all or nothing in one transaction),
// pages a feature's history, and reports per feature the components, the
// thermal share over time and before/after the machine's latest
// compensation change (read from the archived fits and activations).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "core/plant_time.h"
#include "reports/parts/turning_report.h"
#include "service/config.h"
#include "storage/parts/turning_store.h"
#include "storage/storage.h"

namespace thermocomp {

// One parsed row: diameters in nm (already exact decimals), `row` the CSV
// data row (1 = first after the header) or the JSON item (from 0), which
// errors name.
struct TurnedPartInput {
  size_t row = 0;
  std::string part, feature;
  int64_t d_des_nm = 0, d_w_nm = 0, d_c_nm = 0, d_pp_nm = 0;
  int64_t cut_ms = 0;
};

struct TurnedPartsResult {
  int64_t accepted = 0, duplicates = 0;
  std::vector<TurnedPart> parts;  // every row of the request, decomposed
};

class TurningService {
 public:
  // A request holds at most this many rows (413 beyond).
  static constexpr size_t kMaxRows = 100000;
  // A measured diameter further than this from the drawing's is not the
  // feature (a wrong column, inch for mm, a typo): 400 naming the field.
  static constexpr int64_t kMaxDeviationNm = 1000000;  // 1 mm
  static constexpr int64_t kMaxHistoryLimit = 10000;
  static constexpr int64_t kDefaultHistoryLimit = 1000;
  // The report reads at most this many parts, newest kept (the period is
  // then narrowed, and says so by its `from`).
  static constexpr int64_t kMaxReportParts = 200000;

  // A part or feature name: [A-Za-z0-9_.-]{1,64}, the rule for what is
  // stored and for what a history query may ask for.
  static bool ValidName(const std::string& name);

  TurningService(Storage& storage, const Clock& clock, const Config& config);

  // InvalidArgument with `errors` naming row and field, TooLarge, NotFound
  // (machine), Conflict (a part and feature stored with other diameters).
  StatusOr<TurnedPartsResult> Record(const std::string& machine,
                                     const std::vector<TurnedPartInput>& parts,
                                     const std::string& actor, FieldErrors* errors);
  StatusOr<TurnedPartHistory> History(const std::string& machine, const TurnedPartQuery& query);
  // Parts cut within [from_ms, to_ms].
  StatusOr<TurningReport> Report(const std::string& machine, int64_t from_ms, int64_t to_ms);
  StatusOr<std::vector<CompensationChange>> CompensationChanges(const std::string& machine);

 private:
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  PlantTime time_;
};

}  // namespace thermocomp
