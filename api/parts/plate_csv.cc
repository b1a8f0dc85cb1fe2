#include "api/parts/plate_csv.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/time_format.h"
#include "reports/json_text.h"

namespace thermocomp::api {
namespace {

constexpr std::array<const char*, 8> kColumns = {"hole",         "pair",     "nominal_x_mm",
                                                 "nominal_y_mm", "dev_x_mm", "dev_y_mm",
                                                 "compensation", "bored_at"};
enum Column { kHole, kPair, kNominalX, kNominalY, kDevX, kDevY, kCompensation, kBoredAt };

// One line into cells: commas separate, a cell in double quotes may hold
// commas and "" for a quote. False for an unterminated quote.
bool SplitLine(std::string_view line, std::vector<std::string>& cells) {
  cells.clear();
  std::string cell;
  bool quoted = false, was_quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"' && cell.empty() && !was_quoted) {
      quoted = was_quoted = true;
    } else if (c == ',') {
      cells.push_back(std::move(cell));
      cell.clear();
      was_quoted = false;
    } else {
      cell += c;
    }
  }
  if (quoted) return false;
  cells.push_back(std::move(cell));
  return true;
}

std::string Trimmed(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  return s.substr(a, b - a);
}

std::optional<double> FiniteNumber(const std::string& s) {
  if (s.empty() || s.size() > 64) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

}  // namespace

Status ParsePlateCsv(std::string_view body, std::vector<PlateHoleInput>& out, FieldErrors& errors) {
  if (!ValidUtf8(body)) {
    errors.push_back({0, "body", "not valid UTF-8"});
    return Status::InvalidArgument("the CSV is not valid UTF-8");
  }
  if (body.size() >= 3 && body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);  // BOM
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start <= body.size()) {
    size_t end = body.find('\n', start);
    if (end == std::string_view::npos) end = body.size();
    std::string_view line = body.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (end == body.size() && line.empty()) break;  // after the last newline
    lines.push_back(line);
    if (lines.size() > kMaxPlateCsvLines) {
      errors.push_back({lines.size() - 1, "row",
                        "more than " + std::to_string(kMaxPlateHoles) + " rows after the header"});
      return Status::TooLarge("a plate file has at most " + std::to_string(kMaxPlateHoles) +
                              " rows after the header");
    }
    start = end + 1;
  }
  const std::string header_help =
      "the header must be hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,"
      "bored_at";
  if (lines.empty()) {
    errors.push_back({0, "header", "empty file: " + header_help});
    return Status::InvalidArgument("empty file: " + header_help);
  }
  std::vector<std::string> cells;
  if (!SplitLine(lines[0], cells)) {
    errors.push_back({0, "header", "unterminated quote"});
    return Status::InvalidArgument("header: unterminated quote");
  }
  std::array<int, kColumns.size()> index{};
  index.fill(-1);
  for (size_t c = 0; c < cells.size(); ++c) {
    const std::string name = Trimmed(cells[c]);
    bool known = false;
    for (size_t k = 0; k < kColumns.size(); ++k) {
      if (name != kColumns[k]) continue;
      known = true;
      if (index[k] >= 0)
        errors.push_back({0, name, "column appears twice in the header"});
      else
        index[k] = static_cast<int>(c);
    }
    if (!known) {
      std::string message = "unknown column '" + name + "': ";
      message += header_help;
      errors.push_back({0, "header", std::move(message)});
    }
  }
  for (size_t k = 0; k < kColumns.size(); ++k) {
    if (index[k] < 0) errors.push_back({0, kColumns[k], "missing column: " + header_help});
  }
  if (!errors.empty()) return Status::InvalidArgument("header: " + errors.front().message);
  const size_t width = cells.size();
  out.reserve(lines.size() - 1);
  for (size_t r = 1; r < lines.size(); ++r) {
    if (Trimmed(std::string(lines[r])).empty()) continue;  // a blank line
    if (!SplitLine(lines[r], cells)) {
      errors.push_back({r, "row", "unterminated quote"});
      continue;
    }
    if (cells.size() != width) {
      errors.push_back(
          {r, "row",
           "expected " + std::to_string(width) + " fields, got " + std::to_string(cells.size())});
      continue;
    }
    auto cell = [&](Column c) { return Trimmed(cells[static_cast<size_t>(index[c])]); };
    PlateHoleInput h;
    h.hole = cell(kHole);
    if (h.hole.empty()) errors.push_back({r, "hole", "empty"});
    const std::string pair = cell(kPair);
    int p = 0;
    auto [ptr, ec] = std::from_chars(pair.data(), pair.data() + pair.size(), p);
    if (ec != std::errc() || ptr != pair.data() + pair.size() || pair.empty() || p < 1 ||
        p > 1000000) {
      errors.push_back({r, "pair", "must be an integer 1..1000000"});
    }
    h.pair = p;
    const std::array<std::pair<Column, double*>, 4> numbers = {
        std::pair{kNominalX, &h.nominal_x_mm}, std::pair{kNominalY, &h.nominal_y_mm},
        std::pair{kDevX, &h.dev_x_mm}, std::pair{kDevY, &h.dev_y_mm}};
    for (const auto& [column, target] : numbers) {
      auto v = FiniteNumber(cell(column));
      if (!v)
        errors.push_back({r, kColumns[column], "not a finite number"});
      else
        *target = *v;
    }
    const std::string comp = cell(kCompensation);
    if (comp == "on" || comp == "ON" || comp == "On") {
      h.compensated = true;
    } else if (comp == "off" || comp == "OFF" || comp == "Off") {
      h.compensated = false;
    } else {
      errors.push_back({r, "compensation", "must be on or off"});
    }
    if (auto ts = ParseTimestamp(cell(kBoredAt))) {
      h.bored_ms = *ts;
    } else {
      errors.push_back({r, "bored_at", "must be RFC 3339 or Unix ms within 2000-2099"});
    }
    if (errors.empty()) out.push_back(std::move(h));
  }
  if (!errors.empty()) {
    const FieldError& e = errors.front();
    return Status::InvalidArgument("row " + std::to_string(e.index) + ", " + e.field + ": " +
                                   e.message);
  }
  if (out.empty()) {
    errors.push_back({0, "body", "no holes after the header"});
    return Status::InvalidArgument("no holes after the header");
  }
  return Status::Ok();
}

}  // namespace thermocomp::api
