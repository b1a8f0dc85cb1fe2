// Diameters as exact decimals: millimetres with up to six decimals are
// whole nanometres, so a turned feature's four diameters are kept and
// subtracted as integers and printed back digit for digit ("40.030" stays
// 40.030; a component of 30 000 nm / 2 prints 0.015, never 0.0149999).
//
// A radial component is half a diameter difference, so it is a whole
// number of half-nanometres: the difference in nm *is* the component in
// half-nm, and every sum of components is exact.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace thermocomp {

// Diameters above 10 m are not turned parts; the bound also keeps every
// value and difference far inside int64 and exact as a double (< 2^53).
inline constexpr int64_t kMaxDiameterNm = 10'000'000'000;  // 10 000 mm

// A plain decimal in mm ("40.030", "-0.5", "+12"): optional sign, at
// least one integer digit, optionally '.' and fraction digits. Digits
// beyond the sixth decimal must be zeros (a finer value is not a whole
// nm). No exponent, no "nan"/"inf", at most 12 integer digits. Returns the
// value in nm, or nullopt with `why` saying what is wrong.
std::optional<int64_t> ParseMillimetresNm(std::string_view text, std::string* why);

// A JSON number (a double) as the decimal it was written as: its shortest
// round-trip fixed form, parsed as above (so 40.03 is 40 030 000 nm).
std::optional<int64_t> DoubleMillimetresNm(double mm, std::string* why);

// nm as mm with at least `min_decimals` decimals and no trailing zeros
// beyond them: 40030000 -> "40.030" (min 3).
std::string FormatNmAsMm(int64_t nm, int min_decimals = 3);
// A radial component in half-nm as mm, exact (up to 7 decimals), at least
// three decimals, with "+" before a positive value when `plus`: 30000 ->
// "+0.015", -20000 -> "-0.010", 1 -> "+0.0000005".
std::string FormatHalfNmAsMm(int64_t half_nm, bool plus = false);

// The nearest doubles (correctly rounded division of exact integers, so
// their shortest printed forms are the decimals above).
inline double NmToMm(int64_t nm) {
  return static_cast<double>(nm) / 1e6;
}
inline double HalfNmToMm(int64_t half_nm) {
  return static_cast<double>(half_nm) / 2e6;
}
inline double HalfNmToUm(int64_t half_nm) {
  return static_cast<double>(half_nm) / 2e3;
}

}  // namespace thermocomp
