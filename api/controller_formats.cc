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

std::string CommentText(const std::string& text, const std::string& format) {
  std::string out;
  for (const char ch : text) {
    if (out.size() >= 160) break;
    const auto u = static_cast<unsigned char>(ch);
    char c = u >= 0x20 && u < 0x7f ? ch : '?';
    if (format == "fanuc" && (c == '(' || c == ')')) c = c == '(' ? '[' : ']';
    out += c;
  }
  return out;
}

namespace {

std::string Printf(const char* fmt, auto... args) {
  char line[512];
  std::snprintf(line, sizeof line, fmt, args...);
  return line;
}

long AgeSeconds(const AxisCompensation& a) {
  return a.input_age_s ? static_cast<long>(std::floor(*a.input_age_s)) : -1L;
}

// The lines a control or its PLC tests before it applies the values.
std::string StatusLines(const MachineCompensation& c, const AxisCompensation& a,
                        const std::string& format) {
  const int status = a.StatusWord();
  const long age = AgeSeconds(a);
  const std::string& ax = a.axis;
  if (format == "sinumerik") {
    return Printf("TC_STATUS_%s=%d\nTC_AGE_%s=%ld\n", ax.c_str(), status, ax.c_str(), age);
  }
  if (format == "beckhoff") {
    return Printf("%s.tc_status=%d\n%s.tc_input_age_s=%ld\n", ax.c_str(), status, ax.c_str(), age);
  }
  if (format == "heidenhain") {
    return Printf("%s_STATUS=%d\n%s_AGE=%ld\n", ax.c_str(), status, ax.c_str(), age);
  }
  if (format == "fanuc") {
    const int n = ControlAxisNumber(c, ax);
    return n == 0 ? "" : Printf("#%d=%d\n#%d=%ld\n", 980 + n, status, 990 + n, age);
  }
  const std::string lower = Lower(ax);
  return Printf("setp thermocomp.%s.status %d\nsetp thermocomp.%s.input-age-s %ld\n", lower.c_str(),
                status, lower.c_str(), age);
}

std::string ComputedLine(const MachineCompensation& c, const std::string& format) {
  const long long s = c.computed_at_ms / 1000;
  if (format == "sinumerik") return Printf("TC_COMPUTED=%lld\n", s);
  if (format == "beckhoff") return Printf("tc_computed=%lld\n", s);
  if (format == "heidenhain") return Printf("COMPUTED=%lld\n", s);
  if (format == "fanuc") return Printf("#980=%lld\n", s);
  return Printf("setp thermocomp.computed-at %lld\n", s);
}

}  // namespace

std::string RenderForController(const MachineCompensation& c, const std::string& format) {
  std::string out = ComputedLine(c, format);
  const std::string open = format == "linuxcnc" ? "# " : format == "fanuc" ? "(" : "; ";
  const std::string close = format == "fanuc" ? ")" : "";
  for (const auto& a : c.axes) {
    const std::string ax = CommentText(a.axis, format);
    if (!a.valid) {
      out.append(open).append(ax).append(" not valid, ").append(ServedStateName(a.state));
      out.append(": ").append(CommentText(a.reason, format)).append(close).append("\n");
    }
    if (format == "sinumerik") {
      out += Printf(
          "$SA_TEMP_COMP_ABS_VALUE[%s]=%.6f\n$SA_TEMP_COMP_SLOPE[%s]=%.12f\n"
          "$SA_TEMP_COMP_REF_POSITION[%s]=%.3f\n",
          ax.c_str(), a.offset_mm, ax.c_str(), SinumerikSlope(a.slope_um_per_m), ax.c_str(),
          a.reference_position_mm);
    } else if (format == "beckhoff") {
      out += Printf(
          "%s.temp_comp_offset_0=%ld\n%s.temp_comp_position_0=%ld\n"
          "%s.temp_comp_coefficient=%.3f\n",
          ax.c_str(), TenthsOfMicron(a.offset_mm), ax.c_str(),
          TenthsOfMicron(a.reference_position_mm), ax.c_str(), a.slope_um_per_m);
    } else if (format == "heidenhain") {
      // No slope on these controls: the offset where the datum was probed.
      const double mm = std::fmax(-3.0, std::fmin(3.0, a.offset_at_probe_mm));
      out += Printf("%s=%ld\n", ax.c_str(), TenthsOfMicron(mm));
    } else if (format == "fanuc") {
      const int n = ControlAxisNumber(c, a.axis);
      if (n == 0) {
        out.append("(").append(ax).append(" is not in the control's axes ");
        out.append(CommentText(Join(c.control_axes), format)).append(")\n");
      } else {
        out += Printf("#%d=%.4f\n", 5200 + n, a.offset_at_probe_mm);
      }
    } else {  // linuxcnc
      const std::string lower = Lower(ax);
      out += Printf("setp axis.%s.eoffset-scale 0.0001\nsetp axis.%s.eoffset-counts %ld\n",
                    lower.c_str(), lower.c_str(), TenthsOfMicron(a.offset_at_probe_mm));
    }
    out += StatusLines(c, a, format);
  }
  return out;
}

}  // namespace thermocomp::api

namespace thermocomp::api {

std::string RenderThermalErrorLine(const ThermalErrorTable& t, const std::string& format) {
  const bool sinumerik = format == "sinumerik";
  const std::string ax = CommentText(t.axis, format);
  const long long computed = t.computed_at_ms / 1000;
  std::string out =
      sinumerik ? Printf("TC_COMPUTED=%lld\n", computed) : Printf("tc_computed=%lld\n", computed);
  if (!t.valid) {
    out += Printf("; %s not valid, %s: %s\n", ax.c_str(), ServedStateName(t.state),
                  CommentText(t.reason, format).c_str());
  } else if (!t.fallback.empty()) {
    out += Printf("; %s fallback %s: %s\n", ax.c_str(), CommentText(t.fallback, format).c_str(),
                  CommentText(t.reason, format).c_str());
  }
  out += Printf("; %s line max residual %.3f um, rms %.3f um over %.3f..%.3f mm\n", ax.c_str(),
                t.line.max_residual_um, t.line.rms_residual_um, t.travel.min_mm, t.travel.max_mm);
  const double offset_mm = t.line.offset_um * 1e-3;
  if (sinumerik) {
    out += Printf(
        "$SA_TEMP_COMP_ABS_VALUE[%s]=%.6f\n$SA_TEMP_COMP_SLOPE[%s]=%.12f\n"
        "$SA_TEMP_COMP_REF_POSITION[%s]=%.3f\n",
        ax.c_str(), offset_mm, ax.c_str(), SinumerikSlope(t.line.slope_um_per_m), ax.c_str(),
        t.line.reference_position_mm);
  } else {
    out += Printf(
        "%s.temp_comp_offset_0=%ld\n%s.temp_comp_position_0=%ld\n"
        "%s.temp_comp_coefficient=%.3f\n",
        ax.c_str(), TenthsOfMicron(offset_mm), ax.c_str(),
        TenthsOfMicron(t.line.reference_position_mm), ax.c_str(), t.line.slope_um_per_m);
  }
  const long age = t.input_age_s ? static_cast<long>(std::floor(*t.input_age_s)) : -1L;
  out += sinumerik ? Printf("TC_STATUS_%s=%d\nTC_AGE_%s=%ld\n", ax.c_str(), t.StatusWord(),
                            ax.c_str(), age)
                   : Printf("%s.tc_status=%d\n%s.tc_input_age_s=%ld\n", ax.c_str(), t.StatusWord(),
                            ax.c_str(), age);
  return out;
}

std::string ThermalErrorCsv(const ThermalErrorTable& t) {
  std::string out = "position_mm,error_um,correction_um,valid\n";
  for (const ThermalErrorPoint& p : t.points) {
    out +=
        Printf("%.3f,%.3f,%.3f,%d\n", p.position_mm, p.error_um, p.correction_um, p.valid ? 1 : 0);
  }
  return out;
}

}  // namespace thermocomp::api
