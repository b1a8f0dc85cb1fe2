#include "api/parts/process_csv.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

#include "api/csv_cells.h"
#include "core/process_record.h"
#include "core/time_format.h"
#include "reports/json_text.h"

namespace thermocomp::api {
namespace {

// A finite number; "nan", "inf" and 1e999 are not.
std::optional<double> FiniteNumber(std::string_view s) {
  if (s.empty() || s.size() > 64) return std::nullopt;
  const std::string text(s);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

// The line of the first invalid UTF-8 byte (0 = the header).
size_t LineOfBadUtf8(std::string_view body) {
  size_t lo = 0, line = 0;
  while (lo < body.size()) {
    size_t end = body.find('\n', lo);
    if (end == std::string_view::npos) end = body.size();
    if (!ValidUtf8(body.substr(lo, end - lo))) return line;
    lo = end + 1;
    ++line;
  }
  return line;
}

const char* kHeaderHelp =
    "the header must name part, feature, cut_at, ap_mm, f_mm_rev, vc_m_min and at least one of "
    "size_error_um, cylindricity_um, roundness_um (optional: fc_n, ff_n, fp_n, displacement_um, "
    "temperature_c)";

}  // namespace

Status ParseProcessCsv(std::string_view body, std::vector<ProcessRecordInput>& out,
                       std::vector<size_t>& rows, FieldErrors& errors) {
  if (!ValidUtf8(body)) {
    const size_t line = LineOfBadUtf8(body);
    errors.push_back({line, line == 0 ? "header" : "row", "not valid UTF-8"});
    return Status::InvalidArgument("the CSV is not valid UTF-8 (row " + std::to_string(line) + ")");
  }
  if (body.size() >= 3 && body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);  // BOM
  // The header: the first line.
  size_t pos = body.find('\n');
  const std::string_view header_line = TrimCell(body.substr(0, pos));
  if (header_line.empty()) {
    errors.push_back({0, "header", std::string("empty header: ") + kHeaderHelp});
    return Status::InvalidArgument(std::string("empty header: ") + kHeaderHelp);
  }
  const std::vector<std::string_view> header = CsvCells(header_line);
  const std::vector<std::string>& fields = ProcessRecordFields();
  std::vector<std::string> names;
  for (std::string_view h : header) {
    const std::string name(h);
    const bool known = name == "part" || name == "feature" || name == "cut_at" ||
                       std::find(fields.begin(), fields.end(), name) != fields.end();
    if (!known) errors.push_back({0, name.empty() ? "header" : name, "unknown column"});
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      errors.push_back({0, name, "column named twice in the header"});
    }
    names.push_back(name);
  }
  auto has = [&](const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  for (const char* required : {"part", "feature", "cut_at", "ap_mm", "f_mm_rev", "vc_m_min"}) {
    if (!has(required)) errors.push_back({0, required, "missing column"});
  }
  if (!has("size_error_um") && !has("cylindricity_um") && !has("roundness_um")) {
    errors.push_back({0, "size_error_um", "missing column (no measured error in the file)"});
  }
  if (!errors.empty()) return Status::InvalidArgument(std::string("bad header: ") + kHeaderHelp);

  size_t row = 0;
  while (pos != std::string_view::npos && pos < body.size()) {
    const size_t start = pos + 1;
    pos = body.find('\n', start);
    const std::string_view line =
        TrimCell(body.substr(start, pos == std::string_view::npos ? pos : pos - start));
    ++row;
    if (row > kMaxProcessCsvRows) {
      errors.push_back({row, "row",
                        "more than " + std::to_string(kMaxProcessCsvRows) +
                            " rows after the header (blank ones included)"});
      return Status::TooLarge("at most " + std::to_string(kMaxProcessCsvRows) +
                              " rows after the header");
    }
    if (line.empty()) continue;
    const std::vector<std::string_view> cells = CsvCells(line);
    if (cells.size() != names.size()) {
      errors.push_back({row, "row",
                        std::to_string(cells.size()) + " cells where the header has " +
                            std::to_string(names.size())});
      continue;
    }
    ProcessRecordInput r;
    bool ok = true;
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string& name = names[c];
      const std::string_view cell = cells[c];
      if (name == "part") {
        r.part = std::string(cell);
      } else if (name == "feature") {
        r.feature = std::string(cell);
      } else if (name == "cut_at") {
        const auto ts = ParseTimestamp(cell);
        if (!ts) {
          errors.push_back({row, name, "must be RFC 3339 or Unix milliseconds, 2000 to 2099"});
          ok = false;
        } else {
          r.cut_ms = *ts;
        }
      } else if (cell.empty()) {
        // Not logged or not measured; the service says whether it was needed.
      } else if (const auto v = FiniteNumber(cell)) {
        r.values[name] = *v;
      } else {
        errors.push_back(
            {row, name, "must be a finite number, got '" + std::string(cell.substr(0, 32)) + "'"});
        ok = false;
      }
    }
    if (ok) {
      out.push_back(std::move(r));
      rows.push_back(row);
    }
  }
  if (!errors.empty()) return Status::InvalidArgument("invalid process records");
  if (out.empty()) {
    errors.push_back({0, "body", "no records after the header"});
    return Status::InvalidArgument("no records after the header");
  }
  return Status::Ok();
}

}  // namespace thermocomp::api
