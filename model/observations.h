// Observations: the regression data set of one axis. One row per probe
// point pk (k > 0), datum-relative: y = drift since the run's datum p0,
// x = candidate term values (e.g. dT_i = T_i(pk) - T_i(p0)), group = run.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace thermocomp {

struct Observations {
  Eigen::MatrixXd x;               // n x p
  Eigen::VectorXd y;               // n
  std::vector<std::string> names;  // p column names
  std::vector<int> group;          // n run indices, for leave-one-run-out CV
  std::vector<int> source;         // n caller's row ids (optional), kept by Subset

  int rows() const { return static_cast<int>(y.size()); }
  int ColumnIndex(const std::string& name) const;
  // The observations restricted to the given rows and named columns.
  Observations Subset(const std::vector<int>& rows, const std::vector<std::string>& columns) const;
  std::vector<int> AllRows() const;
};

}  // namespace thermocomp
