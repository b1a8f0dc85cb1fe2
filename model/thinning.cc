#include "model/thinning.h"

#include <cmath>

namespace thermocomp {

std::vector<size_t> ThinLttb(const std::vector<double>& x, const std::vector<double>& y,
                             size_t max_points) {
  const size_t n = x.size();
  std::vector<size_t> keep;
  if (n <= max_points) {
    for (size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  if (max_points == 0) return keep;
  keep.push_back(0);
  if (max_points == 1) return keep;
  if (max_points == 2) {
    keep.push_back(n - 1);
    return keep;
  }
  keep.reserve(max_points);
  // n - 2 inner points in max_points - 2 buckets.
  const double width = static_cast<double>(n - 2) / static_cast<double>(max_points - 2);
  size_t a = 0;
  for (size_t b = 0; b < max_points - 2; ++b) {
    size_t start = 1 + static_cast<size_t>(std::floor(b * width));
    size_t end = 1 + static_cast<size_t>(std::floor((b + 1) * width));
    if (end > n - 1) end = n - 1;
    // Average of the next bucket (or the last point) is the third vertex.
    size_t next_start = end;
    size_t next_end = 1 + static_cast<size_t>(std::floor((b + 2) * width));
    if (next_end > n - 1 || b + 1 == max_points - 2) next_end = n;
    if (next_start >= next_end) next_start = n - 1, next_end = n;
    double cx = 0, cy = 0;
    for (size_t i = next_start; i < next_end; ++i) cx += x[i], cy += y[i];
    cx /= static_cast<double>(next_end - next_start);
    cy /= static_cast<double>(next_end - next_start);
    double best = -1;
    size_t best_i = start;
    for (size_t i = start; i < end; ++i) {
      double area = std::fabs((x[a] - cx) * (y[i] - y[a]) - (x[a] - x[i]) * (cy - y[a]));
      if (area > best) best = area, best_i = i;
    }
    keep.push_back(best_i);
    a = best_i;
  }
  keep.push_back(n - 1);
  return keep;
}

}  // namespace thermocomp
