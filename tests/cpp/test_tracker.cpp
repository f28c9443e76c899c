// method.md §4: gate, association, monotone quality, windows, retirement, two-pass prior.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "grasp_core/tracker.hpp"
#include "synthetic_objects.hpp"

using namespace grasp_core;
using namespace grasp_test;

namespace {

constexpr ViewQuality OBL = ViewQuality::OBLIQUE;
constexpr ViewQuality NAD = ViewQuality::NADIR;

const Track* find(const Tracker& t, int tid) {
  for (const auto& tr : t.tracks())
    if (tr.tid == tid) return &tr;
  return nullptr;
}

/// Noisy 5 cm cube top (1 mm grid, 2 mm noise) at (x, y) with a yaw.
PointsD cube_top_at(double x, double y, double yaw_rad, unsigned seed) {
  auto pts = rect_top(0.05, 0.05, 0.05, 0.001);
  add_z_noise(pts, 0.002, seed);
  Placement pl;
  pl.x_m = x;
  pl.y_m = y;
  pl.yaw_rad = yaw_rad;
  return place(pts, pl);
}

/// Footprint span of a horizontal-table cloud along theta (u = x, v = y).
double span_along(const PointsD& P, double theta_rad) {
  std::vector<double> a, b;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    a.push_back(P(i, 0));
    b.push_back(P(i, 1));
  }
  return extent_along(a, b, theta_rad);
}

}  // namespace

TEST(Tracker, GateFromMinPairwiseDistance) {
  const std::vector<Vec3> c = {Vec3(0, 0, 0), Vec3(0.12, 0, 0), Vec3(0, 0.2, 0)};
  const auto g = Tracker::gate_for(c, 0.5);
  ASSERT_TRUE(g);
  EXPECT_NEAR(*g, 0.06, 1e-12);
  EXPECT_FALSE(Tracker::gate_for({Vec3(1, 2, 3)}, 0.5));
  EXPECT_FALSE(Tracker::gate_for({}, 0.5));

  Tracker t{ObbParams{}};
  t.update({make_estimate(c[0]), make_estimate(c[1])}, {OBL, OBL}, 0.0);
  ASSERT_TRUE(t.last_gate());
  EXPECT_NEAR(*t.last_gate(), 0.06, 1e-12);
  t.update({make_estimate(c[0])}, {OBL}, 0.1);
  EXPECT_FALSE(t.last_gate());  // the last frame's gate is kept, here: none
}

TEST(Tracker, NoGateAssociatesEvenFarObservations) {
  Tracker t{ObbParams{}};
  EXPECT_EQ(t.update({make_estimate(Vec3(0.5, 0, 0.2))}, {OBL}, 0.0), std::vector<int>{0});
  EXPECT_EQ(t.update({make_estimate(Vec3(0.9, 0.3, 0.2))}, {OBL}, 0.1), std::vector<int>{0});
  EXPECT_EQ(t.tracks().size(), 1u);
}

TEST(Tracker, AssociationNearestFirstInObservationOrder) {
  Tracker t{ObbParams{}};
  const Vec3 A(0.5, 0, 0.2), B(0.6, 0, 0.2);
  EXPECT_EQ(t.update({make_estimate(A), make_estimate(B)}, {OBL, OBL}, 0.0),
            (std::vector<int>{0, 1}));
  // Observations in the other order, slightly moved: each goes to its nearest track.
  EXPECT_EQ(t.update({make_estimate(B + Vec3(0.002, 0, 0)), make_estimate(A - Vec3(0.002, 0, 0))},
                     {OBL, OBL}, 0.1),
            (std::vector<int>{1, 0}));
  EXPECT_EQ(t.tracks().size(), 2u);
}

TEST(Tracker, FarObservationStartsANewTrack) {
  Tracker t{ObbParams{}};
  const Vec3 A(0.5, 0, 0.2), B(0.6, 0, 0.2);
  t.update({make_estimate(A), make_estimate(B)}, {OBL, OBL}, 0.0);
  // C is 0.4 from B: gate = 0.5 * |A - C| = 0.25 -> new track 2.
  const Vec3 C(1.0, 0, 0.2);
  EXPECT_EQ(t.update({make_estimate(A), make_estimate(C)}, {OBL, NAD}, 0.1),
            (std::vector<int>{0, 2}));
  ASSERT_EQ(t.tracks().size(), 3u);
  EXPECT_EQ(find(t, 2)->quality, NAD);
}

TEST(Tracker, NewTrackIsUsedForTheRestOfTheFrame) {
  ObbParams p;
  p.assoc_gate_frac = 1.0;  // gate = min pairwise distance, so a new track could be matched
  Tracker t{p};
  t.update({make_estimate(Vec3(0, 0, 0))}, {OBL}, 0.0);
  const auto tids = t.update({make_estimate(Vec3(0, 0, 0)), make_estimate(Vec3(0.01, 0, 0)),
                              make_estimate(Vec3(0.012, 0, 0))},
                             {OBL, OBL, OBL}, 0.1);
  EXPECT_EQ(tids, (std::vector<int>{0, 1, 2}));  // obs 3 is 2 mm = gate from track 1: not reused
}

TEST(Tracker, QualityOnlyGoesUp) {
  Tracker t{ObbParams{}};
  const Vec3 c(0.5, 0, 0.225);
  t.update({make_estimate(c, 0.1, 0.05)}, {NAD}, 0.0);
  t.update({make_estimate(c + Vec3(0.004, 0, 0), 0.7, 0.07)}, {OBL}, 1.5);
  ASSERT_EQ(t.tracks().size(), 1u);
  const Track& tr = t.tracks()[0];
  EXPECT_EQ(tr.quality, NAD);
  EXPECT_DOUBLE_EQ(tr.last_seen_s, 1.5);  // refreshed
  EXPECT_DOUBLE_EQ(tr.smoothed.width_m, 0.05);  // not overwritten
  EXPECT_DOUBLE_EQ(tr.smoothed.theta_rad, 0.1);
  EXPECT_TRUE(tr.smoothed.center.isApprox(c));
  EXPECT_EQ(tr.window_size(), 1);
}

TEST(Tracker, WindowsRestartWhenQualityRises) {
  Tracker t{ObbParams{}};
  const Vec3 c(0.5, 0, 0.225);
  for (int i = 0; i < 3; ++i) t.update({make_estimate(c, 0.0, 0.06)}, {OBL}, 0.1 * i);
  EXPECT_EQ(t.tracks()[0].window_size(), 3);
  t.update({make_estimate(c, 0.0, 0.05)}, {NAD}, 0.4);
  EXPECT_EQ(t.tracks()[0].window_size(), 1);
  EXPECT_DOUBLE_EQ(t.tracks()[0].smoothed.width_m, 0.05);  // no oblique sample in the median
  t.update({make_estimate(c, 0.0, 0.052)}, {NAD}, 0.5);
  EXPECT_NEAR(t.tracks()[0].smoothed.width_m, 0.051, 1e-12);  // even count: mean of the two
}

TEST(Tracker, MediansOverAWindowOfLengthWindow) {
  ObbParams p;  // window 7
  Tracker t{p};
  for (int i = 0; i < 10; ++i) {
    const Vec3 c(0.5 + 0.001 * i, -0.001 * i, 0.2 + (i == 9 ? 0.5 : 0.0));
    t.update({make_estimate(c, 0.0, 0.040 + 0.001 * i, 0.06, 0.03, 1.2 + 0.01 * i)}, {OBL}, 0.1 * i);
  }
  const auto& s = t.tracks()[0].smoothed;
  EXPECT_EQ(t.tracks()[0].window_size(), p.window);
  EXPECT_NEAR(s.width_m, 0.046, 1e-12);  // samples 3..9 -> median 6
  EXPECT_NEAR(s.center.x(), 0.506, 1e-12);
  EXPECT_NEAR(s.center.y(), -0.006, 1e-12);
  EXPECT_NEAR(s.center.z(), 0.2, 1e-12);  // one outlier does not move the median
  EXPECT_NEAR(s.anisotropy, 1.26, 1e-12);
  EXPECT_TRUE(s.extents.isApprox(Vec3(s.width_m, s.perp_width_m, s.height_m)));
}

TEST(Tracker, ThetaMedianIsCircularModPi) {
  Tracker t{ObbParams{}};
  const Vec3 c(0.5, 0, 0.2);
  for (double deg : {179.0, 1.0, 2.0}) t.update({make_estimate(c, deg * kDeg)}, {OBL}, 0.0);
  const auto& s = t.tracks()[0].smoothed;
  EXPECT_NEAR(angle_dist_mod_pi(s.theta_rad, 1 * kDeg), 0.0, 1e-12);  // not ~60 deg
  EXPECT_TRUE(s.R_box.col(0).isApprox(Vec3(std::cos(s.theta_rad), std::sin(s.theta_rad), 0)));
  EXPECT_NEAR(s.R_box.determinant(), 1.0, 1e-12);
}

TEST(Tracker, GuardsRebuiltFromSmoothedValuesFrameFieldsKept) {
  Tracker t{ObbParams{}};
  const Vec3 c(0.5, 0, 0.2);
  t.update({make_estimate(c, 0.0, 0.09)}, {OBL}, 0.0);
  EXPECT_FALSE(t.tracks()[0].smoothed.width_ok);
  for (int i = 0; i < 2; ++i) t.update({make_estimate(c, 0.0, 0.05)}, {OBL}, 0.1);
  auto frame = make_estimate(c, 0.0, 0.09);  // this frame alone is too wide ...
  frame.resting = false;
  frame.resting_note = "floating/stacked: test";
  frame.pca_tilt_deg = 12.5;
  frame.num_points = 777;
  t.update({frame}, {OBL}, 0.2);
  const auto& s = t.tracks()[0].smoothed;
  EXPECT_NEAR(s.width_m, 0.07, 1e-12);  // median of 0.09, 0.05, 0.05, 0.09
  EXPECT_TRUE(s.width_ok);              // ... but the smoothed width is graspable
  EXPECT_FALSE(s.resting);              // from this frame
  EXPECT_FALSE(s.grasp_ok);
  EXPECT_EQ(s.notes, std::vector<std::string>{"floating/stacked: test"});
  EXPECT_DOUBLE_EQ(s.pca_tilt_deg, 12.5);
  EXPECT_EQ(s.num_points, 777);
}

TEST(Tracker, TwoLevelRetirement) {
  Tracker t{ObbParams{}};  // max_age 2 s, nadir_hold 10 s
  t.update({make_estimate(Vec3(0.5, 0, 0.2)), make_estimate(Vec3(0.7, 0, 0.2))}, {OBL, NAD}, 0.0);
  t.retire(2.0);
  EXPECT_EQ(t.tracks().size(), 2u);  // age 2.0 is not > 2.0
  t.retire(2.01);
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].tid, 1);  // the NADIR track is held
  t.retire(10.0);
  EXPECT_EQ(t.tracks().size(), 1u);
  t.retire(10.01);
  EXPECT_TRUE(t.tracks().empty());
}

TEST(Tracker, TidsSortedAndNeverReused) {
  Tracker t{ObbParams{}};
  t.update({make_estimate(Vec3(0.5, 0, 0.2))}, {OBL}, 0.0);
  t.retire(5.0);
  ASSERT_TRUE(t.tracks().empty());
  EXPECT_EQ(t.update({make_estimate(Vec3(0.5, 0, 0.2))}, {OBL}, 5.0), std::vector<int>{1});
  t.update({make_estimate(Vec3(0.5, 0, 0.2)), make_estimate(Vec3(0.3, 0, 0.2)),
            make_estimate(Vec3(0.8, 0, 0.2))},
           {OBL, OBL, OBL}, 5.1);
  std::vector<int> tids;
  for (const auto& tr : t.tracks()) tids.push_back(tr.tid);
  EXPECT_EQ(tids, (std::vector<int>{1, 2, 3}));
  t.reset();
  EXPECT_TRUE(t.tracks().empty());
  EXPECT_FALSE(t.last_gate());
  EXPECT_EQ(t.update({make_estimate(Vec3(0.5, 0, 0.2))}, {OBL}, 6.0), std::vector<int>{4});
}

TEST(Tracker, PriorThetaWithinGate) {
  Tracker t{ObbParams{}};
  EXPECT_FALSE(t.prior_theta(Vec3::Zero(), std::nullopt));  // no tracks
  t.update({make_estimate(Vec3(0.5, 0, 0.2), 0.3), make_estimate(Vec3(0.7, 0, 0.2), 1.2)},
           {OBL, OBL}, 0.0);
  EXPECT_NEAR(*t.prior_theta(Vec3(0.51, 0, 0.2), 0.05), 0.3, 1e-12);
  EXPECT_NEAR(*t.prior_theta(Vec3(0.68, 0, 0.2), std::nullopt), 1.2, 1e-12);
  EXPECT_FALSE(t.prior_theta(Vec3(0.6, 0.2, 0.2), 0.05));  // nearest is outside the gate
  EXPECT_TRUE(t.prior_theta(Vec3(0.6, 0.2, 0.2), std::nullopt));
}

TEST(TwoPass, NewObjectDoesNotBorrowANeighboursTheta) {
  const ObbParams p;
  const Plane plane = table_plane(Placement());
  Tracker t{p};
  // Track A (cube at yaw 20 deg) closed along its 110 deg run.
  const PointsD A = cube_top_at(0.5, 0.0, 20 * kDeg, 1);
  const auto a0 = estimate_object(A, plane, p, 110 * kDeg, 0.01);
  ASSERT_TRUE(a0.estimate);
  ASSERT_NEAR(a0.estimate->theta_rad, 110 * kDeg, 0.6 * kDeg);
  t.update({*a0.estimate}, {OBL}, 0.0);
  // Next frame: A again and a new cube B 0.2 m away (gate = 0.1 m).
  const PointsD B = cube_top_at(0.5, 0.2, 20 * kDeg, 2);
  const auto res = estimate_with_priors({A, B, PointsD(0, 3)}, plane, p, t, 0.01);
  ASSERT_EQ(res.size(), 3u);
  ASSERT_TRUE(res[0].estimate && res[1].estimate);
  EXPECT_NEAR(res[0].estimate->theta_rad, 110 * kDeg, 0.6 * kDeg);  // A keeps its prior
  EXPECT_NEAR(res[1].estimate->theta_rad, 20 * kDeg, 0.6 * kDeg);   // B: no prior
  EXPECT_FALSE(res[2].estimate);
  EXPECT_FALSE(res[2].failure.empty());
}

/// method.md §4's flip: a square whose first-pass theta alternates between its two runs.
/// Yaw +1 deg -> runs {1, 91} -> 1 deg; yaw -1 deg -> runs {179, 89} -> 89 deg.
TEST(TwoPass, AlternatingSquareKeepsTheTrueSideNotTheDiagonal) {
  const ObbParams p;
  const Plane plane = table_plane(Placement());
  const int frames = 12;
  auto cloud = [](int k) { return cube_top_at(0.5, 0.0, (k % 2 == 0 ? 1.0 : -1.0) * kDeg, 100 + k); };

  // Naive "smooth first": no prior, the tracker median mixes theta and theta + 90.
  Tracker naive{p};
  double naive_worst = 0.0;
  for (int k = 0; k < frames; ++k) {
    const PointsD P = cloud(k);
    const auto r = estimate_object(P, plane, p, std::nullopt, 0.01);
    ASSERT_TRUE(r.estimate);
    naive.update({*r.estimate}, {OBL}, 0.1 * k);
    naive_worst = std::max(naive_worst, span_along(P, naive.tracks()[0].smoothed.theta_rad));
  }
  EXPECT_GT(naive_worst, 0.05 * 1.35);  // the 45 deg diagonal (+41 %)

  // Two-pass: the prior keeps every frame on the same run.
  Tracker t{p};
  double worst = 0.0;
  for (int k = 0; k < frames; ++k) {
    const PointsD P = cloud(k);
    const auto res = estimate_with_priors({P}, plane, p, t, 0.01);
    ASSERT_TRUE(res[0].estimate);
    t.update({*res[0].estimate}, {OBL}, 0.1 * k);
    ASSERT_EQ(t.tracks().size(), 1u);
    const auto& s = t.tracks()[0].smoothed;
    EXPECT_NEAR(s.width_m, 0.05, 0.002) << "frame " << k;
    worst = std::max(worst, span_along(P, s.theta_rad));
  }
  EXPECT_LT(worst, 0.05 * 1.05);
}
