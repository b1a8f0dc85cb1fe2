// Numbers as text for PostgreSQL's parameters and array literals: the
// shortest decimal that reads back as exactly the same double.
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace thermocomp {

inline std::string ShortestDoubleText(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace thermocomp
