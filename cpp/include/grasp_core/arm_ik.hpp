// Gauss-Newton refinement of arm joints to a flange pose on the exported chain (the C++ twin
// of the refinement loop of python/grasp_pipeline/motion/ik.py, PandaIK._refine_and_verify).
//
// Per seed q: up to `iterations` times, with the flange pose (R_f, p_f) and its 6x7
// geometric Jacobian J (column j: [z_j x (p_f - a_j); z_j], z_j the world axis of hinge j
// through its world anchor a_j) of the current q,
//   e = [p_T - p_f; rotvec(R_T R_f^T)]   (rotvec as scipy's Rotation.as_rotvec),
//   stop when |e_p| <= tol_m and |e_r| <= tol_rad, else q += J^T (J J^T + 1e-12 I)^-1 e.
// The result is kept when it is within the joint limits (± limit_eps_rad), clipped to them,
// and the clipped q reaches the target within accept_m / accept_rad (position norm, rotation
// angle atan2(|vee(R - R^T)|/2, (tr R - 1)/2) of R_T R^T, like poses.pose_error).
#pragma once

#include <array>

#include "grasp_core/robot_chain.hpp"

namespace grasp_core {

struct ArmIkParams {
  int iterations = 30;
  double tol_m = 1e-9, tol_rad = 1e-9;
  double accept_m = 1e-6, accept_rad = 1e-6;
  double limit_eps_rad = 1e-9;
  std::array<double, kArmJoints> q_min_rad{}, q_max_rad{};
};

/// 4x4 homogeneous target pose (row-major rotation + translation).
struct FlangePose {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();
};

class ArmIK {
 public:
  /// Throws std::invalid_argument for a flange body outside the chain, an arm joint not
  /// driving exactly one body, or bad parameters (iterations < 0, non-finite, q_min > q_max).
  ArmIK(RobotChain chain, int flange_body, ArmIkParams params);

  const ArmIkParams& params() const { return params_; }
  /// Flange pose for arm state q (7).
  FlangePose flange(const double* q) const;
  /// Refine `q` (7, in/out) towards T; true when kept (inside the limits and verified).
  bool refine(const FlangePose& T, double* q) const;

 private:
  void pose_and_jacobian(const double* q, FlangePose& f, Eigen::Matrix<double, 6, kArmJoints>& J) const;

  RobotChain chain_;
  int flange_ = 0;
  ArmIkParams params_;
  std::array<int, kArmJoints> joint_body_{};
};

/// Rotation vector of R (scipy's quaternion route: canonical w >= 0, 2 atan2(|v|, w) v/|v|).
Vec3 rotation_vector(const Mat3& R);
/// Rotation angle of R: atan2(|vee(R - R^T)| / 2, (tr R - 1) / 2).
double rotation_angle(const Mat3& R);

}  // namespace grasp_core
