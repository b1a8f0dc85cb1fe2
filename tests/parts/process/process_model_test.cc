// The mathematics of part-error models from the process, on values: the
// quadratic fit against hand-computed and exactly solvable cases, the
// structure search, the random split, the error measures and the input
// ranking on a simulated lathe whose truth is known.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "model/parts/process_quadratic.h"
#include "model/parts/process_sensitivity.h"
#include "model/parts/process_split.h"
#include "sim/parts/process_lathe.h"

namespace thermocomp {
namespace {

TEST(ProcessQuadratic, StraightLineByHand) {
  // x = 0, 1, 2 and y = 0, 1, 3: scaled x = −1, 0, 1, so the intercept is
  // the mean 4/3 and the slope Σxy/Σx² = 3/2 per half range; at x = 3
  // (scaled 2) the line gives 4/3 + 3 = 13/3.
  Eigen::MatrixXd x(3, 1);
  x << 0, 1, 2;
  Eigen::VectorXd y(3);
  y << 0, 1, 3;
  auto fit = FitQuadratic(x, y, QuadraticTerms(1, QuadraticStructure::kLinear));
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  EXPECT_NEAR(fit->coefficients[0], 4.0 / 3.0, 1e-12);
  EXPECT_NEAR(fit->coefficients[1], 1.5, 1e-12);
  EXPECT_NEAR(fit->Predict(Eigen::VectorXd::Constant(1, 3.0)), 13.0 / 3.0, 1e-12);
  // Residuals 1/6, −1/3, 1/6: SSE = 1/6 on one degree of freedom.
  EXPECT_NEAR(fit->residual_rms, std::sqrt(1.0 / 6.0), 1e-12);
}

TEST(ProcessQuadratic, FullQuadraticIsRecoveredExactly) {
  auto truth = [](double a, double b) {
    return 1.0 + 2.0 * a - 3.0 * b + 0.5 * a * a - 1.25 * a * b + 4.0 * b * b;
  };
  Eigen::MatrixXd x(25, 2);
  Eigen::VectorXd y(25);
  int r = 0;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j, ++r) {
      x(r, 0) = 1.0 + 0.5 * i;
      x(r, 1) = 10.0 + 2.0 * j;
      y(r) = truth(x(r, 0), x(r, 1));
    }
  }
  auto fit = FitQuadratic(x, y, QuadraticTerms(2, QuadraticStructure::kFull));
  ASSERT_TRUE(fit.ok());
  EXPECT_EQ(fit->terms.size(), 6u);
  EXPECT_LT(fit->residual_rms, 1e-9);
  for (double a : {1.1, 2.3, 2.9}) {
    for (double b : {10.5, 13.3, 17.9}) {
      Eigen::VectorXd p(2);
      p << a, b;
      EXPECT_NEAR(fit->Predict(p), truth(a, b), 1e-8);
    }
  }
  EXPECT_EQ(QuadraticTermName(fit->terms[5], {"ap_mm", "f_mm_rev"}), "ap_mm*f_mm_rev");
  EXPECT_EQ(QuadraticTermName(fit->terms[3], {"ap_mm", "f_mm_rev"}), "ap_mm^2");
}

TEST(ProcessQuadratic, RefusesWhatCannotBeDetermined) {
  Eigen::MatrixXd x(4, 2);
  x << 1, 5, 2, 5, 3, 5, 4, 5;
  Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(4, 0, 3);
  auto constant = FitQuadratic(x, y, QuadraticTerms(2, QuadraticStructure::kLinear));
  ASSERT_FALSE(constant.ok());
  EXPECT_EQ(constant.status().message(), "input 1 does not vary");

  auto few = FitQuadratic(x.leftCols(1), y, QuadraticTerms(1, QuadraticStructure::kFull));
  ASSERT_TRUE(few.ok());  // 4 rows, 3 terms
  Eigen::MatrixXd x3 = x.topRows(3).leftCols(1);
  auto too_few = FitQuadratic(x3, y.head(3), QuadraticTerms(1, QuadraticStructure::kFull));
  ASSERT_FALSE(too_few.ok());
  EXPECT_NE(too_few.status().message().find("too few records"), std::string::npos);

  // Two settings of an input cannot separate its linear term from its square.
  Eigen::MatrixXd two(6, 1);
  two << 1, 2, 1, 2, 1, 2;
  auto rank = FitQuadratic(two, Eigen::VectorXd::LinSpaced(6, 0, 5),
                           QuadraticTerms(1, QuadraticStructure::kSquares));
  ASSERT_FALSE(rank.ok());
  EXPECT_NE(rank.status().message().find("rank"), std::string::npos);

  Eigen::VectorXd bad = y;
  bad(2) = NAN;
  EXPECT_FALSE(
      FitQuadratic(x.leftCols(1), bad, QuadraticTerms(1, QuadraticStructure::kLinear)).ok());
}

TEST(ProcessQuadratic, BackwardEliminationKeepsTheTruthsTerms) {
  // y = 2 + 3a + noise; b has no effect.
  const auto records = SimulateLathe({.seed = 5, .records = 120});
  Eigen::MatrixXd x(120, 2);
  Eigen::VectorXd y(120);
  for (int i = 0; i < 120; ++i) {
    const auto& v = records[static_cast<size_t>(i)].values;
    x(i, 0) = v.at("ap_mm");
    x(i, 1) = v.at("fp_n");
    y(i) = 2 + 3 * x(i, 0) +
           0.2 * (v.at("size_error_um") - LatheTruthSizeErrorUm(v.at("ap_mm"), v.at("f_mm_rev"),
                                                                v.at("vc_m_min"),
                                                                v.at("temperature_c")));
  }
  auto fit = FitQuadraticBackward(x, y, 2.0);
  ASSERT_TRUE(fit.ok());
  std::set<std::string> names;
  for (const QuadraticTerm& t : fit->terms) names.insert(QuadraticTermName(t, {"a", "b"}));
  EXPECT_TRUE(names.count("a"));
  EXPECT_FALSE(names.count("a*b"));
  EXPECT_FALSE(names.count("b^2"));
  EXPECT_LE(fit->terms.size(), 3u);
}

TEST(ProcessSplit, SeededDisjointAndComplete) {
  const ProcessSplit a = RandomProcessSplit(200, 0.25, 7);
  const ProcessSplit b = RandomProcessSplit(200, 0.25, 7);
  const ProcessSplit c = RandomProcessSplit(200, 0.25, 8);
  EXPECT_EQ(a.held_out.size(), 50u);
  EXPECT_EQ(a.training.size(), 150u);
  EXPECT_EQ(a.held_out, b.held_out);
  EXPECT_NE(a.held_out, c.held_out);
  std::set<size_t> all(a.training.begin(), a.training.end());
  for (size_t i : a.held_out) EXPECT_TRUE(all.insert(i).second) << i;
  EXPECT_EQ(all.size(), 200u);
  // Random, not the newest or the oldest block.
  EXPECT_LT(a.held_out.front(), 50u);
  EXPECT_GE(a.held_out.back(), 150u);
  EXPECT_EQ(RandomProcessSplit(3, 0.1, 1).held_out.size(), 1u);

  const std::vector<int> folds = ProcessFolds(23, 5, 1);
  std::vector<int> count(5, 0);
  for (int f : folds) ++count[static_cast<size_t>(f)];
  for (int n : count) EXPECT_TRUE(n == 4 || n == 5) << n;
}

TEST(ProcessScore, ByHandAndAgainstChance) {
  const ProcessScore s = ScoreProcess({1, 2, 3, 4}, {1, 2, 3, 2}, 2.5);
  EXPECT_NEAR(s.rmse, 1.0, 1e-12);  // one error of 2 in four rows
  EXPECT_NEAR(s.mae, 0.5, 1e-12);
  EXPECT_NEAR(s.baseline_rmse, std::sqrt(5.0 / 4.0), 1e-12);
  EXPECT_NEAR(s.r2, 1.0 - 4.0 / 5.0, 1e-12);

  std::vector<double> measured, perfect, noise;
  const auto records = SimulateLathe({.seed = 3, .records = 60, .nothing_to_find = true});
  for (size_t i = 0; i < records.size(); ++i) {
    measured.push_back(records[i].values.at("size_error_um"));
    perfect.push_back(measured.back() + (i % 2 ? 0.01 : -0.01));
    // A prediction that only follows another noise draw.
    noise.push_back(5.0 + 0.5 * (records[i].values.at("roundness_um") - 2.0));
  }
  EXPECT_TRUE(BeatsBaseline(measured, perfect, 5.0, 2.0));
  EXPECT_FALSE(BeatsBaseline(measured, noise, 5.0, 2.0));
}

TEST(ProcessSensitivity, KeepsTheTruthsInputsAndDropsTheDeadOne) {
  const auto records = SimulateLathe({.seed = 11, .records = 150});
  const std::vector<std::string> names = {"ap_mm", "f_mm_rev", "vc_m_min", "fp_n", "temperature_c"};
  Eigen::MatrixXd x(150, 5);
  Eigen::VectorXd y(150);
  for (int i = 0; i < 150; ++i) {
    for (int k = 0; k < 5; ++k) {
      x(i, k) = records[static_cast<size_t>(i)].values.at(names[static_cast<size_t>(k)]);
    }
    y(i) = records[static_cast<size_t>(i)].values.at("size_error_um");
  }
  auto ranking = RankProcessInputs(x, y, 5, 1, 1.05);
  ASSERT_TRUE(ranking.ok()) << ranking.status().ToString();
  ASSERT_EQ(ranking->inputs.size(), 5u);
  std::set<std::string> kept;
  for (const InputSensitivity& s : ranking->inputs) {
    if (s.kept) kept.insert(names[static_cast<size_t>(s.input)]);
  }
  EXPECT_EQ(kept, (std::set<std::string>{"ap_mm", "f_mm_rev", "vc_m_min", "temperature_c"}));
  // The thermal term is the largest, the dead input the last.
  EXPECT_EQ(names[static_cast<size_t>(ranking->inputs.front().input)], "temperature_c");
  EXPECT_EQ(names[static_cast<size_t>(ranking->inputs.back().input)], "fp_n");
  EXPECT_LT(ranking->cv_rmse_all, 1.5);  // the noise is 1 µm
  EXPECT_GT(ranking->cv_rmse_mean, 3.0);

  // Nothing to find: no input removes 5 % of the error.
  const auto noise = SimulateLathe({.seed = 11, .records = 150, .nothing_to_find = true});
  for (int i = 0; i < 150; ++i) y(i) = noise[static_cast<size_t>(i)].values.at("size_error_um");
  auto none = RankProcessInputs(x, y, 5, 1, 1.05);
  ASSERT_TRUE(none.ok());
  for (const InputSensitivity& s : none->inputs) {
    EXPECT_FALSE(s.kept) << names[static_cast<size_t>(s.input)] << " ratio " << s.ratio;
  }
}

}  // namespace
}  // namespace thermocomp
