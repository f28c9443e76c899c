// method.md §1.1 — one horizontal-constrained RANSAC plane (grasp_core::fit_plane_ransac).
#include <gtest/gtest.h>

#include "grasp_core/plane_fit.hpp"
#include "synthetic_scene.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

using namespace grasp_core;
using grasp_test::SceneBuilder;

namespace {

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

/// Independent least-squares normal of a point set (for checking constructions).
Vec3 ls_normal(const PointsD& pts) {
  const Vec3 c = pts.colwise().mean().transpose();
  Mat3 s = Mat3::Zero();
  for (Eigen::Index i = 0; i < pts.rows(); ++i) {
    const Vec3 d = pts.row(i).transpose() - c;
    s += d * d.transpose();
  }
  Vec3 n = Eigen::SelfAdjointEigenSolver<Mat3>(s).eigenvectors().col(0);
  return n.z() < 0 ? Vec3(-n) : n;
}

}  // namespace

TEST(PlaneFit, RecoversPlaneTiltedWithinLimit) {
  const SceneFilterParams params;
  const double tilt = 6.0;  // < plane_max_tilt_deg = 10
  SceneBuilder b(11);
  b.horizontal_random(0.5, 0.0, 0.2, 0.5, 0.4, 3000, 0.002, tilt, 30.0);
  b.uniform_box(Vec3(0.2, -0.3, 0.0), Vec3(0.8, 0.3, 0.4), 1000);  // clutter
  const auto fit = fit_plane_ransac(b.points_d(), params, 1);
  ASSERT_TRUE(fit.has_value());
  const Vec3 truth = Eigen::AngleAxisd(tilt * M_PI / 180.0,
                                       Vec3(std::cos(M_PI / 6), std::sin(M_PI / 6), 0))
                     * Vec3::UnitZ();
  EXPECT_TRUE(fit->refined);
  EXPECT_LT(angle_deg(fit->plane.n, truth), 0.3);
  EXPECT_NEAR(fit->plane.tilt_deg(), tilt, 0.3);
  EXPECT_NEAR(fit->plane.signed_distance(Vec3(0.5, 0.0, 0.2)), 0.0, 0.001);
  EXPECT_GT(fit->plane.n.z(), 0.0);
  EXPECT_GT(fit->ransac_plane.n.z(), 0.0);
  EXPECT_NEAR(fit->plane.n.norm(), 1.0, 1e-12);
  EXPECT_GE(fit->inliers, 2900);
  EXPECT_EQ(fit->iterations, params.plane_ransac_iters);
}

TEST(PlaneFit, RejectsPlaneTiltedBeyondLimit) {
  const SceneFilterParams params;
  SceneBuilder steep(12);
  steep.horizontal_random(0.5, 0.0, 0.2, 0.5, 0.4, 3000, 0.001, 20.0, 0.0);
  EXPECT_FALSE(fit_plane_ransac(steep.points_d(), params, 1).has_value());

  // A steep plane with many points next to a small horizontal one: the horizontal one wins.
  SceneBuilder both(13);
  both.horizontal_random(0.5, 0.0, 0.3, 0.5, 0.4, 3000, 0.001, 20.0, 0.0);
  both.horizontal_random(0.5, 0.5, 0.1, 0.2, 0.2, 800, 0.001);
  const auto fit = fit_plane_ransac(both.points_d(), params, 1);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT(fit->plane.tilt_deg(), 1.0);
  EXPECT_NEAR(fit->plane.height_m(), 0.1, 0.001);
}

TEST(PlaneFit, TiltLimitIsAParameter) {
  SceneFilterParams params;
  params.plane_max_tilt_deg = 25.0;
  SceneBuilder steep(12);
  steep.horizontal_random(0.5, 0.0, 0.2, 0.5, 0.4, 3000, 0.001, 20.0, 0.0);
  const auto fit = fit_plane_ransac(steep.points_d(), params, 1);
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(fit->plane.tilt_deg(), 20.0, 0.2);
}

TEST(PlaneFit, CollinearSamplesAreDiscarded) {
  const SceneFilterParams params;
  // Every triple of these points is collinear: no model at all (and no crash).
  PointsD line(500, 3);
  for (int i = 0; i < 500; ++i) line.row(i) << 0.3 + 0.001 * i, -0.1, 0.2;
  EXPECT_FALSE(fit_plane_ransac(line, params, 1).has_value());

  // Many collinear points plus a few off the line: only samples that include an off-line
  // point can make a model, and the plane through line + off-line points is found.
  PointsD mixed(520, 3);
  mixed.topRows(500) = line;
  for (int i = 0; i < 20; ++i) mixed.row(500 + i) << 0.3 + 0.02 * i, 0.05 + 0.003 * (i % 5), 0.2;
  SceneFilterParams many = params;
  many.plane_ransac_iters = 400;
  const auto fit = fit_plane_ransac(mixed, many, 3);
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->inliers, 520);
  EXPECT_NEAR(fit->plane.height_m(), 0.2, 1e-6);
  EXPECT_LT(fit->plane.tilt_deg(), 1e-3);
}

TEST(PlaneFit, RefinedTableHeightUnderTwoMillimetreNoise) {
  // method.md §1.1 measured 0.17 mm; we require < 0.5 mm on every seed.
  const SceneFilterParams params;
  double worst = 0.0;
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    SceneBuilder b(seed);
    b.horizontal_random(0.5, 0.0, 0.200, 0.6, 0.5, 3200, 0.002);
    b.box(0.55, -0.05, 0.2, 0.05, 0.05, 0.05, 15.0, 0.004, 0.002, 2, 0);  // objects on it
    b.box(0.45, 0.10, 0.2, 0.05, 0.05, 0.05, -20.0, 0.004, 0.002, 2, 1);
    b.horizontal_random(0.5, -0.5, 0.0, 0.6, 0.3, 600, 0.002);            // floor
    const auto fit = fit_plane_ransac(b.points_d(), params, seed);
    ASSERT_TRUE(fit.has_value());
    EXPECT_TRUE(fit->refined);
    worst = std::max(worst, std::abs(fit->plane.height_m() - 0.200));
  }
  EXPECT_LT(worst, 0.0005);
}

TEST(PlaneFit, PostRefinementTiltRecheckKeepsRansacModel) {
  // A degenerate inlier set: a thin sliver (two rows 1 cm apart, 5 mm height difference,
  // i.e. a 26.6 deg slope across the sliver) plus a few points of a horizontal corner.
  // A horizontal model (from two points of the low row + one corner point) has every point
  // within 5 mm < plane_dist_thresh, but the least-squares plane through all of them is
  // tilted far beyond plane_max_tilt_deg.
  const SceneFilterParams params;
  PointsD pts(440, 3);
  int k = 0;
  for (int i = 0; i < 200; ++i) pts.row(k++) << 0.3 + 0.0025 * i, -0.005, 0.1975;  // low row
  for (int i = 0; i < 200; ++i) pts.row(k++) << 0.3 + 0.0025 * i + 0.001, 0.005, 0.2025;  // high row
  for (int i = 0; i < 40; ++i) pts.row(k++) << 0.3 + 0.0125 * i + 0.0005, 0.005, 0.1975;  // corner
  ASSERT_GT(angle_deg(ls_normal(pts), Vec3::UnitZ()), params.plane_max_tilt_deg);

  const auto fit = fit_plane_ransac(pts, params, 5);
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->inliers, 440);
  EXPECT_FALSE(fit->refined);
  EXPECT_LE(fit->plane.tilt_deg(), params.plane_max_tilt_deg);
  EXPECT_EQ(fit->plane.n, fit->ransac_plane.n);
  EXPECT_EQ(fit->plane.c, fit->ransac_plane.c);
}

TEST(PlaneFit, DegenerateInputsGiveNoPlane) {
  const SceneFilterParams params;
  EXPECT_FALSE(fit_plane_ransac(PointsD(0, 3), params, 1).has_value());
  PointsD two(2, 3);
  two << 0, 0, 0.2, 1, 0, 0.2;
  EXPECT_FALSE(fit_plane_ransac(two, params, 1).has_value());
  PointsD nan = PointsD::Constant(100, 3, std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(fit_plane_ransac(nan, params, 1).has_value());
  PointsD same = PointsD::Constant(100, 3, 0.2);  // all points identical
  EXPECT_FALSE(fit_plane_ransac(same, params, 1).has_value());
  // Three valid points among NaN/Inf rows: exactly one plane.
  PointsD three = PointsD::Constant(6, 3, std::numeric_limits<double>::infinity());
  three.row(1) << 0.0, 0.0, 0.2;
  three.row(3) << 0.1, 0.0, 0.2;
  three.row(5) << 0.0, 0.1, 0.2;
  const auto fit = fit_plane_ransac(three, params, 1);
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(fit->plane.height_m(), 0.2, 1e-6);
  EXPECT_EQ(fit->inliers, 3);
  // Invalid parameters are refused, not silently used (PCL treats eps angle 0 as "no limit").
  SceneFilterParams bad = params;
  bad.plane_max_tilt_deg = 0.0;
  EXPECT_THROW(fit_plane_ransac(three, bad, 1), std::invalid_argument);
}

TEST(PlaneFit, SameSeedSameResultFloatAndDouble) {
  const SceneFilterParams params;
  SceneBuilder b(21);
  b.horizontal_random(0.5, 0.0, 0.2, 0.5, 0.4, 2000, 0.002, 3.0, 0.0);
  b.uniform_box(Vec3(0.2, -0.3, 0.0), Vec3(0.8, 0.3, 0.4), 2000);
  const auto a = fit_plane_ransac(b.points_d(), params, 7);
  const auto c = fit_plane_ransac(b.points_d(), params, 7);
  const auto f = fit_plane_ransac(b.points_f(), params, 7);
  ASSERT_TRUE(a && c && f);
  EXPECT_EQ(a->plane.n, c->plane.n);
  EXPECT_EQ(a->plane.c, c->plane.c);
  EXPECT_EQ(a->inliers, f->inliers);  // the search runs in float either way
  EXPECT_NEAR(a->plane.c, f->plane.c, 1e-9);
}
