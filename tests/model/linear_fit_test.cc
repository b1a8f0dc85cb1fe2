#include "model/linear_fit.h"
#include "model/residual_checks.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace thermocomp {
namespace {

// y = [1, 3, 2, 5] on x = [0, 1, 2, 3], worked by hand:
// xbar = 1.5, ybar = 2.75, Sxx = 5, Sxy = 5.5 -> b1 = 1.1, b0 = 1.1;
// residuals -0.1, 0.8, -1.3, 0.6; SSE = 2.7; SST = 8.75; s^2 = 1.35.
TEST(LinearFitTest, HandComputedSimpleRegression) {
  Eigen::MatrixXd x(4, 1);
  x << 0, 1, 2, 3;
  Eigen::VectorXd y(4);
  y << 1, 3, 2, 5;
  auto fit = FitLinear(x, y, {"x"});
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  EXPECT_NEAR(fit->terms[0].estimate, 1.1, 1e-12);
  EXPECT_NEAR(fit->terms[1].estimate, 1.1, 1e-12);
  EXPECT_NEAR(fit->sse, 2.7, 1e-12);
  EXPECT_NEAR(fit->r2, 1.0 - 2.7 / 8.75, 1e-12);
  EXPECT_NEAR(fit->adj_r2, 1.0 - (2.7 / 2) / (8.75 / 3), 1e-12);
  EXPECT_NEAR(fit->rmse, std::sqrt(2.7 / 4), 1e-12);
  const double se_b1 = std::sqrt(1.35 / 5);
  EXPECT_NEAR(fit->terms[1].std_error, se_b1, 1e-12);
  const double t = 1.1 / se_b1;
  EXPECT_NEAR(fit->terms[1].t, t, 1e-12);
  // Student t with 2 df has the closed form F(t) = 1/2 + t / (2 sqrt(2 + t^2)).
  EXPECT_NEAR(fit->terms[1].p, 1.0 - t / std::sqrt(2 + t * t), 1e-12);
  EXPECT_NEAR(fit->f, 6.05 / 1.35, 1e-12);
  EXPECT_NEAR(fit->f_p, fit->terms[1].p, 1e-12);  // F = t^2 with one predictor
  EXPECT_NEAR(fit->durbin_watson, (0.81 + 4.41 + 3.61) / 2.7, 1e-12);
  // Leverage 1/n + (x - xbar)^2 / Sxx.
  EXPECT_NEAR(fit->leverage(0), 0.7, 1e-12);
  EXPECT_NEAR(fit->leverage(1), 0.3, 1e-12);
  EXPECT_NEAR(fit->standardized_residuals(0), -0.1 / std::sqrt(1.35 * 0.3), 1e-12);
  EXPECT_DOUBLE_EQ(fit->terms[1].vif, 1.0);
}

TEST(LinearFitTest, ExactLinearCombinationIsAliasedNotFatal) {
  Eigen::MatrixXd x(6, 3);
  x << 1, 2, 3,  //
      2, 1, 3,   //
      3, 5, 8,   //
      4, 3, 7,   //
      5, 8, 13,  //
      6, 2, 8;   // column 3 = column 1 + column 2
  Eigen::VectorXd y(6);
  y << 1.1, 1.9, 3.2, 3.9, 5.1, 5.8;
  auto fit = FitLinear(x, y, {"a", "b", "c"});
  ASSERT_TRUE(fit.ok());
  ASSERT_EQ(fit->aliased.size(), 1u);
  EXPECT_EQ(fit->aliased[0], "c");
  EXPECT_EQ(fit->k, 2);
  EXPECT_EQ(fit->Find("c"), nullptr);
}

TEST(LinearFitTest, ConstantColumnIsAliasedWithIntercept) {
  Eigen::MatrixXd x(5, 2);
  x << 1, 7, 2, 7, 3, 7, 4, 7, 5, 7;
  Eigen::VectorXd y(5);
  y << 2, 4.1, 5.9, 8.2, 9.9;
  auto fit = FitLinear(x, y, {"a", "const"});
  ASSERT_TRUE(fit.ok());
  ASSERT_EQ(fit->aliased, std::vector<std::string>{"const"});
}

TEST(LinearFitTest, TooFewObservationsIsUnprocessable) {
  Eigen::MatrixXd x(2, 1);
  x << 1, 2;
  Eigen::VectorXd y(2);
  y << 1, 2;
  auto fit = FitLinear(x, y, {"a"});
  EXPECT_EQ(fit.status().code(), Status::Code::kUnprocessable);
}

TEST(LinearFitTest, NonFiniteInputIsUnprocessable) {
  Eigen::MatrixXd x(4, 1);
  x << 1, 2, NAN, 4;
  Eigen::VectorXd y(4);
  y << 1, 2, 3, 4;
  EXPECT_EQ(FitLinear(x, y, {"a"}).status().code(), Status::Code::kUnprocessable);
}

// The full eight-sensor model on the study data against R's lm() and
// car::vif() (tests/reference/fms_reference.R), to 1e-6 relative.
class StudyReferenceTest : public ::testing::Test {
 protected:
  void ExpectRel(const std::string& key, double actual) {
    ASSERT_TRUE(ref_.count(key)) << key;
    double expected = std::stod(ref_[key]);
    EXPECT_NEAR(actual, expected, 1e-6 * std::fabs(expected)) << key;
  }
  void ExpectFit(const std::string& prefix, const LinearFit& fit) {
    ExpectRel(prefix + ".n", fit.n);
    ExpectRel(prefix + ".r2", fit.r2);
    ExpectRel(prefix + ".adj_r2", fit.adj_r2);
    ExpectRel(prefix + ".f", fit.f);
    ExpectRel(prefix + ".f_p", fit.f_p);
    ExpectRel(prefix + ".rmse", fit.rmse);
    ExpectRel(prefix + ".sigma", fit.sigma);
    ExpectRel(prefix + ".dw", fit.durbin_watson);
    ExpectRel(prefix + ".rstandard.1", fit.standardized_residuals(0));
    ExpectRel(prefix + ".rstandard.max_abs", fit.standardized_residuals.cwiseAbs().maxCoeff());
    ExpectRel(prefix + ".skewness", Skewness(fit.residuals));
    ExpectRel(prefix + ".excess_kurtosis", ExcessKurtosis(fit.residuals));
    for (const auto& t : fit.terms) {
      ExpectRel(prefix + "." + t.name + ".estimate", t.estimate);
      ExpectRel(prefix + "." + t.name + ".std_error", t.std_error);
      ExpectRel(prefix + "." + t.name + ".t", t.t);
      ExpectRel(prefix + "." + t.name + ".p", t.p);
      if (t.name != "intercept") ExpectRel(prefix + "." + t.name + ".vif", t.vif);
    }
  }
  std::map<std::string, std::string> ref_ = testing::LoadReference();
};

TEST_F(StudyReferenceTest, FullModelMatchesR) {
  Observations obs = testing::LoadStudy();
  ASSERT_EQ(obs.rows(), 623);
  auto fit = FitLinear(obs.x, obs.y, obs.names);
  ASSERT_TRUE(fit.ok());
  ASSERT_EQ(fit->terms.size(), 9u);
  ExpectFit("full", *fit);
  auto checks = CheckResiduals(obs.x, obs.y, *fit);
  ASSERT_TRUE(checks.ok());
  ExpectRel("full.gq", checks->goldfeld_quandt);
  ExpectRel("full.gq_p", checks->goldfeld_quandt_p);
  EXPECT_FALSE(checks->normal);  // excess kurtosis 31.9: the outliers are still in
  EXPECT_FALSE(checks->homoscedastic);
}

TEST_F(StudyReferenceTest, TwoTermModelMatchesR) {
  Observations obs = testing::LoadStudy();
  Observations small = obs.Subset(obs.AllRows(), {"dT_x1", "dT_y2"});
  auto fit = FitLinear(small.x, small.y, small.names);
  ASSERT_TRUE(fit.ok());
  ExpectFit("small", *fit);
  auto checks = CheckResiduals(small.x, small.y, *fit);
  ASSERT_TRUE(checks.ok());
  ExpectRel("small.gq", checks->goldfeld_quandt);
  ExpectRel("small.gq_p", checks->goldfeld_quandt_p);
}

TEST(ResidualChecksTest, HandComputedMoments) {
  Eigen::VectorXd symmetric(5);
  symmetric << -2, -1, 0, 1, 2;  // m2 = 2, m3 = 0, m4 = 6.8
  EXPECT_NEAR(Skewness(symmetric), 0.0, 1e-15);
  EXPECT_NEAR(ExcessKurtosis(symmetric), 6.8 / 4 - 3, 1e-12);
  Eigen::VectorXd lopsided(4);
  // A two-point distribution with p = 1/4: skewness (1 - 2p)/sqrt(pq) = 2/sqrt(3),
  // excess kurtosis (1 - 6pq)/(pq) = -2/3.
  lopsided << 0, 0, 0, 3;
  EXPECT_NEAR(Skewness(lopsided), 2 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(ExcessKurtosis(lopsided), -2.0 / 3.0, 1e-12);
}

}  // namespace
}  // namespace thermocomp
