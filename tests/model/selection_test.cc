#include "model/selection.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "model/cross_validation.h"
#include "tests/test_util.h"

namespace thermocomp {
namespace {

double Ref(const std::map<std::string, std::string>& ref, const std::string& key) {
  auto it = ref.find(key);
  EXPECT_NE(it, ref.end()) << key;
  return it == ref.end() ? NAN : std::stod(it->second);
}

// The whole procedure of docs/model.md §4 on the study data, against the same
// procedure written independently in R.
TEST(SelectionTest, StudyProcedureMatchesR) {
  auto ref = testing::LoadReference();
  Observations obs = testing::LoadStudy();
  auto sel = SelectModel(obs, SelectionOptions{});
  ASSERT_TRUE(sel.ok()) << sel.status().ToString();
  std::string terms;
  for (const auto& t : sel->terms) terms += (terms.empty() ? "" : ",") + t;
  EXPECT_EQ(terms, ref["selected.terms"]);  // Tenv and Ty1 drop out, as in the study
  EXPECT_EQ(static_cast<double>(sel->outlier_rows.size()), Ref(ref, "selected.removed_outliers"));
  EXPECT_EQ(sel->outlier_steps, Ref(ref, "selected.outlier_steps"));
  EXPECT_EQ(sel->fit.n, Ref(ref, "selected.n"));
  for (const auto& t : sel->fit.terms) {
    double e = Ref(ref, "selected." + t.name + ".estimate");
    EXPECT_NEAR(t.estimate, e, 1e-6 * std::fabs(e)) << t.name;
    double p = Ref(ref, "selected." + t.name + ".p");
    EXPECT_NEAR(t.p, p, 1e-6 * p) << t.name;
  }
  EXPECT_NEAR(sel->fit.r2, Ref(ref, "selected.r2"), 1e-9);
  // The column-base sensor dominates with a negative coefficient (study: about -12.6 um/K).
  EXPECT_LT(sel->fit.Find("dT_y2")->estimate, -0.010);
}

TEST(CrossValidationTest, LeaveOneRunOutMatchesR) {
  auto ref = testing::LoadReference();
  Observations obs = testing::LoadStudy();
  auto cv = LeaveOneRunOut(obs);
  ASSERT_TRUE(cv.ok());
  EXPECT_EQ(cv->folds, 42);
  double expected = Ref(ref, "full.loro_rmse");
  EXPECT_NEAR(cv->rmse, expected, 1e-6 * expected);

  auto sel = SelectModel(obs, SelectionOptions{});
  ASSERT_TRUE(sel.ok());
  auto cv_sel = LeaveOneRunOut(obs.Subset(sel->rows, sel->terms));
  ASSERT_TRUE(cv_sel.ok());
  expected = Ref(ref, "selected.loro_rmse");
  EXPECT_NEAR(cv_sel->rmse, expected, 1e-6 * expected);
}

// Synthetic data with known truth: an irrelevant sensor is eliminated, a
// collinear copy is eliminated, and planted gross errors are removed.
TEST(SelectionTest, RemovesNoiseTermsCollinearCopyAndPlantedOutliers) {
  std::mt19937 rng(7);
  std::normal_distribution<double> z(0, 1);
  const int n = 400;
  Observations obs;
  obs.names = {"a", "noise", "b", "a_copy"};
  obs.x.resize(n, 4);
  obs.y.resize(n);
  for (int i = 0; i < n; ++i) {
    double a = 2 * z(rng), b = z(rng);
    obs.x.row(i) << a, z(rng), b, a + 0.05 * z(rng);
    obs.y(i) = 0.01 * a - 0.02 * b + 0.001 * z(rng);
    obs.group.push_back(i / 20);
  }
  const std::vector<int> planted = {17, 123, 250, 399};
  for (int i : planted) obs.y(i) += 0.05;
  auto sel = SelectModel(obs, SelectionOptions{});
  ASSERT_TRUE(sel.ok());
  ASSERT_EQ(sel->terms.size(), 2u);
  EXPECT_EQ(sel->terms[1], "b");
  EXPECT_TRUE(sel->terms[0] == "a" || sel->terms[0] == "a_copy");
  for (int i : planted) {
    EXPECT_NE(std::find(sel->outlier_rows.begin(), sel->outlier_rows.end(), i),
              sel->outlier_rows.end())
        << "planted outlier " << i;
  }
  EXPECT_NEAR(sel->fit.Find("b")->estimate, -0.02, 5e-4);
}

TEST(SelectionTest, KeepsDeclaredTermsWhenEliminationIsOff) {
  Observations obs = testing::LoadStudy();
  SelectionOptions opt;
  opt.eliminate = false;
  auto sel = SelectModel(obs, opt);
  ASSERT_TRUE(sel.ok());
  EXPECT_EQ(sel->terms.size(), 8u);
}

}  // namespace
}  // namespace thermocomp
