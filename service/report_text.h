// Number and list formats the readable reports share (Markdown and the
// pages made from it), so every report prints a length, a p-value and a
// missing value the same way.
#pragma once

#include <string>
#include <vector>

namespace thermocomp::report_text {

// printf `format` of a finite value; "-" for NaN (not computed) or inf.
std::string Fixed(double v, const char* format);
// Millimetres as micrometres with two decimals.
std::string Um(double mm);
// A p-value; 0 means it underflowed double, not that it is zero.
std::string P(double p);
// "a, b, c", or "none".
std::string Join(const std::vector<std::string>& list);

}  // namespace thermocomp::report_text
