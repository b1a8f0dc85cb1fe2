#include "api/controller_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace thermocomp::api {
namespace {

long TenthsOfMicron(double mm) {
  return std::lround(mm * 1e4);
}

// The axis' number on the control (1-based), 0 when the control has no such axis.
int ControlAxisNumber(const MachineCompensation& c, const std::string& axis) {
  auto it = std::find(c.control_axes.begin(), c.control_axes.end(), axis);
  return it == c.control_axes.end() ? 0 : static_cast<int>(it - c.control_axes.begin()) + 1;
}

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x;
  return s;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

double SinumerikSlope(double slope_um_per_m) {
  return slope_um_per_m * 1e-6;
}

bool KnownControllerFormat(const std::string& f) {
  return f == "sinumerik" || f == "beckhoff" || f == "heidenhain" || f == "fanuc" ||
         f == "linuxcnc";
}

std::string RenderForController(const MachineCompensation& c, const std::string& format) {
  std::string out;
  char line[256];
  const char* comment = format == "linuxcnc" ? "#" : format == "fanuc" ? "(" : ";";
  for (const auto& a : c.axes) {
    if (!a.valid) {
      std::snprintf(line, sizeof line, "%s %s not valid: %s%s\n", comment, a.axis.c_str(),
                    a.reason.c_str(), format == "fanuc" ? ")" : "");
      out += line;
    }
    if (format == "sinumerik") {
      std::snprintf(line, sizeof line,
                    "$SA_TEMP_COMP_ABS_VALUE[%s]=%.6f\n$SA_TEMP_COMP_SLOPE[%s]=%.12f\n"
                    "$SA_TEMP_COMP_REF_POSITION[%s]=%.3f\n",
                    a.axis.c_str(), a.offset_mm, a.axis.c_str(), SinumerikSlope(a.slope_um_per_m),
                    a.axis.c_str(), a.reference_position_mm);
    } else if (format == "beckhoff") {
      std::snprintf(line, sizeof line,
                    "%s.temp_comp_offset_0=%ld\n%s.temp_comp_position_0=%ld\n"
                    "%s.temp_comp_coefficient=%.3f\n",
                    a.axis.c_str(), TenthsOfMicron(a.offset_mm), a.axis.c_str(),
                    TenthsOfMicron(a.reference_position_mm), a.axis.c_str(), a.slope_um_per_m);
    } else if (format == "heidenhain") {
      // No slope on these controls: the offset where the datum was probed.
      double mm = std::fmax(-3.0, std::fmin(3.0, a.offset_at_probe_mm));
      std::snprintf(line, sizeof line, "%s=%ld\n", a.axis.c_str(), TenthsOfMicron(mm));
    } else if (format == "fanuc") {
      const int n = ControlAxisNumber(c, a.axis);
      if (n == 0) {
        std::snprintf(line, sizeof line, "(%s is not in the control's axes %s)\n", a.axis.c_str(),
                      Join(c.control_axes).c_str());
      } else {
        std::snprintf(line, sizeof line, "#%d=%.4f\n", 5200 + n, a.offset_at_probe_mm);
      }
    } else {  // linuxcnc
      std::string ax = Lower(a.axis);
      std::snprintf(line, sizeof line,
                    "setp axis.%s.eoffset-scale 0.0001\nsetp axis.%s.eoffset-counts %ld\n",
                    ax.c_str(), ax.c_str(), TenthsOfMicron(a.offset_at_probe_mm));
    }
    out += line;
  }
  return out;
}

}  // namespace thermocomp::api
