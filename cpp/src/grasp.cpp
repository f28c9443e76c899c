// Grasp pose math and view quality (method.md §3). See grasp.hpp.
#include "grasp_core/grasp.hpp"

#include <cmath>
#include <limits>

namespace grasp_core {
namespace {

/// Unit normal of the plane (+z if the plane's normal is degenerate).
Vec3 unit_normal(const Plane& plane) {
  const double len = plane.n.norm();
  return (std::isfinite(len) && len > 0.0) ? Vec3(plane.n / len) : Vec3(Vec3::UnitZ());
}

}  // namespace

std::optional<Mat3> top_down_rotation(const Mat3& R_box, const Vec3& n) {
  const double n_len = n.norm();
  if (!std::isfinite(n_len) || !(n_len > 0.0) || !R_box.allFinite()) return std::nullopt;
  const Vec3 nn = n / n_len;
  const Vec3 closing = R_box.col(0);
  const Vec3 y = closing.cross(nn);
  const double y_len = y.norm();
  if (!(y_len >= kDegenerateNorm)) return std::nullopt;
  Mat3 R;
  R.col(0) = nn;
  R.col(1) = y / y_len;
  R.col(2) = R.col(0).cross(R.col(1));  // = closing when closing is perpendicular to n
  return R;
}

std::optional<BestGrasp> best_grasp_from_estimate(const ObjectEstimate& est, const Plane& plane) {
  const auto R = top_down_rotation(est.R_box, plane.n);
  if (!R) return std::nullopt;
  BestGrasp g;
  g.R = *R;
  g.R.col(0) = -g.R.col(0);  // approach axis points into the object
  g.R.col(2) = -g.R.col(2);  // keeps det +1
  g.position = est.center;
  g.width_m = est.width_m;
  g.score = 0.0;
  return g;
}

Pose camera_above_pose(const Vec3& object, const Plane& plane, const Pose& ready_camera_world) {
  const Vec3 n = unit_normal(plane);
  const Vec3 z_c = -n;
  const Vec3 x_ready = ready_camera_world.R.col(0);
  Vec3 x_c = x_ready - x_ready.dot(n) * n;
  const double x_len = x_c.norm();
  if (!(x_len >= kDegenerateNorm)) {
    Vec3 u, v;
    in_plane_basis(n, &u, &v);
    x_c = u;
  } else {
    x_c /= x_len;
  }
  Pose cam;
  cam.R.col(0) = x_c;
  cam.R.col(1) = z_c.cross(x_c);
  cam.R.col(2) = z_c;
  cam.t = Vec3(object.x(), object.y(), ready_camera_world.t.z());
  return cam;
}

Pose camera_above_flange_target(const Vec3& object, const Plane& plane,
                                const Pose& ready_camera_world, const Pose& camera_in_flange) {
  const Pose cam = camera_above_pose(object, plane, ready_camera_world);
  Pose flange;
  flange.R = cam.R * camera_in_flange.R.transpose();
  flange.t = cam.t - flange.R * camera_in_flange.t;
  return flange;
}

ViewAssessment assess_view(const Vec3& object, const Vec3& camera_position, const Vec3& n,
                           double nadir_angle_max_deg) {
  ViewAssessment out;
  const Vec3 ray = object - camera_position;
  const double n_len = n.norm();
  if (!(ray.norm() >= kCoincidentDistance_m) || !(n_len > 0.0) || !std::isfinite(n_len)) {
    out.quality = ViewQuality::OBLIQUE;
    out.angle_deg = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const Vec3 down = -n / n_len;
  // atan2 form: accurate near 0 where acos loses digits.
  out.angle_deg = std::atan2(ray.cross(down).norm(), ray.dot(down)) * 180.0 / M_PI;
  out.quality =
      (out.angle_deg <= nadir_angle_max_deg) ? ViewQuality::NADIR : ViewQuality::OBLIQUE;
  return out;
}

}  // namespace grasp_core
