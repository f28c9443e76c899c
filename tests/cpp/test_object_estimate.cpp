// method.md §2.1-2.4 and 2.6: decomposition, width scan, direction choice, box, height, guards.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "grasp_core/object_estimate.hpp"
#include "synthetic_objects.hpp"

using namespace grasp_core;
using namespace grasp_test;

namespace {

constexpr double kBand = 0.01;  // method.md §1.6 default band [m]

bool has_note(const std::vector<std::string>& notes, const std::string& part) {
  return std::any_of(notes.begin(), notes.end(),
                     [&](const std::string& s) { return s.find(part) != std::string::npos; });
}

/// (a, b) of a horizontal-table cloud (u = x, v = y, p0 on the z axis).
void ab_of(const PointsD& P, std::vector<double>* a, std::vector<double>* b) {
  a->clear();
  b->clear();
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    a->push_back(P(i, 0));
    b->push_back(P(i, 1));
  }
}

/// Noisy top of a 5 cm cube (1 mm grid, 2 mm depth noise) at the given yaw.
PointsD cube_top(double yaw_rad, unsigned seed = 3, double corner_radius_m = 0.0) {
  auto pts = rect_top(0.05, 0.05, 0.05, 0.001, corner_radius_m);
  add_z_noise(pts, 0.002, seed);
  Placement pl;
  pl.yaw_rad = yaw_rad;
  return place(pts, pl);
}

EstimateResult estimate(const PointsD& P, std::optional<double> prev = std::nullopt,
                        const Placement& pl = Placement()) {
  return estimate_object(P, table_plane(pl), ObbParams{}, prev, kBand);
}

}  // namespace

// ---- helpers ---------------------------------------------------------------------------

TEST(Stats, MedianOddEvenEmpty) {
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);  // mean of the two middle values
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(Stats, AngleDistModPi) {
  EXPECT_NEAR(angle_dist_mod_pi(1 * kDeg, 179 * kDeg), 2 * kDeg, 1e-12);
  EXPECT_NEAR(angle_dist_mod_pi(0.0, 90 * kDeg), 90 * kDeg, 1e-12);
  EXPECT_NEAR(angle_dist_mod_pi(10 * kDeg, 190 * kDeg), 0.0, 1e-12);
  EXPECT_NEAR(angle_dist_mod_pi(-5 * kDeg, 5 * kDeg), 10 * kDeg, 1e-12);
}

TEST(Stats, WrapModPi) {
  EXPECT_NEAR(wrap_mod_pi(-1 * kDeg), 179 * kDeg, 1e-12);
  EXPECT_NEAR(wrap_mod_pi(181 * kDeg), 1 * kDeg, 1e-12);
  EXPECT_GE(wrap_mod_pi(-1e-300), 0.0);
  EXPECT_LT(wrap_mod_pi(-1e-300), M_PI);
}

TEST(Stats, CircularMedianAcrossWrapIsOrderFree) {
  std::vector<double> ang = {178 * kDeg, 179 * kDeg, 1 * kDeg, 2 * kDeg};
  const double m1 = circular_median_mod_pi(ang, ang.front());
  EXPECT_NEAR(angle_dist_mod_pi(m1, 0.0), 0.0, 1e-12);  // offsets 0, 1, 3, 4 deg -> 2 deg
  std::reverse(ang.begin(), ang.end());
  const double m2 = circular_median_mod_pi(ang, ang.front());
  EXPECT_NEAR(m1, m2, 1e-12);
  // A naive median of the raw angles lands on the opposite side of the circle.
  EXPECT_GT(angle_dist_mod_pi(median(ang), m1), 1.0);
}

// ---- 2.1 decomposition -----------------------------------------------------------------

TEST(Decomposition, InPlaneBasisIsRightHandedAndDeterministic) {
  const std::vector<Vec3> normals = {Vec3::UnitZ(), Vec3(0.1, -0.05, 1).normalized(),
                                     Vec3(1, 0, 0.2).normalized(), Vec3(0, 1, 1).normalized()};
  for (const auto& n : normals) {
    Vec3 u, v, u2, v2;
    in_plane_basis(n, &u, &v);
    in_plane_basis(n, &u2, &v2);
    EXPECT_NEAR(u.norm(), 1.0, 1e-12);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12);
    EXPECT_NEAR(u.dot(n), 0.0, 1e-12);
    EXPECT_NEAR(v.dot(n), 0.0, 1e-12);
    EXPECT_TRUE(u.cross(v).isApprox(n, 1e-12));
    EXPECT_EQ(u, u2);
    EXPECT_EQ(v, v2);
  }
  Vec3 u, v;
  in_plane_basis(Vec3::UnitZ(), &u, &v);
  EXPECT_TRUE(u.isApprox(Vec3::UnitX()));
  EXPECT_TRUE(v.isApprox(Vec3::UnitY()));
}

TEST(Decomposition, CentreAndHeightOnATiltedTable) {
  Placement pl;
  pl.table_z_m = 0.3;
  pl.table_tilt = Eigen::AngleAxisd(6 * kDeg, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  pl.x_m = 0.4;
  pl.y_m = -0.1;
  pl.yaw_rad = 0.4;
  const PointsD P = place(box_top_and_side(0.03, 0.06, 0.04, 0.001, 0.0, 1), pl);
  const auto r = estimate(P, std::nullopt, pl);
  ASSERT_TRUE(r.estimate) << r.failure;
  const Vec3 truth = to_world(Vec3(0, 0, 0.02), pl);
  EXPECT_LT((r.estimate->center - truth).norm(), 1e-3);
  EXPECT_NEAR(r.estimate->height_m, 0.04, 1e-6);
  EXPECT_NEAR(r.estimate->width_m, 0.03, 1e-3);
  EXPECT_NEAR(r.estimate->perp_width_m, 0.06, 1e-3);
  EXPECT_TRUE(r.estimate->R_box.col(2).isApprox(table_plane(pl).n, 1e-12));
  EXPECT_NEAR(r.estimate->R_box.determinant(), 1.0, 1e-12);
}

// ---- 2.2 width scan ----------------------------------------------------------------------

TEST(WidthScan, RectangleExtentsAtZeroAndNinety) {
  std::vector<double> a, b;
  ab_of(place(rect_top(0.08, 0.03, 0.02, 0.002), Placement()), &a, &b);
  const auto ext = width_scan(a, b, 4);  // 0, 45, 90, 135 deg
  ASSERT_EQ(ext.size(), 4u);
  EXPECT_NEAR(ext[0], 0.08, 1e-12);
  EXPECT_NEAR(ext[2], 0.03, 1e-12);
  EXPECT_NEAR(ext[1], 0.11 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(scan_angle_rad(180, 361), M_PI * 180 / 361, 1e-15);  // theta_t = pi t / T
  EXPECT_EQ(width_scan({}, {}, 5), std::vector<double>(5, 0.0));
}

TEST(WidthScan, AnisotropySquareRoundCuboid) {
  const ObbParams p;
  // Square: a 5 cm cube top with the corner loss of a depth camera (5 mm radius).
  for (double yaw : {0.0, 0.3, 1.0}) {
    const auto r = estimate(cube_top(yaw, 5, 0.005));
    ASSERT_TRUE(r.estimate);
    EXPECT_GE(r.estimate->anisotropy, 1.28) << yaw;
    EXPECT_LE(r.estimate->anisotropy, 1.38) << yaw;
    EXPECT_TRUE(r.estimate->yaw_defined);
  }
  // Round: a 5 cm cylinder top, 1 mm grid.
  auto disk = disk_top(0.025, 0.07, 0.001);
  add_z_noise(disk, 0.002, 9);
  const auto round = estimate(place(disk, Placement()));
  ASSERT_TRUE(round.estimate);
  EXPECT_GE(round.estimate->anisotropy, 1.004);
  EXPECT_LE(round.estimate->anisotropy, 1.04);
  EXPECT_FALSE(round.estimate->yaw_defined);
  // 2:1 cuboid.
  const auto cub = estimate(place(rect_top(0.06, 0.03, 0.04, 0.001), Placement()));
  ASSERT_TRUE(cub.estimate);
  EXPECT_GT(cub.estimate->anisotropy, p.isotropy_ratio_max);
  EXPECT_TRUE(cub.estimate->yaw_defined);
  EXPECT_TRUE(std::isinf(anisotropy_ratio({0.0, 0.01})));
}

// ---- 2.3 direction choice ----------------------------------------------------------------

TEST(Direction, SquareGivesTwoRunsAndPriorPicksTheNearer) {
  const double yaw = 20 * kDeg;
  std::vector<double> a, b;
  ab_of(cube_top(yaw), &a, &b);
  const ObbParams p;
  const auto ext = width_scan(a, b, p.n_theta);
  const auto runs = direction_runs(ext, p.width_tol_m);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_NEAR(runs[0].theta_rad, yaw, 0.6 * kDeg);
  EXPECT_NEAR(runs[1].theta_rad, yaw + M_PI / 2, 0.6 * kDeg);
  for (const auto& r : runs) EXPECT_NEAR(r.width_m, 0.05, 1e-3);

  EXPECT_NEAR(choose_direction(ext, p.width_tol_m, 100 * kDeg).theta_rad, runs[1].theta_rad, 1e-12);
  EXPECT_NEAR(choose_direction(ext, p.width_tol_m, 30 * kDeg).theta_rad, runs[0].theta_rad, 1e-12);
  // mod-pi distance: 175 deg is nearer to 20 deg (25 deg) than to 110 deg (65 deg).
  EXPECT_NEAR(choose_direction(ext, p.width_tol_m, 175 * kDeg).theta_rad, runs[0].theta_rad, 1e-12);
  // Without prior: the smallest theta.
  const auto none = choose_direction(ext, p.width_tol_m, std::nullopt);
  EXPECT_NEAR(none.theta_rad, runs[0].theta_rad, 1e-12);
  EXPECT_EQ(none.chosen, 0);
}

TEST(Direction, WithoutPriorSmallestThetaWinsWhateverTheYaw) {
  // Yaw 100 deg: runs at 10 and 100 deg -> 10 deg, the run NOT aligned with the yaw.
  const auto r = estimate(cube_top(100 * kDeg));
  ASSERT_TRUE(r.estimate);
  EXPECT_NEAR(r.estimate->theta_rad, 10 * kDeg, 0.6 * kDeg);
  // With a prior near 100 deg the other run is taken.
  const auto r2 = estimate(cube_top(100 * kDeg), 95 * kDeg);
  ASSERT_TRUE(r2.estimate);
  EXPECT_NEAR(r2.estimate->theta_rad, 100 * kDeg, 0.6 * kDeg);
  EXPECT_NEAR(r2.estimate->width_m, 0.05, 1e-3);
}

TEST(Direction, RunTouchingBothEndsIsMergedWithCorrectMedian) {
  const double yaw = -0.2 * kDeg;  // the minimum straddles theta = 0 = pi
  std::vector<double> a, b;
  ab_of(cube_top(yaw), &a, &b);
  const ObbParams p;
  const auto ext = width_scan(a, b, p.n_theta);
  const auto runs = direction_runs(ext, p.width_tol_m);
  ASSERT_EQ(runs.size(), 2u);  // not 3: the two ends are one run
  const DirectionRun* merged = nullptr;
  for (const auto& r : runs)
    if (r.last < r.first) merged = &r;
  ASSERT_NE(merged, nullptr);
  EXPECT_EQ(merged->indices.front(), merged->first);
  EXPECT_EQ(merged->indices.back(), merged->last);
  EXPECT_EQ(merged->indices.back() + 1 + (p.n_theta - merged->indices.front()),
            static_cast<int>(merged->indices.size()));
  EXPECT_LT(angle_dist_mod_pi(merged->theta_rad, yaw), 0.6 * kDeg);
  // A naive median of the raw angles is ~90 deg off: the test can fail.
  std::vector<double> raw;
  for (int t : merged->indices) raw.push_back(scan_angle_rad(t, p.n_theta));
  EXPECT_GT(angle_dist_mod_pi(median(raw), yaw), 80 * kDeg);
  // Order inside the run does not matter.
  std::vector<double> shuffled = raw;
  std::mt19937 rng(1);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  EXPECT_NEAR(circular_median_mod_pi(shuffled, shuffled.front()), merged->theta_rad, 1e-12);
  // The full estimate closes along the yaw with the true side as width.
  const auto r = estimate(cube_top(yaw), yaw);
  ASSERT_TRUE(r.estimate);
  EXPECT_LT(angle_dist_mod_pi(r.estimate->theta_rad, yaw), 0.6 * kDeg);
  EXPECT_NEAR(r.estimate->width_m, 0.05, 1e-3);
}

TEST(Direction, RunsOfASyntheticScan) {
  // Hand-made scan: candidates {0,1} and {8,9} (merged) and {4,5}; tol 0.
  const std::vector<double> ext = {1, 1, 2, 2, 1, 1, 2, 2, 1, 1};
  const auto runs = direction_runs(ext, 0.0);
  ASSERT_EQ(runs.size(), 2u);
  const double step = M_PI / 10;
  // Merged run {8, 9, 0, 1}: offsets from 8: 0, 1, 2, 3 steps -> median 1.5 steps -> 9.5.
  // Sorted by theta: run {4,5} (4.5 steps) first, then the merged run (9.5 steps).
  EXPECT_NEAR(runs[0].theta_rad, 4.5 * step, 1e-12);
  EXPECT_NEAR(runs[1].theta_rad, 9.5 * step, 1e-12);
  EXPECT_EQ(runs[1].first, 8);
  EXPECT_EQ(runs[1].last, 1);
  // All candidates: one run over the whole circle.
  EXPECT_EQ(direction_runs(std::vector<double>(6, 1.0), 0.0).size(), 1u);
  EXPECT_TRUE(direction_runs({}, 0.0).empty());
}

TEST(Direction, SmallestThetaOnlyAmongRunsNearTheSmallestWidth) {
  // Run A at index 1 (width 1.0015), run B at index 6 (width 1.0): tol 0.002 -> both
  // candidates; runs within tol of the smallest width: both -> smallest theta (A).
  std::vector<double> ext(10, 5.0);
  ext[1] = 1.0015;
  ext[6] = 1.0;
  const auto c = choose_direction(ext, 0.002, std::nullopt);
  ASSERT_EQ(c.runs.size(), 2u);
  EXPECT_NEAR(c.theta_rad, M_PI * 1 / 10, 1e-12);
  EXPECT_NEAR(c.width_m, 1.0015, 1e-12);
  // NaN prior is ignored.
  EXPECT_NEAR(choose_direction(ext, 0.002, std::numeric_limits<double>::quiet_NaN()).theta_rad,
              M_PI * 1 / 10, 1e-12);
}

// ---- 2.4 box, height, centre -----------------------------------------------------------------

TEST(Box, CuboidWidthPerpWidthAndAxes) {
  Placement pl;
  pl.yaw_rad = 30 * kDeg;
  const auto r = estimate(place(rect_top(0.03, 0.06, 0.04, 0.001), pl));
  ASSERT_TRUE(r.estimate);
  const auto& e = *r.estimate;
  EXPECT_NEAR(e.width_m, 0.03, 5e-4);       // the short side closes
  EXPECT_NEAR(e.perp_width_m, 0.06, 5e-4);
  EXPECT_NEAR(e.theta_rad, 30 * kDeg, 0.6 * kDeg);
  EXPECT_TRUE(e.extents.isApprox(Vec3(e.width_m, e.perp_width_m, e.height_m)));
  EXPECT_NEAR(e.R_box.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(e.R_box.col(0).isApprox(Vec3(std::cos(e.theta_rad), std::sin(e.theta_rad), 0)));
  EXPECT_TRUE((e.center - to_world(Vec3(0, 0, 0.02), pl)).norm() < 1e-4);
}

TEST(Height, SliceMedianBeatsMaxUnderNoise) {
  const double h = 0.05;
  auto pts = rect_top(0.05, 0.05, h, 0.001);
  add_z_noise(pts, 0.002, 11);
  const PointsD P = place(pts, Placement());
  const auto r = estimate(P);
  ASSERT_TRUE(r.estimate);
  double max_d = -1;
  for (Eigen::Index i = 0; i < P.rows(); ++i) max_d = std::max(max_d, P(i, 2) - 0.2);
  EXPECT_NEAR(r.estimate->height_m, h, 1e-3);
  EXPECT_GT(max_d - h, 0.004);  // max is biased upward by several mm
}

TEST(Height, SliceMedianRules) {
  const ObbParams p;
  // Fewer than 3 kept: stays at the max.
  EXPECT_DOUBLE_EQ(slice_median_top({0.0, 0.001, 0.05}, 0.002, 4.0, 3), 0.05);
  // Even count in the slice: mean of the two middle values.
  EXPECT_DOUBLE_EQ(slice_median_top({0.0, 0.040, 0.042, 0.044, 0.046}, 0.002, 4.0, 1), 0.043);
  // Side points far below the slice do not pull the top down.
  std::vector<double> d = {0.05, 0.05, 0.05, 0.05, 0.01, 0.02, 0.03};
  EXPECT_DOUBLE_EQ(slice_median_top(d, p.depth_noise_sigma, p.top_slice_sigmas, p.top_slice_iters), 0.05);
  EXPECT_TRUE(std::isnan(slice_median_top({}, 0.002, 4.0, 3)));
}

// ---- 2.5 / failures -------------------------------------------------------------------------

TEST(Failures, PcaFailureFailsTheEstimate) {
  PointsD line(20, 3);
  for (int i = 0; i < 20; ++i) line.row(i) = Vec3(0.5 + 0.001 * i, 0, 0.23).transpose();
  const auto r = estimate(line);
  EXPECT_FALSE(r.estimate);
  EXPECT_NE(r.failure.find("collinear"), std::string::npos) << r.failure;
}

TEST(Failures, TinyEmptyNanAndBadPlaneNeverCrash) {
  EXPECT_FALSE(estimate(PointsD(0, 3)).estimate);
  EXPECT_FALSE(estimate(PointsD::Zero(2, 3)).estimate);
  PointsD P = cube_top(0.1);
  const Eigen::Index n = P.rows();
  P.conservativeResize(n + 2, 3);
  P.row(n) = Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0).transpose();
  P.row(n + 1) = Vec3(0, std::numeric_limits<double>::infinity(), 0).transpose();
  const auto r = estimate(P);
  ASSERT_TRUE(r.estimate) << r.failure;
  EXPECT_EQ(r.estimate->num_points, n);
  Plane bad;
  bad.n = Vec3::Zero();
  EXPECT_FALSE(estimate_object(P, bad, ObbParams{}).estimate);
}

TEST(Failures, ZeroWidthFootprintIsRefusedNotCrashed) {
  // A vertical sheet: PCA coplanar (valid), footprint width 0.
  std::vector<Vec3> sheet;
  for (int j = 0; j <= 30; ++j)
    for (int k = 0; k <= 30; ++k) sheet.emplace_back(0.0, -0.015 + 0.001 * j, 0.001 * k);
  const auto r = estimate(place(sheet, Placement()));
  ASSERT_TRUE(r.estimate) << r.failure;
  EXPECT_NEAR(r.estimate->width_m, 0.0, 1e-12);
  EXPECT_TRUE(std::isinf(r.estimate->anisotropy));
  EXPECT_FALSE(r.estimate->width_ok);
  EXPECT_FALSE(r.estimate->grasp_ok);
}

// ---- 2.6 guards --------------------------------------------------------------------------

TEST(Guards, RestingCubeWithSidesIsGraspable) {
  const auto r = estimate(place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.002, 2), Placement()));
  ASSERT_TRUE(r.estimate);
  EXPECT_TRUE(r.estimate->resting);
  EXPECT_TRUE(r.estimate->grasp_ok);
  EXPECT_TRUE(r.estimate->notes.empty());
  EXPECT_TRUE(r.estimate->undetermined_notes.empty());
}

TEST(Guards, FloatingObjectIsRefusedWithANote) {
  Placement pl;
  pl.lift_m = 0.03;  // lowest point 30 mm above the plane > band + margin = 18 mm
  const auto r = estimate(place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.0, 2), pl));
  ASSERT_TRUE(r.estimate);
  EXPECT_FALSE(r.estimate->resting);
  EXPECT_FALSE(r.estimate->grasp_ok);
  EXPECT_TRUE(has_note(r.estimate->notes,
                       "floating/stacked: lowest point 30.0 mm above plane (band + margin = 18.0 mm)"))
      << (r.estimate->notes.empty() ? "" : r.estimate->notes[0]);
  EXPECT_NEAR(r.estimate->lowest_m, 0.03, 1e-9);
}

TEST(Guards, TopOnlyViewIsUndeterminedNotRefused) {
  Placement pl;
  pl.lift_m = 0.03;  // even lifted: only the top is seen, so resting cannot be judged
  const PointsD top = cube_top(0.2);
  const auto r = estimate(top);
  ASSERT_TRUE(r.estimate);
  // The literal "max d - min d > 3 sigma" would call this noisy top "sides seen" (and
  // refuse the cube as floating): the range of ~2500 noisy samples is ~7 sigma.
  const double span = top.col(2).maxCoeff() - top.col(2).minCoeff();
  EXPECT_GT(span, ObbParams{}.side_seen_sigmas * ObbParams{}.depth_noise_sigma);
  EXPECT_TRUE(r.estimate->resting);
  EXPECT_TRUE(r.estimate->grasp_ok);
  EXPECT_TRUE(r.estimate->notes.empty());
  EXPECT_TRUE(has_note(r.estimate->undetermined_notes, "only the top is seen"));
  const auto lifted = estimate(place(rect_top(0.05, 0.05, 0.05, 0.001), pl));
  ASSERT_TRUE(lifted.estimate);
  EXPECT_TRUE(lifted.estimate->grasp_ok);
}

TEST(Guards, UnknownBandIsUndetermined) {
  Placement pl;
  pl.lift_m = 0.03;
  const auto r = estimate_object(place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.0, 2), pl),
                                 table_plane(pl), ObbParams{}, std::nullopt, std::nullopt);
  ASSERT_TRUE(r.estimate);
  EXPECT_TRUE(r.estimate->resting);
  EXPECT_TRUE(has_note(r.estimate->undetermined_notes, "band unknown"));
}

TEST(Guards, TooLow) {
  // A 3 mm tall plate: its side is too short to judge resting (undetermined), but the
  // height guard still applies.
  const auto r = estimate(place(box_top_and_side(0.04, 0.04, 0.003, 0.001, 0.0, 2), Placement()));
  ASSERT_TRUE(r.estimate);
  EXPECT_FALSE(r.estimate->height_ok);
  EXPECT_FALSE(r.estimate->grasp_ok);
  EXPECT_TRUE(has_note(r.estimate->notes, "too low: 3.0 mm")) << r.estimate->notes[0];
}

// Regression: a cluster below the plane gave an estimate with a negative height (and
// extents.z < 0), refused only by the "too low" guard. It is no estimate now.
TEST(Failures, ClusterBelowThePlaneHasNoEstimate) {
  Placement pl;
  pl.lift_m = -0.08;  // a 5 cm cube whose top is 3 cm below the plane
  const auto r = estimate(place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.0, 2), pl));
  EXPECT_FALSE(r.estimate);
  EXPECT_NE(r.failure.find("not above the plane"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("30.0 mm below the plane"), std::string::npos) << r.failure;
  // Straddling the plane (top above it) is still an estimate, judged by the guards.
  pl.lift_m = -0.03;
  const auto s = estimate(place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.0, 2), pl));
  ASSERT_TRUE(s.estimate) << s.failure;
  EXPECT_NEAR(s.estimate->height_m, 0.02, 1e-6);
  EXPECT_GE(s.estimate->extents.z(), 0.0);
}

TEST(Failures, AbsurdCoordinatesAreIgnored) {
  PointsD pts = place(box_top_and_side(0.05, 0.05, 0.05, 0.001, 0.002, 2), Placement());
  const auto ref = estimate(pts);
  ASSERT_TRUE(ref.estimate);
  PointsD more(pts.rows() + 20, 3);
  more.topRows(pts.rows()) = pts;
  for (Eigen::Index i = pts.rows(); i < more.rows(); ++i) more.row(i) << 3.4e38, 3.4e38, 3.4e38;
  const auto r = estimate(more);
  ASSERT_TRUE(r.estimate) << r.failure;
  EXPECT_EQ(r.estimate->num_points, ref.estimate->num_points);
  EXPECT_TRUE(r.estimate->center.isApprox(ref.estimate->center));
}

TEST(Guards, TooWideAndTooNarrow) {
  const auto wide = estimate(place(box_top_and_side(0.10, 0.12, 0.05, 0.002, 0.0, 2), Placement()));
  ASSERT_TRUE(wide.estimate);
  EXPECT_FALSE(wide.estimate->width_ok);
  EXPECT_FALSE(wide.estimate->grasp_ok);
  EXPECT_TRUE(has_note(wide.estimate->notes, "width not graspable: 100.0 mm (5.0\u201380.0 mm)"))
      << wide.estimate->notes[0];

  const auto narrow = estimate(place(box_top_and_side(0.003, 0.06, 0.05, 0.001, 0.0, 2), Placement()));
  ASSERT_TRUE(narrow.estimate);
  EXPECT_FALSE(narrow.estimate->width_ok);
  EXPECT_TRUE(has_note(narrow.estimate->notes, "width not graspable: 3.0 mm"));

  // Just inside the limit: 79 mm is graspable.
  const auto edge = estimate(place(box_top_and_side(0.079, 0.09, 0.05, 0.001, 0.0, 2), Placement()));
  ASSERT_TRUE(edge.estimate);
  EXPECT_NEAR(edge.estimate->width_m, 0.079, 1e-9);
  EXPECT_TRUE(edge.estimate->width_ok);
}
