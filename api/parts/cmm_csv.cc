#include "api/parts/cmm_csv.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <unordered_map>

namespace thermocomp::api {
namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

// The 1-based line of the first byte that is not UTF-8, or 0 when all is.
size_t FirstBadUtf8Line(std::string_view s) {
  size_t line = 1;
  for (size_t p = 0; p < s.size();) {
    const auto c = static_cast<unsigned char>(s[p]);
    if (c == '\n') ++line;
    size_t extra = 0;
    unsigned min = 0;
    if (c < 0x80) {
      ++p;
      continue;
    }
    if ((c & 0xE0) == 0xC0) {
      extra = 1, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2, min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3, min = 0x10000;
    } else {
      return line;
    }
    if (p + extra >= s.size()) return line;
    unsigned cp = c & (0x3F >> extra);
    for (size_t k = 1; k <= extra; ++k) {
      const auto cc = static_cast<unsigned char>(s[p + k]);
      if ((cc & 0xC0) != 0x80) return line;
      cp = (cp << 6) | (cc & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return line;
    p += extra + 1;
  }
  return 0;
}

bool ValidId(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
          c == ':' || c == '/')) {
      return false;
    }
  }
  return true;
}

// A finite number, or the reason it is not one.
std::optional<double> Number(std::string_view s, std::string* why) {
  double v = 0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty()) {
    *why = "empty: a number is required";
  } else if (ec == std::errc::result_out_of_range) {
    *why = "'" + std::string(s.substr(0, 32)) + "' is out of range";
  } else if (ec != std::errc() || p != s.data() + s.size()) {
    *why = "'" + std::string(s.substr(0, 32)) + "' is not a number (use '.' for decimals)";
  } else if (!std::isfinite(v)) {
    *why = "'" + std::string(s.substr(0, 32)) + "' is not finite";
  } else {
    return v;
  }
  return std::nullopt;
}

enum Column { kPoint, kX, kY, kZ, kI, kJ, kK, kMx, kMy, kMz, kDev, kAllowance, kColumns };
constexpr const char* kNames[kColumns] = {"point", "x_mm",  "y_mm",   "z_mm",
                                          "i",     "j",     "k",      "mx_mm",
                                          "my_mm", "mz_mm", "dev_mm", "allowance_mm"};
constexpr const char* kHeaderHelp =
    "the header must name point,x_mm,y_mm,z_mm,i,j,k and either mx_mm,my_mm,mz_mm or dev_mm "
    "(optionally allowance_mm)";

}  // namespace

Status ParseCmmCsv(std::string_view body, std::vector<CmmPoint>& out, FieldErrors& errors) {
  out.clear();
  if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);
  if (const size_t line = FirstBadUtf8Line(body); line != 0) {
    errors.push_back({line > 1 ? line - 1 : 0, line > 1 ? "row" : "header", "not valid UTF-8"});
    return Status::InvalidArgument("the CSV is not valid UTF-8");
  }
  // Lines, the header first; blank lines before it are skipped.
  size_t pos = 0;
  std::string_view header_line;
  while (pos < body.size() && header_line.empty()) {
    size_t end = body.find('\n', pos);
    if (end == std::string_view::npos) end = body.size();
    header_line = Trim(body.substr(pos, end - pos));
    pos = end + 1;
  }
  if (header_line.empty()) {
    errors.push_back({0, "header", kHeaderHelp});
    return Status::InvalidArgument("empty CSV");
  }
  int where[kColumns];
  std::fill(std::begin(where), std::end(where), -1);
  int columns = 0;
  for (size_t c = 0;; ++columns) {
    const size_t comma = header_line.find(',', c);
    const std::string_view name = Trim(header_line.substr(
        c, comma == std::string_view::npos ? std::string_view::npos : comma - c));
    int known = -1;
    for (int k = 0; k < kColumns; ++k) {
      if (name == kNames[k]) known = k;
    }
    if (known < 0) {
      errors.push_back(
          {0, std::string(name.substr(0, 64)), "unknown column; " + std::string(kHeaderHelp)});
    } else if (where[known] >= 0) {
      errors.push_back({0, std::string(name), "column named twice in the header"});
    } else {
      where[known] = columns;
    }
    if (comma == std::string_view::npos) break;
    c = comma + 1;
  }
  ++columns;
  for (int k : {kPoint, kX, kY, kZ, kI, kJ, kK}) {
    if (where[k] < 0)
      errors.push_back({0, kNames[k], "missing column; " + std::string(kHeaderHelp)});
  }
  const bool measured = where[kMx] >= 0 || where[kMy] >= 0 || where[kMz] >= 0;
  const bool deviation = where[kDev] >= 0;
  if (measured && deviation) {
    errors.push_back({0, "dev_mm", "give either mx_mm,my_mm,mz_mm or dev_mm, not both"});
  } else if (measured) {
    for (int k : {kMx, kMy, kMz}) {
      if (where[k] < 0) errors.push_back({0, kNames[k], "missing column (the measured point)"});
    }
  } else if (!deviation) {
    errors.push_back({0, "dev_mm", "missing column: " + std::string(kHeaderHelp)});
  }
  if (!errors.empty()) return Status::InvalidArgument("bad CSV header");

  std::unordered_map<std::string_view, size_t> first_row;
  std::vector<std::string_view> cells(static_cast<size_t>(columns));
  size_t row = 0;
  while (pos < body.size()) {
    size_t end = body.find('\n', pos);
    if (end == std::string_view::npos) end = body.size();
    const std::string_view line = Trim(body.substr(pos, end - pos));
    pos = end + 1;
    ++row;
    if (row > kMaxCmmLines) {
      errors.push_back({row, "row", "more than " + std::to_string(kMaxCmmLines) + " lines"});
      out.clear();
      return Status::TooLarge("the CSV has more than " + std::to_string(kMaxCmmLines) + " lines");
    }
    if (line.empty()) continue;
    if (out.size() + 1 > kMaxCmmPoints) {
      errors.push_back({row, "row", "more than " + std::to_string(kMaxCmmPoints) + " points"});
      out.clear();
      return Status::TooLarge("more than " + std::to_string(kMaxCmmPoints) + " points");
    }
    size_t n = 0;
    for (size_t c = 0;; ++n) {
      const size_t comma = line.find(',', c);
      if (n < cells.size()) {
        cells[n] = Trim(
            line.substr(c, comma == std::string_view::npos ? std::string_view::npos : comma - c));
      }
      if (comma == std::string_view::npos) break;
      c = comma + 1;
    }
    ++n;
    if (n != cells.size()) {
      errors.push_back(
          {row, "row",
           "expected " + std::to_string(cells.size()) + " fields, got " + std::to_string(n)});
      continue;
    }
    CmmPoint p;
    p.row = row;
    const std::string_view id = cells[static_cast<size_t>(where[kPoint])];
    if (!ValidId(id)) {
      errors.push_back({row, "point", "a point id is 1 to 64 of A-Z a-z 0-9 _ - . : /"});
    } else if (auto [it, fresh] = first_row.emplace(id, row); !fresh) {
      errors.push_back({row, "point",
                        "point '" + std::string(id) + "' again (first in row " +
                            std::to_string(it->second) + ")"});
    }
    p.nominal.id = std::string(id);
    auto read = [&](int k, bool optional_empty) -> std::optional<double> {
      if (where[k] < 0) return std::nullopt;
      const std::string_view cell = cells[static_cast<size_t>(where[k])];
      if (optional_empty && cell.empty()) return std::nullopt;
      std::string why;
      auto v = Number(cell, &why);
      if (!v) errors.push_back({row, kNames[k], why});
      return v;
    };
    p.nominal.x_mm = read(kX, false).value_or(0);
    p.nominal.y_mm = read(kY, false).value_or(0);
    p.nominal.z_mm = read(kZ, false).value_or(0);
    p.nominal.i = read(kI, false).value_or(0);
    p.nominal.j = read(kJ, false).value_or(0);
    p.nominal.k = read(kK, false).value_or(0);
    p.mx_mm = read(kMx, false);
    p.my_mm = read(kMy, false);
    p.mz_mm = read(kMz, false);
    p.dev_mm = read(kDev, false);
    p.allowance_mm = read(kAllowance, true);
    if (p.allowance_mm && *p.allowance_mm < 0) {
      errors.push_back({row, "allowance_mm", "stock before finishing cannot be negative"});
    }
    if (!NormalisedPoint(p.nominal)) {
      const double len = std::sqrt(p.nominal.i * p.nominal.i + p.nominal.j * p.nominal.j +
                                   p.nominal.k * p.nominal.k);
      errors.push_back({row, "i",
                        len == 0 ? std::string("zero-length normal (i, j, k)")
                                 : "normal (i, j, k) has length " + std::to_string(len) +
                                       "; a unit normal is required (within 0.01)"});
    }
    if (errors.empty()) out.push_back(std::move(p));
  }
  if (!errors.empty()) {
    out.clear();
    return Status::InvalidArgument("bad CSV rows");
  }
  if (out.empty()) {
    errors.push_back({1, "row", "no points after the header"});
    return Status::Unprocessable("the CSV has no points");
  }
  return Status::Ok();
}

}  // namespace thermocomp::api
