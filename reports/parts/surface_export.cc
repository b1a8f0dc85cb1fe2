#include "reports/parts/surface_export.h"

#include <cstdio>

namespace thermocomp {
namespace {

// Micrometre resolution and below: the program is regenerated from these.
void Append(std::string& out, double v) {
  char buf[40];
  const int n = std::snprintf(buf, sizeof buf, "%.6f", v + 0.0);
  out.append(buf, static_cast<size_t>(n));
}

}  // namespace

std::string SurfacePointsCsv(const std::vector<SurfacePoint>& points) {
  std::string out = "point,x_mm,y_mm,z_mm,i,j,k\n";
  out.reserve(points.size() * 90 + out.size());
  for (const SurfacePoint& p : points) {
    out += p.id;
    for (double v : {p.x_mm, p.y_mm, p.z_mm, p.i, p.j, p.k}) {
      out += ',';
      Append(out, v);
    }
    out += '\n';
  }
  return out;
}

std::string SurfacePointsDxf(const std::vector<SurfacePoint>& points) {
  std::string out =
      "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n"
      "0\nSECTION\n2\nTABLES\n0\nTABLE\n2\nLAYER\n70\n1\n"
      "0\nLAYER\n2\nCORRECTED\n70\n0\n62\n7\n6\nCONTINUOUS\n0\nENDTAB\n0\nENDSEC\n"
      "0\nSECTION\n2\nENTITIES\n";
  out.reserve(points.size() * 80 + out.size());
  for (const SurfacePoint& p : points) {
    out += "0\nPOINT\n8\nCORRECTED\n10\n";
    Append(out, p.x_mm);
    out += "\n20\n";
    Append(out, p.y_mm);
    out += "\n30\n";
    Append(out, p.z_mm);
    out += '\n';
  }
  out += "0\nENDSEC\n0\nEOF\n";
  return out;
}

}  // namespace thermocomp
