#include "model/parts/diameter_decimal.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

namespace thermocomp {
namespace {

constexpr int kDecimals = 6;           // 1 nm
constexpr int kMaxIntegerDigits = 12;  // 10^12 mm: far beyond any bound, far inside int64 nm

bool Digit(char c) {
  return c >= '0' && c <= '9';
}

// |v| as digits with `decimals` decimals, trailing zeros trimmed down to
// `min_decimals`.
std::string Decimal(uint64_t v, int decimals, int min_decimals) {
  uint64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  std::string frac = std::to_string(v % scale);
  frac.insert(0, static_cast<size_t>(decimals) - frac.size(), '0');
  while (static_cast<int>(frac.size()) > min_decimals && frac.back() == '0') frac.pop_back();
  std::string out = std::to_string(v / scale);
  if (!frac.empty()) out += "." + frac;
  return out;
}

}  // namespace

std::optional<int64_t> ParseMillimetresNm(std::string_view text, std::string* why) {
  const std::string_view s = text;
  auto fail = [&](const char* message) -> std::optional<int64_t> {
    if (why) *why = message;
    return std::nullopt;
  };
  const char* kNotDecimal = "must be a decimal number in mm, e.g. 40.030";
  size_t i = 0;
  bool negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  const size_t int_begin = i;
  while (i < s.size() && Digit(s[i])) ++i;
  const size_t int_digits = i - int_begin;
  if (int_digits == 0) return fail(kNotDecimal);
  int64_t nm = 0;
  // Leading zeros do not count towards the bound.
  size_t first = int_begin;
  while (first + 1 < i && s[first] == '0') ++first;
  if (i - first > kMaxIntegerDigits) return fail("is too large for a diameter in mm");
  for (size_t k = first; k < i; ++k) nm = nm * 10 + (s[k] - '0');
  int decimals = 0;
  if (i < s.size() && s[i] == '.') {
    ++i;
    const size_t frac_begin = i;
    while (i < s.size() && Digit(s[i])) {
      if (decimals < kDecimals) {
        nm = nm * 10 + (s[i] - '0');
        ++decimals;
      } else if (s[i] != '0') {
        return fail("has more than 6 decimals: diameters are read to 1 nm (0.000001 mm)");
      }
      ++i;
    }
    if (i == frac_begin) return fail(kNotDecimal);
  }
  if (i != s.size()) return fail(kNotDecimal);
  for (; decimals < kDecimals; ++decimals) nm *= 10;
  return negative ? -nm : nm;
}

std::optional<int64_t> DoubleMillimetresNm(double mm, std::string* why) {
  if (!std::isfinite(mm)) {
    if (why) *why = "must be a finite number in mm";
    return std::nullopt;
  }
  if (std::fabs(mm) >= 1e12) {
    if (why) *why = "is too large for a diameter in mm";
    return std::nullopt;
  }
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, mm, std::chars_format::fixed);
  if (ec != std::errc()) {
    if (why) *why = "must be a finite number in mm";
    return std::nullopt;
  }
  return ParseMillimetresNm(std::string_view(buffer, static_cast<size_t>(end - buffer)), why);
}

std::string FormatNmAsMm(int64_t nm, int min_decimals) {
  const uint64_t magnitude = nm < 0 ? 0 - static_cast<uint64_t>(nm) : static_cast<uint64_t>(nm);
  return (nm < 0 ? "-" : "") + Decimal(magnitude, kDecimals, min_decimals);
}

std::string FormatHalfNmAsMm(int64_t half_nm, bool plus) {
  const uint64_t magnitude =
      half_nm < 0 ? 0 - static_cast<uint64_t>(half_nm) : static_cast<uint64_t>(half_nm);
  // Half-nm as tenths of a nm: mm with seven decimals, exact.
  const std::string digits = Decimal(magnitude * 5, kDecimals + 1, 3);
  if (half_nm < 0) return "-" + digits;
  return (plus && half_nm > 0 ? "+" : "") + digits;
}

}  // namespace thermocomp
