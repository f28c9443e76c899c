// A small spatial arm for the state-checker tests (header-only): a base column and four
// hinged links turned by 90 degrees about x like a Panda's, then a tool turned by 45 degrees
// about z (a fixed rotation with two terms per column), spheres off the joint axes, every
// sphere pair of non-adjacent bodies checked (links 3 and 5 with enough spheres for a fine
// joint-space table between them). Also an independent forward kinematics
// (Eigen rotations, no shared code with RobotChain) and the sphere-by-sphere self test.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <vector>

#include "grasp_core/robot_collision.hpp"

namespace grasp_test {

using grasp_core::kArmJoints;
using grasp_core::Mat3;
using grasp_core::RobotCollisionSpec;
using grasp_core::Vec3;

/// Rotation of `deg` degrees about the axis (x, y, z).
inline Mat3 turn(double deg, double x, double y, double z) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, Vec3(x, y, z).normalized()).toRotationMatrix();
}

/// Exactly 90 degrees about x (sign +1) or -90 degrees: entries 0 and +-1 only.
inline Mat3 quarter_x(int sign) {
  Mat3 m;
  m << 1, 0, 0, 0, 0, -sign, 0, sign, 0;
  return m;
}

/// Bodies: 0 world, 1 base (fixed), 2..5 hinged links (joints 0..3), 6 tool (fixed on 5).
/// Fixed rotations: exact quarter turns (bodies 3, 5), a rounded one (body 4, every entry
/// non-zero) and 45 degrees about z (body 6).
inline RobotCollisionSpec spatial_arm_spec(double self_margin_m = 0.0) {
  RobotCollisionSpec s;
  s.bodies.resize(7);
  s.bodies[1].p = Vec3(0, 0, 0.3);
  s.bodies[2].parent = 1; s.bodies[2].p = Vec3(0, 0, 0.25); s.bodies[2].joint = 0;
  s.bodies[3].parent = 2; s.bodies[3].R = quarter_x(-1); s.bodies[3].joint = 1;
  s.bodies[4].parent = 3; s.bodies[4].R = turn(90, 1, 0, 0); s.bodies[4].p = Vec3(0.01, -0.3, 0.02); s.bodies[4].joint = 2;
  s.bodies[5].parent = 4; s.bodies[5].R = quarter_x(1); s.bodies[5].p = Vec3(0.06, 0, 0.05); s.bodies[5].joint = 3;
  s.bodies[5].axis = Vec3(0, 0, -1);  // a hinge turning the other way
  s.bodies[6].parent = 5; s.bodies[6].R = turn(45, 0, 0, 1); s.bodies[6].p = Vec3(0, 0.12, 0);
  auto add = [&](int body, Vec3 c, double r, bool hand) {
    s.sphere_body.push_back(body); s.sphere_center.push_back(c); s.sphere_radius.push_back(r);
    s.sphere_geom.push_back(body); s.env_sphere.push_back(body >= 2); s.hand_sphere.push_back(hand);
  };
  for (int k = 0; k < 4; ++k) add(1, Vec3(0.03 * std::cos(k * 1.6), 0.03 * std::sin(k * 1.6), -0.1 * k), 0.08, false);
  for (int k = 0; k < 3; ++k) add(2, Vec3(0.02, 0.01 * k, -0.08 + 0.05 * k), 0.06, false);
  for (int k = 0; k < 8; ++k) add(3, Vec3(0.01, -0.025 * k, 0.02 * (k % 3)), 0.05, false);
  for (int k = 0; k < 4; ++k) add(4, Vec3(0.03, 0.0, -0.05 + 0.04 * k), 0.05, false);
  for (int k = 0; k < 8; ++k) add(5, Vec3(0.01 * (k % 2), 0.07 + 0.025 * k, 0.02 * (k % 2)), 0.04, k >= 5);
  for (int k = 0; k < 4; ++k) add(6, Vec3(0.04 * (k % 2) - 0.02, 0.03 * (k / 2), 0.05), 0.03, true);
  for (std::size_t i = 0; i < s.sphere_body.size(); ++i)
    for (std::size_t j = i + 1; j < s.sphere_body.size(); ++j) {
      const int bi = s.sphere_body[i], bj = s.sphere_body[j];
      const bool adjacent = bj == bi + 1 || (bi == 5 && bj == 6) || bi == bj;
      if (!adjacent) s.pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  const double lim[kArmJoints] = {2.9, 1.8, 2.9, 3.0, 0, 0, 0};
  for (int j = 0; j < kArmJoints; ++j) { s.q_min_rad[j] = -lim[j]; s.q_max_rad[j] = lim[j]; }
  s.q_min_rad[3] = -0.1;  // an asymmetric range
  s.self_margin_m = self_margin_m;
  return s;
}

/// World rotation and position of every body: R_b = R_parent R_fixed Rot(axis, q - q0),
/// p_b = p_parent + R_parent p_fixed (every hinge here turns about its body's origin).
inline void reference_poses(const RobotCollisionSpec& s, const double* q, std::vector<Mat3>& R, std::vector<Vec3>& p) {
  R.assign(s.bodies.size(), Mat3::Identity());
  p.assign(s.bodies.size(), Vec3::Zero());
  for (std::size_t b = 1; b < s.bodies.size(); ++b) {
    const auto& c = s.bodies[b];
    const auto par = static_cast<std::size_t>(c.parent);
    Mat3 Rb = R[par] * c.R;
    if (c.joint >= 0) Rb = Rb * Eigen::AngleAxisd(q[c.joint] - c.q0_rad, c.axis.normalized()).toRotationMatrix();
    R[b] = Rb;
    p[b] = p[par] + R[par] * c.p;
  }
}

inline std::vector<Vec3> reference_centres(const RobotCollisionSpec& s, const double* q) {
  std::vector<Mat3> R;
  std::vector<Vec3> p;
  reference_poses(s, q, R, p);
  std::vector<Vec3> c;
  for (std::size_t i = 0; i < s.sphere_radius.size(); ++i) {
    const auto b = static_cast<std::size_t>(s.sphere_body[i]);
    c.push_back(p[b] + R[b] * s.sphere_center[i]);
  }
  return c;
}

/// Smallest clearance minus margin over the listed pairs whose spheres lie on bodies
/// (ba, bb) (either order); every listed pair when ba < 0.
inline double reference_self_clearance(const RobotCollisionSpec& s, const std::vector<Vec3>& c, int ba = -1, int bb = -1) {
  double best = 1e300;
  for (const auto& [i, j] : s.pairs) {
    const int x = s.sphere_body[static_cast<std::size_t>(i)], y = s.sphere_body[static_cast<std::size_t>(j)];
    if (ba >= 0 && !((x == ba && y == bb) || (x == bb && y == ba))) continue;
    const double d = (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(j)]).norm() -
                     (s.sphere_radius[static_cast<std::size_t>(i)] + s.sphere_radius[static_cast<std::size_t>(j)]) - s.self_margin_m;
    best = std::min(best, d);
  }
  return best;
}

}  // namespace grasp_test
