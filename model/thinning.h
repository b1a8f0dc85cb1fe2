// Thinning of a time series for plotting: Largest-Triangle-Three-Buckets
// (Steinarsson 2013). Keeps the first and last point and, from each bucket,
// the point that spans the largest triangle with its neighbours, so peaks
// and turning points survive where plain decimation would drop them.
#pragma once

#include <cstddef>
#include <vector>

namespace thermocomp {

// Indices (ascending) of at most max_points points of (x, y) to keep.
// x must be ascending. All points are kept when there are no more than
// max_points, or when max_points < 3 (then the first and last only, if 2).
std::vector<size_t> ThinLttb(const std::vector<double>& x, const std::vector<double>& y,
                             size_t max_points);

}  // namespace thermocomp
