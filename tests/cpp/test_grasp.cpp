// method.md §3: top-down grasp, BestGrasp convention, camera-above target, view quality.
#include <gtest/gtest.h>

#include <cmath>

#include "grasp_core/grasp.hpp"
#include "synthetic_objects.hpp"

using namespace grasp_core;
using namespace grasp_test;

namespace {

Mat3 rot(double angle_rad, const Vec3& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

Placement tilted_placement() {
  Placement pl;
  pl.table_tilt = rot(4 * kDeg, Vec3(1, -2, 0));
  pl.yaw_rad = 35 * kDeg;
  pl.x_m = 0.56;
  pl.y_m = -0.03;
  return pl;
}

}  // namespace

TEST(Grasp, TopDownRotationColumnsAndDet) {
  const Vec3 n = Vec3(0.05, -0.02, 1).normalized();
  Vec3 u, v;
  in_plane_basis(n, &u, &v);
  Mat3 R_box;
  R_box << u, v, n;
  const auto R = top_down_rotation(R_box, n);
  ASSERT_TRUE(R);
  EXPECT_NEAR(R->determinant(), 1.0, 1e-12);
  EXPECT_TRUE(R->col(0).isApprox(n, 1e-12));
  EXPECT_TRUE(R->col(1).isApprox(u.cross(n).normalized(), 1e-12));
  EXPECT_TRUE(R->col(2).isApprox(u, 1e-12));  // closing = R_box[:,0]
}

TEST(Grasp, TopDownRotationFailsWhenClosingParallelToNormal) {
  Mat3 R_box = Mat3::Identity();
  R_box.col(0) = Vec3::UnitZ();
  EXPECT_FALSE(top_down_rotation(R_box, Vec3::UnitZ()));
  EXPECT_FALSE(top_down_rotation(Mat3::Identity(), Vec3::Zero()));
}

TEST(Grasp, BestGraspConvention) {
  const Placement pl = tilted_placement();
  const Plane plane = table_plane(pl);
  const auto r = estimate_object(place(box_top_and_side(0.03, 0.06, 0.05, 0.001, 0.0, 4), pl),
                                 plane, ObbParams{}, std::nullopt, 0.01);
  ASSERT_TRUE(r.estimate) << r.failure;
  const auto g = best_grasp_from_estimate(*r.estimate, plane);
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->R.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(g->R.col(0).isApprox(-plane.n, 1e-12));  // approach points into the object
  EXPECT_NEAR(std::abs(g->R.col(2).dot(r.estimate->R_box.col(0))), 1.0, 1e-12);
  EXPECT_TRUE(g->position.isApprox(r.estimate->center));
  EXPECT_DOUBLE_EQ(g->width_m, r.estimate->width_m);
  EXPECT_NEAR(g->width_m, 0.03, 1e-3);
  EXPECT_EQ(g->score, 0.0);
  // The approach axis points from above the object down through its centre.
  const Vec3 above = g->position + 0.1 * plane.n;
  EXPECT_GT((g->position - above).dot(g->R.col(0)), 0.0);
}

TEST(CameraAbove, OpticalAxisDownAtReadyHeightAndFlangeRecoversCamera) {
  const Placement pl = tilted_placement();
  const Plane plane = table_plane(pl);
  Pose ready;  // a start-up camera looking obliquely down
  ready.R = rot(150 * kDeg, Vec3(1, 0.3, 0)) * rot(20 * kDeg, Vec3::UnitZ());
  ready.t = Vec3(0.3, 0.05, 0.62);
  Pose cam_in_flange;  // from the robot model: offset and rotated camera mount
  cam_in_flange.R = rot(-45 * kDeg, Vec3::UnitZ()) * rot(3 * kDeg, Vec3::UnitX());
  cam_in_flange.t = Vec3(0.05, -0.02, 0.04);
  const Vec3 object(0.56, -0.03, 0.225);

  const Pose cam = camera_above_pose(object, plane, ready);
  EXPECT_TRUE(cam.R.col(2).isApprox(-plane.n, 1e-12));
  EXPECT_NEAR(cam.R.determinant(), 1.0, 1e-12);
  EXPECT_TRUE((cam.R.transpose() * cam.R).isApprox(Mat3::Identity(), 1e-12));
  EXPECT_NEAR(cam.t.x(), object.x(), 1e-12);
  EXPECT_NEAR(cam.t.y(), object.y(), 1e-12);
  EXPECT_NEAR(cam.t.z(), ready.t.z(), 1e-12);
  // x_c is the ready camera x projected into the plane.
  const Vec3 xr = ready.R.col(0);
  EXPECT_TRUE(cam.R.col(0).isApprox((xr - xr.dot(plane.n) * plane.n).normalized(), 1e-12));

  const Pose flange = camera_above_flange_target(object, plane, ready, cam_in_flange);
  // Composing the flange pose with the camera-in-flange pose gives the camera pose.
  EXPECT_TRUE((flange.R * cam_in_flange.R).isApprox(cam.R, 1e-12));
  EXPECT_TRUE((flange.R * cam_in_flange.t + flange.t).isApprox(cam.t, 1e-12));
  EXPECT_NEAR(flange.R.determinant(), 1.0, 1e-12);
  // The mount matters: a different camera_in_flange gives a different flange target.
  Pose other = cam_in_flange;
  other.t.x() += 0.01;
  EXPECT_GT((camera_above_flange_target(object, plane, ready, other).t - flange.t).norm(), 5e-3);
}

TEST(CameraAbove, FallbackToUWhenReadyXIsParallelToNormal) {
  const Plane plane;  // n = +z
  Pose ready;
  ready.R = rot(-90 * kDeg, Vec3::UnitY());  // camera x = +z
  ASSERT_TRUE(ready.R.col(0).isApprox(Vec3::UnitZ(), 1e-12));
  ready.t = Vec3(0.3, 0.0, 0.6);
  const Pose cam = camera_above_pose(Vec3(0.5, 0.1, 0.22), plane, ready);
  Vec3 u, v;
  in_plane_basis(plane.n, &u, &v);
  EXPECT_TRUE(cam.R.col(0).isApprox(u, 1e-12));
  EXPECT_TRUE(cam.R.col(2).isApprox(-Vec3::UnitZ(), 1e-12));
  EXPECT_NEAR(cam.R.determinant(), 1.0, 1e-12);
}

TEST(ViewQuality, NadirAboveObliqueAtTenDegreesAndCoincident) {
  const Vec3 n = Vec3::UnitZ();
  const Vec3 object(0.5, 0.0, 0.22);
  const double max_deg = ObbParams{}.nadir_angle_max_deg;

  const auto above = assess_view(object, object + 0.39 * n, n, max_deg);
  EXPECT_EQ(above.quality, ViewQuality::NADIR);
  EXPECT_NEAR(above.angle_deg, 0.0, 1e-9);

  const Vec3 ten = object + 0.39 * (rot(10 * kDeg, Vec3::UnitX()) * n);
  const auto oblique = assess_view(object, ten, n, max_deg);
  EXPECT_EQ(oblique.quality, ViewQuality::OBLIQUE);
  EXPECT_NEAR(oblique.angle_deg, 10.0, 1e-9);

  const Vec3 four = object + 0.39 * (rot(4 * kDeg, Vec3(1, 1, 0)) * n);
  EXPECT_EQ(assess_view(object, four, n, max_deg).quality, ViewQuality::NADIR);

  const auto same = assess_view(object, object, n, max_deg);
  EXPECT_EQ(same.quality, ViewQuality::OBLIQUE);
  EXPECT_TRUE(std::isnan(same.angle_deg));

  // A camera below the plane looking up is as far from nadir as it gets.
  EXPECT_NEAR(assess_view(object, object - 0.3 * n, n, max_deg).angle_deg, 180.0, 1e-9);
}
