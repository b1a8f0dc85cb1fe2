// The corrected program points in the two formats they leave in: CSV
// (point,x_mm,y_mm,z_mm,i,j,k) and DXF R12 ASCII with one POINT entity per
// point on layer CORRECTED, which CAM systems import as points to rebuild
// the surface from. DXF rather than IGES: its group-code pairs need no
// fixed 80-column records or directory section, every CAM system reads R12,
// and a reader of ours can check it line by line.
#pragma once

#include <string>
#include <vector>

#include "model/parts/surface_mirror.h"

namespace thermocomp {

std::string SurfacePointsCsv(const std::vector<SurfacePoint>& points);
std::string SurfacePointsDxf(const std::vector<SurfacePoint>& points);

}  // namespace thermocomp
