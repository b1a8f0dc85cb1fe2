// PlateService: test plates (docs/model.md §15.1, docs/api.md "Test
// plates"). Import takes a plate's CMM results for a machine and an axis
// (X or Y), checks every hole (the row named in the error), joins each hole
// with the compensation served at its bore time (ServedAt: the newest row
// of the served log at or before it, at most a day old) and the machine's
// filtered temperatures then (each sensor's newest sample at or before it,
// at most kPlateTemperatureMaxAgeMs old), stores the plate and its holes in
// one transaction and answers with the report; nothing is stored on any
// error. List and Report read back; the report is computed from the stored
// holes (model/parts/plate_stats.h), so it follows the statistics' code.
#pragma once

#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "reports/parts/plate_report.h"
#include "service/config.h"
#include "storage/parts/plate_store.h"
#include "storage/storage.h"

namespace thermocomp {

// One CMM row as the parser read it (lengths mm, time Unix ms).
struct PlateHoleInput {
  std::string hole;
  int pair = 0;
  double nominal_x_mm = 0, nominal_y_mm = 0;
  double dev_x_mm = 0, dev_y_mm = 0;
  bool compensated = false;
  int64_t bored_ms = 0;
};

struct PlateImport {
  std::string machine, plate, axis, actor;
  std::vector<PlateHoleInput> holes;  // holes[i] is CSV data row i + 1
};

// Holes a plate may have.
inline constexpr size_t kMaxPlateHoles = 10000;
// A CMM deviation beyond this is not a thermal error of a hole (or not in mm).
inline constexpr double kMaxPlateDeviationMm = 1.0;
// Nominal positions within +-this (mm).
inline constexpr double kMaxPlateNominalMm = 10000.0;
// A plate is bored within this span; a bore time may be at most
// kPlateMaxFutureMs ahead of the server's clock.
inline constexpr int64_t kMaxPlateSpanMs = 7 * 86400000LL;
inline constexpr int64_t kPlateMaxFutureMs = 300000;
// A temperature older than this at a bore time is not joined.
inline constexpr int64_t kPlateTemperatureMaxAgeMs = 600000;

class PlateService {
 public:
  PlateService(Storage& storage, const Clock& clock, const Config& config);

  // InvalidArgument (400) for a bad name or axis parameter, NotFound for an
  // unknown machine or an axis it lacks, Unprocessable (422) with `errors`
  // (index = CSV data row, 1 = first after the header) for bad holes,
  // TooLarge beyond kMaxPlateHoles, Conflict if the plate name exists.
  StatusOr<PlateReport> Import(const PlateImport& in, FieldErrors* errors);
  // NotFound for an unknown machine.
  StatusOr<std::vector<PlateSummary>> List(const std::string& machine);
  // NotFound for an unknown machine or plate.
  StatusOr<PlateReport> Report(const std::string& machine, const std::string& plate);

  // The report of stored holes (pure; what Report and Import both use).
  static StatusOr<PlateReport> ReportOf(const std::string& machine, const PlateRecord& plate);

 private:
  Storage& storage_;
  const Clock& clock_;
  [[maybe_unused]] const Config& config_;
};

// Whether `name` is a plate name: [A-Za-z0-9_.-]{1,64}, as in the paths.
bool ValidPlateName(const std::string& name);

}  // namespace thermocomp
