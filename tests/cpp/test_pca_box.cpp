// method.md §2.5: PCA OBB (diagnostic) and its failure rules.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "grasp_core/pca_box.hpp"
#include "synthetic_objects.hpp"

using namespace grasp_core;
using namespace grasp_test;

namespace {

PointsD rows(const std::vector<Vec3>& v) {
  PointsD p(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) p.row(static_cast<Eigen::Index>(i)) = v[i];
  return p;
}

}  // namespace

TEST(PcaBox, FewerThanThreePointsFails) {
  std::string why;
  EXPECT_FALSE(pca_box(PointsD(0, 3), &why));
  EXPECT_NE(why.find("fewer than 3"), std::string::npos) << why;
  EXPECT_FALSE(pca_box(rows({Vec3(0, 0, 0), Vec3(1, 2, 3)}), &why));
}

TEST(PcaBox, CoincidentPointsFail) {
  std::string why;
  EXPECT_FALSE(pca_box(rows({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}), &why));
  EXPECT_NE(why.find("coincide"), std::string::npos) << why;
}

TEST(PcaBox, CollinearPointsFail) {
  std::vector<Vec3> line;
  for (int i = 0; i < 50; ++i) line.emplace_back(0.3 + 0.01 * i, -0.2 + 0.005 * i, 0.2 + 0.002 * i);
  std::string why;
  EXPECT_FALSE(pca_box(rows(line), &why));
  EXPECT_NE(why.find("collinear"), std::string::npos) << why;
}

TEST(PcaBox, NonFiniteCovarianceFails) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::string why;
  EXPECT_FALSE(pca_box(rows({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(nan, 0, 0)}), &why));
  EXPECT_NE(why.find("non-finite"), std::string::npos) << why;
}

TEST(PcaBox, CoplanarTopFaceIsValidAndTiltZero) {
  Placement pl;
  const PointsD top = place(rect_top(0.08, 0.05, 0.05, 0.002), pl);
  const auto box = pca_box(top);
  ASSERT_TRUE(box);
  EXPECT_NEAR(box->R.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(box->R.col(2).z()), 1.0, 1e-9);  // minor axis = normal
  EXPECT_NEAR(pca_tilt_deg(*box, Vec3::UnitZ()), 0.0, 1e-3);
  EXPECT_NEAR(box->extents(0), 0.08, 1e-9);
  EXPECT_NEAR(box->extents(1), 0.05, 1e-9);
  EXPECT_NEAR(box->extents(2), 0.0, 1e-9);
}

TEST(PcaBox, EigenvaluesDescendingAndDetPlusOne) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Vec3> pts;
    const Vec3 scale(1.0 + trial % 3, 0.5 + (trial % 5) * 0.3, 0.2 + (trial % 7) * 0.1);
    for (int i = 0; i < 40; ++i) pts.emplace_back(scale.cwiseProduct(Vec3(g(rng), g(rng), g(rng))));
    const auto box = pca_box(rows(pts));
    ASSERT_TRUE(box);
    EXPECT_NEAR(box->R.determinant(), 1.0, 1e-9) << "trial " << trial;
    EXPECT_TRUE((box->R.transpose() * box->R).isApprox(Mat3::Identity(), 1e-9));
    EXPECT_GE(box->eigenvalues(0), box->eigenvalues(1));
    EXPECT_GE(box->eigenvalues(1), box->eigenvalues(2));
  }
}

TEST(PcaBox, CovarianceUsesNMinusOne) {
  // x in {-1, 1} (+ a little y, z so it is not collinear): var with N-1 = 4/3 for 3 points?
  // Use 4 points: x = -1, -1, 1, 1 -> sum sq = 4 -> N-1 gives 4/3, N gives 1.
  const auto box = pca_box(rows({Vec3(-1, -0.1, 0), Vec3(-1, 0.1, 0), Vec3(1, -0.1, 0), Vec3(1, 0.1, 0)}));
  ASSERT_TRUE(box);
  EXPECT_NEAR(box->eigenvalues(0), 4.0 / 3.0, 1e-12);
}

TEST(PcaBox, CentreIsBoxMidpointNotCentroid) {
  // Asymmetric: 100 points near x = 0, 5 points near x = 1 (y, z spread so not collinear).
  std::vector<Vec3> pts;
  for (int i = 0; i < 100; ++i) pts.emplace_back(0.0, 0.01 * (i % 10), 0.001 * (i / 10));
  for (int i = 0; i < 5; ++i) pts.emplace_back(1.0, 0.02 * i, 0.0);
  const PointsD P = rows(pts);
  const auto box = pca_box(P);
  ASSERT_TRUE(box);
  const Vec3 centroid = P.colwise().mean().transpose();
  EXPECT_NEAR(centroid.x(), 5.0 / 105.0, 1e-12);
  EXPECT_NEAR(box->center.x(), 0.5, 1e-3);  // the box midpoint (axis slightly off x)
  EXPECT_GT((box->center - centroid).norm(), 0.4);
}

TEST(PcaBox, TiltLargeForObliquelySeenBox) {
  Placement pl;
  pl.yaw_rad = 0.3;
  const PointsD pts = place(box_top_and_side(0.05, 0.05, 0.05, 0.002, 0.0, 1), pl);
  const auto box = pca_box(pts);
  ASSERT_TRUE(box);
  EXPECT_GT(pca_tilt_deg(*box, Vec3::UnitZ()), 10.0);
  // The same box seen from above (top only) has tilt 0.
  const auto top = pca_box(place(rect_top(0.05, 0.05, 0.05, 0.002), pl));
  ASSERT_TRUE(top);
  EXPECT_NEAR(pca_tilt_deg(*top, Vec3::UnitZ()), 0.0, 1e-3);
}

TEST(PcaBox, TiltUsesAbsoluteDot) {
  PcaBox b;
  b.R.col(2) = -Vec3::UnitZ();
  EXPECT_NEAR(pca_tilt_deg(b, Vec3::UnitZ()), 0.0, 1e-9);
  EXPECT_TRUE(std::isnan(pca_tilt_deg(b, Vec3::Zero())));
}
