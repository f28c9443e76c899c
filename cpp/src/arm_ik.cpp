#include "grasp_core/arm_ik.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grasp_core {

namespace {
/// Regularisation of J J^T in the Newton step (as numpy: J J^T + 1e-12 I).
constexpr double kNewtonRegularisation = 1e-12;
/// Bodies up to the flange the fixed-size pose buffers hold.
constexpr int kMaxBodies = 64;
}  // namespace

Vec3 rotation_vector(const Mat3& R) {
  // quaternion (x, y, z, w) by the largest-pivot rule, then normalised
  const double tr = R(0, 0) + R(1, 1) + R(2, 2);
  double q[4];
  int choice = 3;
  double best = tr;
  for (int i = 0; i < 3; ++i)
    if (R(i, i) > best) { best = R(i, i); choice = i; }
  if (choice == 3) {
    q[0] = R(2, 1) - R(1, 2);
    q[1] = R(0, 2) - R(2, 0);
    q[2] = R(1, 0) - R(0, 1);
    q[3] = 1.0 + tr;
  } else {
    const int i = choice, j = (i + 1) % 3, k = (j + 1) % 3;
    q[i] = 1.0 - tr + 2.0 * R(i, i);
    q[j] = R(j, i) + R(i, j);
    q[k] = R(k, i) + R(i, k);
    q[3] = R(k, j) - R(j, k);
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& v : q) v /= n;
  if (q[3] < 0.0)
    for (double& v : q) v = -v;
  const double vn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const double angle = 2.0 * std::atan2(vn, q[3]);
  const double scale = angle <= 1e-3 ? 2.0 + angle * angle / 12.0 + 7.0 * std::pow(angle, 4) / 2880.0
                                     : angle / std::sin(angle / 2.0);
  return Vec3(scale * q[0], scale * q[1], scale * q[2]);
}

double rotation_angle(const Mat3& R) {
  const double a = R(2, 1) - R(1, 2), b = R(0, 2) - R(2, 0), c = R(1, 0) - R(0, 1);
  const double s = 0.5 * std::sqrt(a * a + b * b + c * c);
  const double co = 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0);
  return std::atan2(s, co);
}

ArmIK::ArmIK(RobotChain chain, int flange_body, ArmIkParams params)
    : chain_(std::move(chain)), flange_(flange_body), params_(params) {
  if (flange_ <= 0 || flange_ >= chain_.num_bodies())
    throw std::invalid_argument("arm IK: flange body index out of range");
  if (flange_ >= kMaxBodies) throw std::invalid_argument("arm IK: more than 64 bodies before the flange");
  joint_body_.fill(-1);
  for (int b = 0; b < chain_.num_bodies(); ++b) {
    const int j = chain_.body(b).joint;
    if (j < 0) continue;
    if (joint_body_[static_cast<std::size_t>(j)] >= 0)
      throw std::invalid_argument("arm IK: arm joint " + std::to_string(j + 1) + " drives two bodies");
    joint_body_[static_cast<std::size_t>(j)] = b;
  }
  for (int j = 0; j < kArmJoints; ++j)
    if (joint_body_[static_cast<std::size_t>(j)] < 0 || joint_body_[static_cast<std::size_t>(j)] > flange_)
      throw std::invalid_argument("arm IK: arm joint " + std::to_string(j + 1) + " is not on the flange's chain");
  const ArmIkParams& p = params_;
  if (p.iterations < 0) throw std::invalid_argument("arm IK: iterations must be >= 0");
  if (!std::isfinite(p.tol_m) || !std::isfinite(p.tol_rad) || !std::isfinite(p.accept_m) ||
      !std::isfinite(p.accept_rad) || !std::isfinite(p.limit_eps_rad))
    throw std::invalid_argument("arm IK: tolerances must be finite");
  for (int j = 0; j < kArmJoints; ++j)
    if (!std::isfinite(p.q_min_rad[j]) || !std::isfinite(p.q_max_rad[j]) || p.q_min_rad[j] > p.q_max_rad[j])
      throw std::invalid_argument("arm IK: joint limits must be finite with q_min <= q_max");
}

FlangePose ArmIK::flange(const double* q) const {
  Mat3 Rs[kMaxBodies];
  Vec3 ps[kMaxBodies];
  chain_.poses(q, Rs, ps, flange_ + 1);
  return FlangePose{Rs[flange_], ps[flange_]};
}

void ArmIK::pose_and_jacobian(const double* q, FlangePose& f, Eigen::Matrix<double, 6, kArmJoints>& J) const {
  Mat3 Rs[kMaxBodies];
  Vec3 ps[kMaxBodies];
  chain_.poses(q, Rs, ps, flange_ + 1);
  f.R = Rs[flange_];
  f.p = ps[flange_];
  for (int j = 0; j < kArmJoints; ++j) {
    const int b = joint_body_[static_cast<std::size_t>(j)];
    const ChainBody& c = chain_.body(b);
    const Vec3 z = Rs[b] * c.axis;
    const Vec3 a = ps[b] + Rs[b] * c.anchor;
    J.block<3, 1>(0, j) = z.cross(f.p - a);
    J.block<3, 1>(3, j) = z;
  }
}

bool ArmIK::refine(const FlangePose& T, double* q) const {
  const ArmIkParams& p = params_;
  Eigen::Matrix<double, 6, kArmJoints> J;
  FlangePose f;
  for (int it = 0; it < p.iterations; ++it) {
    pose_and_jacobian(q, f, J);
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = T.p - f.p;
    e.tail<3>() = rotation_vector(T.R * f.R.transpose());
    if (e.head<3>().norm() <= p.tol_m && e.tail<3>().norm() <= p.tol_rad) break;
    Eigen::Matrix<double, 6, 6> A = J * J.transpose();
    A.diagonal().array() += kNewtonRegularisation;
    const Eigen::Matrix<double, 6, 1> y = A.partialPivLu().solve(e);
    const Eigen::Matrix<double, kArmJoints, 1> step = J.transpose() * y;
    for (int j = 0; j < kArmJoints; ++j) q[j] += step[j];
  }
  for (int j = 0; j < kArmJoints; ++j) {
    if (!(q[j] >= p.q_min_rad[j] - p.limit_eps_rad && q[j] <= p.q_max_rad[j] + p.limit_eps_rad)) return false;
    q[j] = std::min(p.q_max_rad[j], std::max(p.q_min_rad[j], q[j]));
  }
  const FlangePose g = flange(q);
  return (T.p - g.p).norm() <= p.accept_m && rotation_angle(T.R * g.R.transpose()) <= p.accept_rad;
}

}  // namespace grasp_core
