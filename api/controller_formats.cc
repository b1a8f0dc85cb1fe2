#include "api/controller_formats.h"

#include <cctype>
#include <cmath>
#include <cstdio>

namespace thermocomp::api {
namespace {

long TenthsOfMicron(double mm) {
  return std::lround(mm * 1e4);
}

int FanucAxisNumber(const std::string& axis) {
  static const std::string order = "XYZABC";
  auto pos = order.find(axis);
  return pos == std::string::npos ? 0 : static_cast<int>(pos) + 1;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

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
                    "$SA_TEMP_COMP_ABS_VALUE[%s]=%.6f\n$SA_TEMP_COMP_SLOPE[%s]=%.3f\n"
                    "$SA_TEMP_COMP_REF_POSITION[%s]=%.3f\n",
                    a.axis.c_str(), a.offset_mm, a.axis.c_str(), a.slope_um_per_m, a.axis.c_str(),
                    a.reference_position_mm);
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
      int n = FanucAxisNumber(a.axis);
      if (n == 0) {
        std::snprintf(line, sizeof line, "(%s has no external work offset variable)\n",
                      a.axis.c_str());
      } else {
        std::snprintf(line, sizeof line, "#520%d=%.4f\n", n, a.offset_at_probe_mm);
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
