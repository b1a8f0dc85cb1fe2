#include "api/check_reports.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "api/report_page.h"
#include "core/time_format.h"
#include "reports/report_text.h"

namespace thermocomp::api {
namespace {

// An RFC 3339 time from a stored report, as the plant reads it (digits,
// dashes, colons: nothing to escape); kept, escaped, when it does not parse.
std::string PlantText(const std::string& rfc3339, const PlantTime& time) {
  const auto ms = ParseRfc3339(rfc3339);
  return ms ? time.Format(*ms) : report_text::Text(rfc3339);
}

using nlohmann::json;
using report_text::Text;

std::string F(double v, const char* format = "%.2f") {
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

long TenthsOfMicron(double mm) {
  return std::lround(mm * 1e4);
}

// The error plot: mean deviation up (blue) and down (red) over the target,
// each with its +-2s band.
std::string ErrorPlotSvg(const json& per) {
  const double w = 640, h = 320, left = 50, right = 10, top = 10, bottom = 30;
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
  for (const auto& p : per) {
    const double t = p["target_mm"];
    xmin = std::min(xmin, t), xmax = std::max(xmax, t);
    for (const char* d : {"up", "down"}) {
      const double m = p[std::string("mean_") + d + "_um"], s = p[std::string("s_") + d + "_um"];
      ymin = std::min(ymin, m - 2 * s), ymax = std::max(ymax, m + 2 * s);
    }
  }
  if (!(xmax > xmin)) xmax = xmin + 1;
  if (!(ymax > ymin)) ymax = ymin + 1;
  auto X = [&](double v) { return left + (v - xmin) / (xmax - xmin) * (w - left - right); };
  auto Y = [&](double v) { return top + (ymax - v) / (ymax - ymin) * (h - top - bottom); };
  std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' width='" + F(w, "%.0f") +
                    "' height='" + F(h, "%.0f") + "' font-size='10'>";
  svg += "<line x1='" + F(left) + "' y1='" + F(Y(0)) + "' x2='" + F(w - right) + "' y2='" +
         F(Y(0)) + "' stroke='#ccc'/>";
  for (const auto& [dir, colour] : {std::pair{"up", "#2a6ebb"}, std::pair{"down", "#c0392b"}}) {
    std::string band, line;
    const std::string mean = std::string("mean_") + dir + "_um",
                      sd = std::string("s_") + dir + "_um";
    for (const auto& p : per)
      band +=
          F(X(p["target_mm"])) + "," + F(Y(p[mean].get<double>() + 2 * p[sd].get<double>())) + " ";
    for (auto it = per.rbegin(); it != per.rend(); ++it) {
      const auto& p = *it;
      band +=
          F(X(p["target_mm"])) + "," + F(Y(p[mean].get<double>() - 2 * p[sd].get<double>())) + " ";
    }
    for (const auto& p : per) line += F(X(p["target_mm"])) + "," + F(Y(p[mean])) + " ";
    svg += "<polygon points='" + band + "' fill='" + colour + "' fill-opacity='0.15'/>";
    svg += "<polyline points='" + line + "' fill='none' stroke='" + colour + "'/>";
  }
  svg += "<text x='" + F(left) + "' y='" + F(h - 8) + "'>" + F(xmin, "%.0f") + " mm</text>";
  svg +=
      "<text x='" + F(w - right - 60) + "' y='" + F(h - 8) + "'>" + F(xmax, "%.0f") + " mm</text>";
  svg += "<text x='2' y='" + F(top + 8) + "'>" + F(ymax, "%.1f") + " µm</text>";
  svg += "<text x='2' y='" + F(h - bottom) + "'>" + F(ymin, "%.1f") + " µm</text>";
  return svg + "</svg>";
}

}  // namespace

std::string ColumnCheckMarkdown(const json& r, const PlantTime& time) {
  const json& z = r["machine_zero_mm"];
  std::string md =
      "# Column check " + std::to_string(r.value("id", 0)) + ": " + Text(r.value("machine", "")) +
      "\n\nMeasured " + PlantText(r.value("ts", ""), time) + " on artifact " +
      Text(r.value("artifact", "")) + " at " + F(r.value("artifact_temperature_c", 0.0), "%.2f") +
      " °C (points corrected for its expansion).\n\n## Machine zero\n\n"
      "| | X | Y | Z |\n|---|---|---|---|\n| offset µm | " +
      F(z["X"].get<double>() * 1000) + " | " + F(z["Y"].get<double>() * 1000) + " | " +
      F(z["Z"].get<double>() * 1000) + " |\n";
  if (r.contains("zero_change_um")) {
    const json& c = r["zero_change_um"];
    md += "| change since " + PlantText(c.value("since", ""), time) + " µm | " +
          F(c["X"].get<double>()) + " | " + F(c["Y"].get<double>()) + " | " +
          F(c["Z"].get<double>()) + " |\n";
  }
  md += std::string("\n") +
        (r.value("beyond_tolerance", false) ? "**Beyond tolerance**: logged as an event.\n\n"
                                            : "Within tolerance.\n\n") +
        (r.contains("spindle_z_parallelism_um_per_100mm")
             ? "Spindle-to-Z parallelism: X " +
                   F(r["spindle_z_parallelism_um_per_100mm"]["X"].get<double>()) + ", Y " +
                   F(r["spindle_z_parallelism_um_per_100mm"]["Y"].get<double>()) +
                   " µm per 100 mm.\n\n"
             : std::string()) +
        "Circle through the sphere positions: radius " +
        F(r["circle"]["radius_mm"].get<double>(), "%.4f") + " mm, residual " +
        F(r["circle"]["residual_um"].get<double>()) +
        " µm.\n\n## Straightness (µm)\n\n"
        "| scheme | straightness | points (deviation from the least-squares line, ISO 230-1) "
        "|\n|---|---|---|\n";
  for (const auto& [scheme, value] : r["straightness_um"].items()) {
    std::string points;
    for (const auto& [id, v] : r["straightness_points_um"][scheme].items()) {
      if (!points.empty()) points += ", ";
      points += Text(id) + " " + F(v.get<double>());
    }
    md += "| " + Text(scheme) + " | ";
    md += F(value.get<double>()) + " | " + points + " |\n";
  }
  return md;
}

std::string ColumnCheckHtml(const json& r, const PlantTime& time) {
  return ReportPage("Column check " + std::to_string(r.value("id", 0)),
                    ColumnCheckMarkdown(r, time));
}

std::string PositioningMarkdown(const json& r, const PlantTime& time) {
  const json& iso = r["iso230_2"];
  const json& vdi = r["vdi3441"];
  const json& u = r["uncertainty_um"];
  const json& in = r["input"];
  std::string md = "# Positioning check " + std::to_string(r.value("id", 0)) + ": " +
                   Text(r.value("machine", "")) + " axis " + Text(in.value("axis", "")) + "\n\n";
  md += "Measured " + PlantText(in.value("ts", ""), time) + "; " +
        std::to_string(iso.value("runs_per_direction", 0)) + " runs per direction at " +
        std::to_string(iso["per_position"].size()) + " targets; compensation " +
        (in.value("compensation_active", false) ? "active" : "off") +
        (in.contains("machine_temperature_c")
             ? "; machine " + F(in["machine_temperature_c"].get<double>(), "%.1f") + " °C"
             : "") +
        (in.contains("air_temperature_c")
             ? "; air " + F(in["air_temperature_c"].get<double>(), "%.1f") + " °C"
             : "") +
        ".\n\n## ISO 230-2 (µm, expanded uncertainty k = 2)\n\n| | value | U |\n|---|---|---|\n";
  // Without an uncertainty budget nothing is claimed about the uncertainty.
  const bool stated = u.value("stated", true);
  auto uncertainty = [&](const char* ukey) {
    return !ukey ? std::string("-") : stated ? F(u[ukey].get<double>()) : "not stated";
  };
  auto row = [&](const char* name, const char* key, const char* ukey) {
    md += std::string("| ") + name + " | " + F(iso[key].get<double>()) + " | " + uncertainty(ukey) +
          " |\n";
  };
  row("A (accuracy)", "A_um", "A");
  md += "| A up / down | " + F(iso["A_up_um"].get<double>()) + " / " +
        F(iso["A_down_um"].get<double>()) + " | |\n";
  row("E (systematic)", "E_um", "E");
  row("M (mean bidirectional)", "M_um", "M");
  row("R (repeatability)", "R_um", "R");
  md += "| R up / down | " + F(iso["R_up_um"].get<double>()) + " / " +
        F(iso["R_down_um"].get<double>()) + " | " + uncertainty("R_up_down") + " |\n";
  row("B (reversal)", "B_um", "B");
  row("B mean", "B_mean_um", nullptr);
  if (!stated) {
    md +=
        "\nExpanded uncertainties are not stated: the check came without an uncertainty "
        "budget (device, misalignment, temperatures, E_VE).\n";
  }
  md +=
      "\n## VDI/DGQ 3441 (µm)\n\n| P | Pa | Ps max | U max | U mean |\n|---|---|---|---|---|\n| " +
      F(vdi["P_um"].get<double>()) + " | " + F(vdi["Pa_um"].get<double>()) + " | " +
      F(vdi["Ps_max_um"].get<double>()) + " | " + F(vdi["U_max_um"].get<double>()) + " | " +
      F(vdi["U_mean_um"].get<double>()) +
      " |\n\n## Per target (µm)\n\n"
      "| target mm | mean up | mean down | s up | s down | B | R "
      "|\n|---|---|---|---|---|---|---|\n";
  for (const auto& p : iso["per_position"]) {
    md += "| " + F(p["target_mm"].get<double>(), "%.3f") + " | " +
          F(p["mean_up_um"].get<double>()) + " | " + F(p["mean_down_um"].get<double>()) + " | " +
          F(p["s_up_um"].get<double>()) + " | " + F(p["s_down_um"].get<double>()) + " | " +
          F(p["reversal_um"].get<double>()) + " | " + F(p["R_um"].get<double>()) + " |\n";
  }
  return md;
}

std::string PositioningHtml(const json& r, const PlantTime& time) {
  return ReportPage("Positioning check " + std::to_string(r.value("id", 0)),
                    PositioningMarkdown(r, time),
                    "<figure>" + ErrorPlotSvg(r["iso230_2"]["per_position"]) +
                        "<figcaption>Mean deviation approaching up (blue) and down (red) with "
                        "&plusmn;2s bands.</figcaption></figure>");
}

StatusOr<std::string> RenderPitchTable(const PitchTable& t, const std::string& axis,
                                       const std::string& format, bool per_direction) {
  const size_t n = t.position_mm.size();
  const auto& up = per_direction ? t.correction_up_mm : t.correction_mm;
  const auto& down = per_direction ? t.correction_down_mm : t.correction_mm;
  std::string out;
  char line[160];
  if (format == "linuxcnc") {
    // [JOINT_n] COMP_FILE_TYPE = 0: nominal, actual moving forward, actual
    // moving backward (machine units); actual = nominal - correction.
    out = "# pitch table axis " + axis + " for [JOINT_n] COMP_FILE = ..., COMP_FILE_TYPE = 0\n";
    for (size_t i = 0; i < n; ++i) {
      std::snprintf(line, sizeof line, "%.6f %.6f %.6f\n", t.position_mm[i],
                    t.position_mm[i] - up[i], t.position_mm[i] - down[i]);
      out += line;
    }
    return out;
  }
  if (format == "sinumerik") {
    if (!t.equidistant) {
      return Status::Unprocessable(
          "format sinumerik: LEC needs equidistant targets; use csv or linuxcnc");
    }
    const std::string ax = axis + "1";
    out = "; leadscrew error compensation (LEC) axis " + ax +
          ", bidirectional mean; backlash MD32450\n";
    std::snprintf(line, sizeof line,
                  "$AA_ENC_COMP_STEP[0,%s]=%.4f\n$AA_ENC_COMP_MIN[0,%s]=%.4f\n"
                  "$AA_ENC_COMP_MAX[0,%s]=%.4f\n$AA_ENC_COMP_IS_MODULO[0,%s]=0\n",
                  ax.c_str(), t.step_mm, ax.c_str(), t.position_mm.front(), ax.c_str(),
                  t.position_mm.back(), ax.c_str());
    out += line;
    for (size_t i = 0; i < n; ++i) {
      std::snprintf(line, sizeof line, "$AA_ENC_COMP[0,%zu,%s]=%.6f\n", i, ax.c_str(),
                    t.correction_mm[i]);
      out += line;
    }
    std::snprintf(line, sizeof line, "$MA_BACKLASH[0,%s]=%.6f\n", ax.c_str(), t.backlash_mm);
    return out + line;
  }
  if (format == "beckhoff") {
    // TwinCAT CNC leadscrew error compensation list (kw.ssfk), 0.1 um.
    std::snprintf(line, sizeof line,
                  "# axis %s\nkw.ssfk.interval 0\nkw.ssfk.kw_nr_max %zu\nkw.ssfk.bilateral %d\n",
                  axis.c_str(), n, per_direction ? 1 : 0);
    out = line;
    for (size_t i = 0; i < n; ++i) {
      std::snprintf(line, sizeof line,
                    "kw.ssfk.table[%zu].setpoint %ld\nkw.ssfk.table[%zu].pos %ld\n"
                    "kw.ssfk.table[%zu].neg %ld\n",
                    i, TenthsOfMicron(t.position_mm[i]), i, TenthsOfMicron(up[i]), i,
                    TenthsOfMicron(down[i]));
      out += line;
    }
    return out;
  }
  if (format == "csv") {
    out = per_direction ? "position_mm,correction_up_mm,correction_down_mm\n"
                        : "position_mm,correction_mm\n";
    for (size_t i = 0; i < n; ++i) {
      if (per_direction) {
        std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f\n", t.position_mm[i], up[i], down[i]);
      } else {
        std::snprintf(line, sizeof line, "%.6f,%.6f\n", t.position_mm[i], up[i]);
      }
      out += line;
    }
    if (!per_direction) {
      std::snprintf(line, sizeof line, "# backlash_mm,%.6f\n", t.backlash_mm);
      out += line;
    }
    return out;
  }
  return Status::InvalidArgument("format: must be linuxcnc, sinumerik, beckhoff or csv");
}

}  // namespace thermocomp::api
