#include "service/report_text.h"

#include <cmath>
#include <cstdio>

namespace thermocomp::report_text {

std::string Fixed(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string Um(double mm) {
  return Fixed(mm * 1000.0, "%.2f");
}

std::string P(double p) {
  return p == 0.0 ? "< 1e-300" : Fixed(p, "%.2g");
}

std::string Join(const std::vector<std::string>& list) {
  std::string out;
  for (const auto& s : list) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "none" : out;
}

}  // namespace thermocomp::report_text
