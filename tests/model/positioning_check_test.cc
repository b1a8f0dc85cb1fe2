// ISO 230-2 and VDI/DGQ 3441 (docs/model.md §11) against a vector worked by
// hand and against an independent implementation written here from the
// definitions; the circle through sphere positions; artifact correction.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "model/column_check.h"
#include "model/pitch_table.h"
#include "model/positioning_check.h"

namespace thermocomp {
namespace {

const double kR2 = std::sqrt(2.0);

// Two targets, two runs per direction:
//   target 0 mm:    up 1, 3   down 0, 2
//   target 1000 mm: up -1, -1 down 2, 4
PositioningData HandVector() {
  PositioningData d;
  d.targets_mm = {0.0, 1000.0};
  d.runs = {{+1, {1.0, -1.0}}, {-1, {0.0, 2.0}}, {+1, {3.0, -1.0}}, {-1, {2.0, 4.0}}};
  return d;
}

TEST(Iso230_2, HandComputedVector) {
  UncertaintyInputs u{0.5, 2.0, 11.7, 0.35, 3.0, 1.0, 2.0};  // the api.md example
  auto e = EvaluatePositioning(HandVector(), u);
  ASSERT_TRUE(e.ok()) << e.status().message();
  const Iso230Result& r = e->iso;
  // Per position: means 2/1 and -1/3, s sqrt(2) except 0 (up at 1000 mm).
  EXPECT_DOUBLE_EQ(r.positions[0].mean_um, 1.5);
  EXPECT_DOUBLE_EQ(r.positions[0].reversal_um, 1.0);
  EXPECT_NEAR(r.positions[0].s_up_um, kR2, 1e-12);
  EXPECT_NEAR(r.positions[0].r_um, 4 * kR2 + 1, 1e-12);  // 2s + 2s + |B| = 6.657
  EXPECT_DOUBLE_EQ(r.positions[1].reversal_um, -4.0);
  EXPECT_NEAR(r.positions[1].r_um, 2 * kR2 + 4, 1e-12);  // 6.828
  // Per axis.
  EXPECT_DOUBLE_EQ(r.B_um, 4.0);
  EXPECT_DOUBLE_EQ(r.B_mean_um, -1.5);
  EXPECT_NEAR(r.R_up_um, 4 * kR2, 1e-12);
  EXPECT_NEAR(r.R_down_um, 4 * kR2, 1e-12);
  EXPECT_NEAR(r.R_um, 2 * kR2 + 4, 1e-12);
  EXPECT_DOUBLE_EQ(r.E_up_um, 3.0);
  EXPECT_DOUBLE_EQ(r.E_down_um, 2.0);
  EXPECT_DOUBLE_EQ(r.E_um, 4.0);
  EXPECT_DOUBLE_EQ(r.M_um, 0.5);
  EXPECT_NEAR(r.A_up_um, 3 + 2 * kR2, 1e-12);    // (2 + 2s) - (-1)
  EXPECT_NEAR(r.A_down_um, 2 + 4 * kR2, 1e-12);  // (3 + 2s) - (1 - 2s)
  EXPECT_NEAR(r.A_um, 2 + 4 * kR2, 1e-12);       // the same extremes over both
  // VDI 3441: Pa = M, U = down - up: -1 and 4, Ps = 6 (s_up + s_down) / 2.
  EXPECT_DOUBLE_EQ(e->vdi.Pa_um, 0.5);
  EXPECT_DOUBLE_EQ(e->vdi.U_max_um, 4.0);
  EXPECT_DOUBLE_EQ(e->vdi.U_mean_um, 2.5);
  EXPECT_NEAR(e->vdi.Ps_max_um, 6 * kR2, 1e-12);
  EXPECT_NEAR(e->vdi.P_um, 1 + 6 * kR2, 1e-12);  // (1.5 + (1 + 6s)/2) - (1.5 - (1 + 6s)/2)
  // Uncertainty, L = 1 m: device 0.3, misalignment 1.2, M 2.457, E 1.8, EVE 1.2.
  const PositioningUncertainty& U = e->uncertainty;
  const double comp = 0.09 + 1.44 + 2.457 * 2.457 + 3.24;
  EXPECT_NEAR(U.device_um, 0.3, 1e-12);
  EXPECT_NEAR(U.misalignment_um, 1.2, 1e-12);
  EXPECT_NEAR(U.machine_m_um, 2.457, 1e-12);
  EXPECT_NEAR(U.machine_e_um, 1.8, 1e-12);
  EXPECT_NEAR(U.E_um, std::sqrt(comp + 1.44 / 5), 1e-12);
  EXPECT_NEAR(U.M_um, std::sqrt(comp + 1.44 / 10), 1e-12);
  EXPECT_NEAR(U.R_up_down_um, 2.4, 1e-12);
  EXPECT_NEAR(U.B_um, 1.08, 1e-12);
  EXPECT_NEAR(U.R_um, 2.64, 1e-12);
  EXPECT_NEAR(U.A_um, std::sqrt(comp + 1.44 / 5 + 5.76), 1e-12);
}

// ---- an independent implementation, from the definitions, for comparison
struct Reference {
  double A, Aup, Adn, E, Eup, Edn, M, R, Rup, Rdn, B, Bmean, P, Ps, Umax, Umean;
};

Reference ReferenceIso(const PositioningData& d) {
  const size_t m = d.targets_mm.size();
  std::vector<std::vector<double>> up(m), dn(m);
  for (const auto& run : d.runs) {
    for (size_t i = 0; i < m; ++i) (run.direction > 0 ? up : dn)[i].push_back(run.deviations_um[i]);
  }
  auto mean = [](const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  };
  auto sd = [&](const std::vector<double>& v) {
    const double mu = mean(v);
    double s = 0;
    for (double x : v) s += (x - mu) * (x - mu);
    return std::sqrt(s / (v.size() - 1));
  };
  std::vector<double> mu(m), md(m), su(m), sdn(m), mb(m), b(m), u(m), ps(m);
  for (size_t i = 0; i < m; ++i) {
    mu[i] = mean(up[i]), md[i] = mean(dn[i]), su[i] = sd(up[i]), sdn[i] = sd(dn[i]);
    mb[i] = (mu[i] + md[i]) / 2, b[i] = mu[i] - md[i], u[i] = md[i] - mu[i];
    ps[i] = 3 * (su[i] + sdn[i]);
  }
  auto span = [](const std::vector<double>& hi, const std::vector<double>& lo) {
    return *std::max_element(hi.begin(), hi.end()) - *std::min_element(lo.begin(), lo.end());
  };
  auto plus = [&](const std::vector<double>& a, const std::vector<double>& s, double k) {
    std::vector<double> o(m);
    for (size_t i = 0; i < m; ++i) o[i] = a[i] + k * s[i];
    return o;
  };
  auto cat = [](std::vector<double> a, const std::vector<double>& b2) {
    a.insert(a.end(), b2.begin(), b2.end());
    return a;
  };
  Reference r{};
  r.Aup = span(plus(mu, su, 2), plus(mu, su, -2));
  r.Adn = span(plus(md, sdn, 2), plus(md, sdn, -2));
  r.A = span(cat(plus(mu, su, 2), plus(md, sdn, 2)), cat(plus(mu, su, -2), plus(md, sdn, -2)));
  r.Eup = span(mu, mu);
  r.Edn = span(md, md);
  r.E = span(cat(mu, md), cat(mu, md));
  r.M = span(mb, mb);
  for (size_t i = 0; i < m; ++i) {
    r.Rup = std::max(r.Rup, 4 * su[i]);
    r.Rdn = std::max(r.Rdn, 4 * sdn[i]);
    r.R = std::max({r.R, 2 * su[i] + 2 * sdn[i] + std::fabs(b[i]), 4 * su[i], 4 * sdn[i]});
    r.B = std::max(r.B, std::fabs(b[i]));
    r.Bmean += b[i] / m;
    r.Ps = std::max(r.Ps, ps[i]);
    r.Umax = std::max(r.Umax, std::fabs(u[i]));
    r.Umean += std::fabs(u[i]) / m;
  }
  std::vector<double> hi(m), lo(m);
  for (size_t i = 0; i < m; ++i) {
    hi[i] = mb[i] + (std::fabs(u[i]) + ps[i]) / 2;
    lo[i] = mb[i] - (std::fabs(u[i]) + ps[i]) / 2;
  }
  r.P = span(hi, lo);
  return r;
}

TEST(Iso230_2, AgreesWithAnIndependentImplementationOnRandomAxes) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> z(0, 1);
  for (int trial = 0; trial < 50; ++trial) {
    PositioningData d;
    const int m = 2 + trial % 40, n = 2 + trial % 5;
    for (int i = 0; i < m; ++i) d.targets_mm.push_back(25.0 * i);
    for (int r = 0; r < 2 * n; ++r) {
      PositioningRun run{r % 2 == 0 ? +1 : -1, {}};
      for (int i = 0; i < m; ++i) {
        run.deviations_um.push_back(3 * std::sin(i * 0.3) + (run.direction > 0 ? 1.5 : -1.5) +
                                    0.8 * z(rng));
      }
      d.runs.push_back(run);
    }
    auto e = EvaluatePositioning(d, {});
    ASSERT_TRUE(e.ok());
    Reference ref = ReferenceIso(d);
    const Iso230Result& r = e->iso;
    for (auto [got, want] : {std::pair{r.A_um, ref.A},
                             {r.A_up_um, ref.Aup},
                             {r.A_down_um, ref.Adn},
                             {r.E_um, ref.E},
                             {r.E_up_um, ref.Eup},
                             {r.E_down_um, ref.Edn},
                             {r.M_um, ref.M},
                             {r.R_um, ref.R},
                             {r.R_up_um, ref.Rup},
                             {r.R_down_um, ref.Rdn},
                             {r.B_um, ref.B},
                             {r.B_mean_um, ref.Bmean},
                             {e->vdi.P_um, ref.P},
                             {e->vdi.Ps_max_um, ref.Ps},
                             {e->vdi.U_max_um, ref.Umax},
                             {e->vdi.U_mean_um, ref.Umean}}) {
      EXPECT_NEAR(got, want, 1e-9) << "trial " << trial;
    }
  }
}

TEST(Iso230_2, MalformedDataIsRefusedWithTheField) {
  PositioningData d = HandVector();
  d.runs.resize(3);  // one direction has a single run
  EXPECT_NE(ValidatePositioning(d).message().find("at least 2 runs"), std::string::npos);
  d = HandVector();
  d.runs[1].deviations_um.pop_back();
  EXPECT_NE(ValidatePositioning(d).message().find("runs[1].deviations_um"), std::string::npos);
  d = HandVector();
  d.targets_mm = {1000.0, 0.0};
  EXPECT_NE(ValidatePositioning(d).message().find("strictly increasing"), std::string::npos);
  d = HandVector();
  d.targets_mm = {0.0};
  EXPECT_FALSE(ValidatePositioning(d).ok());
}

TEST(PitchTable, NegatedMeanPerTargetAndBacklash) {
  auto e = EvaluatePositioning(HandVector(), {});
  PitchTable t = MakePitchTable(e->iso);
  EXPECT_DOUBLE_EQ(t.correction_mm[0], -0.0015);
  EXPECT_DOUBLE_EQ(t.correction_up_mm[1], 0.001);
  EXPECT_DOUBLE_EQ(t.correction_down_mm[1], -0.003);
  EXPECT_DOUBLE_EQ(t.backlash_mm, -0.0015);
  EXPECT_TRUE(t.equidistant);
  EXPECT_DOUBLE_EQ(t.step_mm, 1000.0);
}

TEST(ColumnCheck, CircleThroughThreeSpherePositionsIsExact) {
  // Centre (12.5, -40), radius 250: B = 0, 90, 180 degrees.
  auto c = FitCircle({{262.5, -40.0}, {12.5, 210.0}, {-237.5, -40.0}});
  ASSERT_TRUE(c.ok());
  EXPECT_NEAR(c->cx, 12.5, 1e-9);
  EXPECT_NEAR(c->cz, -40.0, 1e-9);
  EXPECT_NEAR(c->r, 250.0, 1e-9);
  EXPECT_NEAR(c->rms, 0.0, 1e-9);
  // A fourth point 2 um outside: minimising 2 rho^2 + (d - rho)^2 +
  // (0.002 - d - rho)^2 over the centre shift d and radius change rho gives
  // d = 0.001, rho = 0.0005. Collinear points have no circle.
  auto c4 = FitCircle({{262.5, -40.0}, {12.5, 210.0}, {-237.5, -40.0}, {12.5, -290.002}});
  ASSERT_TRUE(c4.ok());
  EXPECT_NEAR(c4->cz, -40.001, 1e-7);
  EXPECT_NEAR(c4->r, 250.0005, 1e-7);
  EXPECT_NEAR(c4->cx, 12.5, 1e-9);
  EXPECT_FALSE(FitCircle({{0, 0}, {1, 1}, {2, 2}}).ok());
}

TEST(ColumnCheck, ArtifactExpansionIsCorrectedBeforeUse) {
  // The study's KD sphere in Y (docs/model.md §11), eps = 0.0069 * TW - 0.1371 mm; at 21.3 degC
  // 0.00987 mm.
  PointExpansion kd;
  kd.beta_y = 0.0069;
  kd.b_y = -0.1371;
  EXPECT_NEAR(kd.At(21.3).y, 0.00987, 1e-12);
  Artifact art;
  art.points["KD"] = {{0.0, 500.0, 0.0}, kd};
  art.points["P1"] = {{100.0, 400.0, 0.0}, {}};
  art.points["P2"] = {{100.0, 600.0, 0.0}, {}};
  art.points["P3"] = {{100.0, 800.0, 0.0}, {}};
  art.schemes = {{"a", 'Y', 'X', "P1"}};
  // Spheres measured where the expanded sphere is: nominal Y + eps + 0.004 (zero shift).
  const double y = 500.0 + 0.00987 + 0.004;
  std::vector<SphereProbe> spheres = {
      {"KD", 0, {250.0, y, 0.0}}, {"KD", 90, {0.0, y, 250.0}}, {"KD", 180, {-250.0, y, 0.0}}};
  std::vector<SurfaceProbe> points = {{"P1", "a", {100.002, 400.0, 0.0}},
                                      {"P2", "a", {100.004, 600.0, 0.0}},
                                      {"P3", "a", {100.007, 800.0, 0.0}}};
  // The shank sees the sphere 3 um further in X and 1 um less in Y at 100 mm.
  ParallelismProbe par{{0.0, 500.0, 0.0}, {0.003, 499.999, 0.0}, 100.0};
  auto r = EvaluateColumnCheck(art, 21.3, spheres, points, par);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_NEAR(r->machine_zero_mm.y, 0.004, 1e-9);
  EXPECT_NEAR(r->machine_zero_mm.x, 0.0, 1e-9);
  ASSERT_EQ(r->straightness.size(), 1u);
  // Deviations 0, 2, 5 um at 400, 600, 800 mm (relative to P1). By hand:
  // the least-squares line has slope 5/400 um/mm = 12.5 um/m and passes
  // 7/3 um at 600 mm; residuals +1/6, -1/3, +1/6 um; straightness 0.5 um
  // (the old reading against P1 alone said 5 um: the slope).
  EXPECT_NEAR(r->straightness[0].slope_um_per_m, 12.5, 1e-6);
  EXPECT_NEAR(r->straightness[0].relative_um["P1"], 1.0 / 6, 1e-6);
  EXPECT_NEAR(r->straightness[0].relative_um["P2"], -1.0 / 3, 1e-6);
  EXPECT_NEAR(r->straightness[0].relative_um["P3"], 1.0 / 6, 1e-6);
  EXPECT_NEAR(r->straightness[0].straightness_um, 0.5, 1e-6);
  ASSERT_TRUE(r->parallelism_um_per_100mm);
  EXPECT_NEAR(r->parallelism_um_per_100mm->first, 3.0, 1e-6);
  EXPECT_NEAR(r->parallelism_um_per_100mm->second, -1.0, 1e-6);
}

}  // namespace
}  // namespace thermocomp
