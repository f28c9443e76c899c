// method.md §1.4 — Euclidean clustering with extent filters (grasp_core::euclidean_clusters).
#include <gtest/gtest.h>

#include "grasp_core/clustering.hpp"
#include "synthetic_scene.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

using namespace grasp_core;
using grasp_test::SceneBuilder;

namespace {

constexpr double kEps = 0.015;
constexpr double kFast = 0.003;  // any value > 0 selects the grid path
constexpr double kExact = 0.0;   // per-point pcl::EuclideanClusterExtraction

ClusterResult run(const PointsF& pts, double voxel, int min_points = 20, double min_ext = 0.01,
                  double max_ext = 0.30) {
  return euclidean_clusters(pts, kEps, min_points, min_ext, max_ext, voxel);
}

/// Two labellings describe the same partition of the labelled (>= 0) points, and the same
/// points are unlabelled.
bool same_partition(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  std::map<int, int> ab, ba;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i] < 0) != (b[i] < 0)) return false;
    if (a[i] < 0) {
      if (a[i] != b[i]) return false;
      continue;
    }
    if (ab.emplace(a[i], b[i]).first->second != b[i]) return false;
    if (ba.emplace(b[i], a[i]).first->second != a[i]) return false;
  }
  return true;
}

/// Two 5 cm boxes whose nearest faces are `gap` apart along x, on a table at z = 0.2
/// (only the object points, i.e. already above the band).
PointsF two_boxes(double gap, std::uint32_t seed) {
  SceneBuilder b(seed);
  b.box(0.50, 0.0, 0.2, 0.05, 0.05, 0.05, 0.0, 0.002, 0.0005, 4, 0);
  b.box(0.55 + gap, 0.0, 0.2, 0.05, 0.05, 0.05, 0.0, 0.002, 0.0005, 4, 1);
  return b.points_f();
}

}  // namespace

TEST(Clustering, TwoObjectsTwelveCentimetresApartAreTwoClusters) {
  for (const double voxel : {kFast, kExact}) {
    const PointsF pts = two_boxes(0.12, 1);
    const auto r = run(pts, voxel);
    EXPECT_EQ(r.num_accepted, 2);
    std::set<int> left, right;
    for (Eigen::Index i = 0; i < pts.rows(); ++i) (pts(i, 0) < 0.55 ? left : right).insert(r.labels[i]);
    ASSERT_EQ(left.size(), 1u);
    ASSERT_EQ(right.size(), 1u);
    EXPECT_NE(*left.begin(), *right.begin());
    EXPECT_GE(*left.begin(), 0);
    EXPECT_GE(*right.begin(), 0);
  }
  // Closer than eps: one cluster.
  const auto joined = run(two_boxes(0.010, 2), kFast);
  EXPECT_EQ(joined.num_accepted, 1);
}

TEST(Clustering, TinyClusterBelowMinPointsIsNoise) {
  SceneBuilder b(3);
  b.box(0.5, 0.0, 0.2, 0.05, 0.05, 0.05, 0.0, 0.003, 0.0005, 2, 0);
  b.uniform_box(Vec3(0.70, 0.20, 0.25), Vec3(0.703, 0.203, 0.253), 12, 7);  // 12 < 20 points
  const PointsF pts = b.points_f();
  for (const double voxel : {kFast, kExact}) {
    const auto r = run(pts, voxel);
    EXPECT_EQ(r.num_accepted, 1);
    ASSERT_EQ(r.clusters.size(), 1u);  // the tiny component is not even a rejected cluster
    for (std::size_t i = 0; i < b.tags().size(); ++i)
      EXPECT_EQ(r.labels[i], b.tags()[i] == 7 ? kLabelEnvironment : 0);
    // With a lower min_points it becomes an object of its own: extent ~5 mm needs min_ext 0.
    const auto low = run(pts, voxel, 10, 0.0);
    EXPECT_EQ(low.num_accepted, 2);
  }
}

TEST(Clustering, MinPointsCountsOriginalPoints) {
  // 25 points packed into one 1 mm voxel-sized spot: 25 >= 20 original points.
  PointsF pts(25, 3);
  for (int i = 0; i < 25; ++i) pts.row(i) << 0.5f + 0.0001f * i, 0.0f, 0.3f + 0.0004f * i;
  for (const double voxel : {kFast, kExact}) {
    const auto r = run(pts, voxel, 20, 0.0);
    EXPECT_EQ(r.num_accepted, 1);
    ASSERT_EQ(r.clusters.size(), 1u);
    EXPECT_EQ(r.clusters[0].num_points, 25);
  }
}

TEST(Clustering, ExtentFilters) {
  SceneBuilder b(4);
  b.uniform_box(Vec3(0.30, 0.0, 0.25), Vec3(0.305, 0.005, 0.255), 200, 0);  // ~8.7 mm diagonal
  b.box(0.50, 0.0, 0.2, 0.05, 0.05, 0.05, 0.0, 0.003, 0.0005, 2, 1);         // a 5 cm object
  b.horizontal(0.60, 0.30, 0.25, 0.40, 0.05, 0.004, 0.0005, 0.0, 0.0, 2);    // a 40 cm board
  const PointsF pts = b.points_f();
  const auto tag_label = [&](const ClusterResult& r, int tag) {
    std::set<int> s;
    for (std::size_t i = 0; i < b.tags().size(); ++i)
      if (b.tags()[i] == tag) s.insert(r.labels[i]);
    return s;
  };
  for (const double voxel : {kFast, kExact}) {
    const auto r = run(pts, voxel);  // min 0.01, max 0.30
    EXPECT_EQ(r.num_accepted, 1);
    EXPECT_EQ(tag_label(r, 0), std::set<int>{kLabelEnvironment});  // too small
    EXPECT_EQ(tag_label(r, 1), std::set<int>{0});
    EXPECT_EQ(tag_label(r, 2), std::set<int>{kLabelEnvironment});  // too large
    ASSERT_EQ(r.clusters.size(), 3u);
    EXPECT_TRUE(r.clusters[0].accepted);
    EXPECT_FALSE(r.clusters[1].accepted);
    EXPECT_FALSE(r.clusters[2].accepted);
    EXPECT_EQ(r.clusters[1].label, kLabelEnvironment);
    EXPECT_GT(r.clusters[1].extent_m, 0.30);  // rejected ones: larger first
    EXPECT_LT(r.clusters[2].extent_m, 0.01);

    const auto no_max = run(pts, voxel, 20, 0.01, 0.0);  // max <= 0 disables the upper bound
    EXPECT_EQ(no_max.num_accepted, 2);
    EXPECT_EQ(tag_label(no_max, 2), std::set<int>{0});  // the board is the largest: label 0
    const auto no_min = run(pts, voxel, 20, 0.0, -1.0);
    EXPECT_EQ(no_min.num_accepted, 3);
  }
}

TEST(Clustering, EveryRowLabelledAndNonFiniteRowsInvalid) {
  SceneBuilder b(5);
  b.box(0.5, 0.0, 0.2, 0.05, 0.05, 0.05, 0.0, 0.003, 0.0005, 2, 0);
  b.invalid_rows(50);
  b.shuffle();
  const PointsF pts = b.points_f();
  for (const double voxel : {kFast, kExact}) {
    const auto r = run(pts, voxel);
    ASSERT_EQ(r.labels.size(), static_cast<std::size_t>(pts.rows()));
    for (std::size_t i = 0; i < r.labels.size(); ++i)
      EXPECT_EQ(r.labels[i], b.tags()[i] == grasp_test::kTagNaN ? kLabelInvalid : 0);
  }
}

TEST(Clustering, DegenerateInputs) {
  for (const double voxel : {kFast, kExact}) {
    EXPECT_TRUE(run(PointsF(0, 3), voxel).labels.empty());
    const auto nan = run(PointsF::Constant(10, 3, std::numeric_limits<float>::quiet_NaN()), voxel);
    EXPECT_EQ(nan.labels, std::vector<int>(10, kLabelInvalid));
    EXPECT_EQ(nan.num_components, 0);
    PointsF one(1, 3);
    one << 0.1f, 0.2f, 0.3f;
    const auto r1 = run(one, voxel, 1, 0.0);
    EXPECT_EQ(r1.labels, std::vector<int>{0});
    // Huge but finite coordinates are beyond the sane bound: dropped and counted.
    PointsF huge(3, 3);
    huge << 1e30f, 0, 0, -1e30f, 0, 0, 1e30f, 0.001f, 0;
    const auto rh = run(huge, voxel, 1, 0.0, 0.0);
    EXPECT_EQ(rh.num_components, 0);
    EXPECT_EQ(rh.num_invalid, 3);
    EXPECT_EQ(rh.num_out_of_range, 3);
    EXPECT_EQ(rh.labels, std::vector<int>(3, kLabelInvalid));
    // With the largest allowed bound they are still out (1e9 m), and in range ones cluster.
    const auto rb = euclidean_clusters(huge, kEps, 1, 0.0, 0.0, voxel, kMaxAbsCoordinateLimit_m);
    EXPECT_EQ(rb.num_out_of_range, 3);
  }
  EXPECT_THROW(euclidean_clusters(PointsF(PointsF::Zero(3, 3)), kEps, 1, 0, 0, 0, 0.0),
               std::invalid_argument);
  EXPECT_THROW(euclidean_clusters(PointsF(PointsF::Zero(3, 3)), 0.0, 1, 0, 0, 0), std::invalid_argument);
  float dummy[3] = {0, 0, 0};
  EXPECT_THROW(euclidean_clusters(dummy, 1, 2, kEps, 1, 0, 0, 0), std::invalid_argument);
  EXPECT_THROW(euclidean_clusters(nullptr, 1, 3, kEps, 1, 0, 0, 0), std::invalid_argument);
  EXPECT_NO_THROW(euclidean_clusters(nullptr, 0, 3, kEps, 1, 0, 0, 0));
}

// Regression: >= 16 identical rows near float max made FLANN's kd-tree split midpoint
// +inf and abort the process (kdtree_single_index.h: index > 0 && index < count).
TEST(Clustering, IdenticalRowsAtFloatMaxAreDroppedNotAborted) {
  const float big = std::numeric_limits<float>::max();
  PointsF pts(40, 3);
  for (Eigen::Index i = 0; i < 20; ++i) pts.row(i) << big, big, big;
  for (Eigen::Index i = 20; i < 40; ++i) pts.row(i) << 0.5f + 0.001f * static_cast<float>(i), 0.0f, 0.3f;
  for (const double voxel : {kFast, kExact}) {
    const auto r = run(pts, voxel, 5, 0.0, 0.0);
    EXPECT_EQ(r.num_out_of_range, 20);
    EXPECT_EQ(r.num_accepted, 1);
    for (Eigen::Index i = 0; i < 40; ++i)
      EXPECT_EQ(r.labels[static_cast<std::size_t>(i)], i < 20 ? kLabelInvalid : 0);
  }
  // Doubles beyond float range are out of range too (not turned into Inf first).
  PointsD d(2, 3);
  d << 1e300, 0, 0, 0, 0, 0;
  EXPECT_EQ(euclidean_clusters(d, kEps, 1, 0, 0, kExact).num_out_of_range, 1);
}

// Regression: the reference path ran PCL's radius search over every copy of a duplicated
// point (O(N^2): 100k identical rows took ~6 minutes). Duplicates are merged first.
TEST(Clustering, ManyIdenticalRowsAreFastOnBothPaths) {
  PointsF pts(100000, 3);
  for (Eigen::Index i = 0; i < pts.rows(); ++i) pts.row(i) << 0.5f, 0.0f, 0.3f;
  pts.row(0) << 0.505f, 0.0f, 0.3f;  // one distinct neighbour within eps
  for (const double voxel : {kFast, kExact}) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = run(pts, voxel, 20, 0.0, 0.0);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(s, 2.0) << "voxel " << voxel;
    EXPECT_EQ(r.num_accepted, 1);
    EXPECT_EQ(r.clusters.at(0).num_points, 100000);
  }
}

TEST(Clustering, StridedInput) {
  const PointsF pts = two_boxes(0.12, 6);
  std::vector<float> wide(static_cast<std::size_t>(pts.rows()) * 5, 99.0f);  // x y z + 2 extra
  for (Eigen::Index i = 0; i < pts.rows(); ++i)
    for (int a = 0; a < 3; ++a) wide[static_cast<std::size_t>(i) * 5 + a] = pts(i, a);
  const auto r = euclidean_clusters(wide.data(), static_cast<std::size_t>(pts.rows()), 5, kEps,
                                    20, 0.01, 0.3, kFast);
  EXPECT_EQ(r.labels, run(pts, kFast).labels);
}

TEST(Clustering, FastPathEqualsExactPclOnRealisticCloud) {
  // The object candidates of the reference tabletop (above the 1 cm band), plus clutter:
  // isolated outliers, a thin bridge of noise between two objects and small blobs.
  const auto scene = grasp_test::reference_tabletop(8, 0.002, 0.0015);
  std::vector<Vec3> cand;
  for (const auto& p : scene.points())
    if (std::isfinite(p.x()) && p.z() - 0.2 > 0.01) cand.push_back(p);
  SceneBuilder extra(9);
  extra.uniform_box(Vec3(0.30, -0.25, 0.21), Vec3(0.75, 0.25, 0.30), 300);   // sparse outliers
  extra.uniform_box(Vec3(0.485, -0.10, 0.215), Vec3(0.54, -0.095, 0.22), 40);  // a bridge
  extra.uniform_box(Vec3(0.40, 0.15, 0.22), Vec3(0.404, 0.154, 0.224), 30);    // a tiny blob
  for (const auto& p : extra.points()) cand.push_back(p);
  PointsF pts(static_cast<Eigen::Index>(cand.size()), 3);
  for (std::size_t i = 0; i < cand.size(); ++i) pts.row(static_cast<Eigen::Index>(i)) = cand[i].cast<float>().transpose();
  ASSERT_GT(pts.rows(), 5000);

  const auto fast = run(pts, kFast);
  const auto exact = run(pts, kExact);
  EXPECT_GE(fast.num_accepted, 3);
  EXPECT_EQ(fast.num_components, exact.num_components);
  EXPECT_EQ(fast.num_accepted, exact.num_accepted);
  EXPECT_EQ(fast.labels, exact.labels);  // labels are a deterministic function of the partition
  EXPECT_TRUE(same_partition(fast.labels, exact.labels));
  // Without min_points / extent filters every component is compared.
  const auto fast_all = run(pts, kFast, 1, 0.0, 0.0);
  const auto exact_all = run(pts, kExact, 1, 0.0, 0.0);
  EXPECT_EQ(fast_all.labels, exact_all.labels);
}

TEST(Clustering, FastPathEqualsExactNearThePercolationThreshold) {
  // Random points at a density where component sizes vary wildly, and chains of points spaced
  // just below and just above eps: the hardest case for any shortcut.
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> u(0.0f, 0.3f);
  PointsF pts(3000 + 40, 3);
  for (int i = 0; i < 3000; ++i) pts.row(i) << u(rng), u(rng), u(rng);
  for (int i = 0; i < 20; ++i) pts.row(3000 + i) << 0.5f + static_cast<float>(i) * 0.0149f, 0.5f, 0.5f;
  for (int i = 0; i < 20; ++i) pts.row(3020 + i) << 0.5f + static_cast<float>(i) * 0.0151f, 0.6f, 0.6f;
  const auto fast = run(pts, kFast, 1, 0.0, 0.0);
  const auto exact = run(pts, kExact, 1, 0.0, 0.0);
  EXPECT_GT(exact.num_components, 100);
  EXPECT_EQ(fast.num_components, exact.num_components);
  EXPECT_EQ(fast.labels, exact.labels);
  // The chain below eps is one component, the one above is 20 singletons.
  std::set<int> below, above;
  for (int i = 0; i < 20; ++i) {
    below.insert(fast.labels[3000 + i]);
    above.insert(fast.labels[3020 + i]);
  }
  EXPECT_EQ(below.size(), 1u);
  EXPECT_EQ(above.size(), 20u);
}
