// Arm IK refinement (grasp_core::ArmIK) on a synthetic 7-joint spatial arm.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "grasp_core/arm_ik.hpp"

using namespace grasp_core;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// world, base, 7 hinge links (alternating +-90 deg about x between them, offsets along the
/// links), flange (fixed, 0.1 m along z of link 7). Body 9 is the flange.
std::vector<ChainBody> arm_bodies() {
  std::vector<ChainBody> b(10);
  b[1].p = Vec3(0, 0, 0.1);
  const double offsets[7][3] = {{0, 0, 0.3}, {0, 0, 0}, {0, -0.3, 0}, {0.08, 0, 0}, {-0.08, 0.35, 0}, {0, 0, 0}, {0.09, 0, 0}};
  for (int j = 0; j < 7; ++j) {
    ChainBody& c = b[static_cast<std::size_t>(j + 2)];
    c.parent = j + 1;
    c.joint = j;
    c.p = Vec3(offsets[j][0], offsets[j][1], offsets[j][2]);
    if (j > 0) c.R = Eigen::AngleAxisd((j % 2 ? -0.5 : 0.5) * kPi, Vec3::UnitX()).toRotationMatrix();
  }
  b[9].parent = 8;
  b[9].p = Vec3(0, 0, 0.1);
  return b;
}

ArmIkParams params() {
  ArmIkParams p;
  for (int j = 0; j < kArmJoints; ++j) { p.q_min_rad[j] = -2.8; p.q_max_rad[j] = 2.8; }
  return p;
}

}  // namespace

TEST(ArmIK, RotationVectorAndAngleMatchAxisAngle) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double angle : {0.0, 1e-8, 1e-4, 0.3, 2.0, kPi - 1e-6, kPi}) {
    for (int k = 0; k < 20; ++k) {
      const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
      const Mat3 R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
      EXPECT_NEAR(rotation_angle(R), angle, 1e-9);
      const Vec3 v = rotation_vector(R);
      EXPECT_NEAR(v.norm(), angle, 1e-9);
      EXPECT_LT((Eigen::AngleAxisd(v.norm(), v.norm() > 0 ? Vec3(v.normalized()) : Vec3::UnitZ()).toRotationMatrix() - R).norm(), 1e-9);
    }
  }
}

TEST(ArmIK, RefinesPerturbedSeedsToTheTargetPose) {
  const ArmIK ik(RobotChain(arm_bodies()), 9, params());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.03);
  int kept = 0;
  for (int k = 0; k < 200; ++k) {
    double q_true[kArmJoints], q[kArmJoints];
    for (int j = 0; j < kArmJoints; ++j) { q_true[j] = u(rng); q[j] = q_true[j] + noise(rng); }
    const FlangePose T = ik.flange(q_true);
    if (!ik.refine(T, q)) continue;
    ++kept;
    const FlangePose g = ik.flange(q);
    EXPECT_LE((g.p - T.p).norm(), 1e-6);
    EXPECT_LE(rotation_angle(T.R * g.R.transpose()), 1e-6);
    for (int j = 0; j < kArmJoints; ++j) {
      EXPECT_GE(q[j], -2.8);
      EXPECT_LE(q[j], 2.8);
    }
  }
  EXPECT_GE(kept, 190);  // a 0.03 rad perturbation converges except near singular states
}

TEST(ArmIK, RefusesUnreachableTargetsAndSolutionsOutsideTheLimits) {
  const ArmIK ik(RobotChain(arm_bodies()), 9, params());
  double q[kArmJoints] = {0.1, 0.2, 0.3, -0.4, 0.5, 0.6, 0.7};
  FlangePose far = ik.flange(q);
  far.p += Vec3(5.0, 0, 0);  // beyond the arm's reach
  double seed[kArmJoints] = {0.1, 0.2, 0.3, -0.4, 0.5, 0.6, 0.7};
  EXPECT_FALSE(ik.refine(far, seed));
  // the exact solution has joint 1 at 2.7 rad; limits of +-2.5 rad refuse it
  ArmIkParams narrow = params();
  for (int j = 0; j < kArmJoints; ++j) { narrow.q_min_rad[j] = -2.5; narrow.q_max_rad[j] = 2.5; }
  const ArmIK tight(RobotChain(arm_bodies()), 9, narrow);
  double q_out[kArmJoints] = {2.7, 0.2, 0.3, -0.4, 0.5, 0.6, 0.7};
  const FlangePose T = tight.flange(q_out);
  double s[kArmJoints] = {2.7, 0.2, 0.3, -0.4, 0.5, 0.6, 0.7};
  EXPECT_FALSE(tight.refine(T, s));
}

TEST(ArmIK, RejectsBadConstruction) {
  EXPECT_THROW(ArmIK(RobotChain(arm_bodies()), 0, params()), std::invalid_argument);
  EXPECT_THROW(ArmIK(RobotChain(arm_bodies()), 10, params()), std::invalid_argument);
  EXPECT_THROW(ArmIK(RobotChain(arm_bodies()), 5, params()), std::invalid_argument);  // joints 5-7 after it
  ArmIkParams p = params();
  p.iterations = -1;
  EXPECT_THROW(ArmIK(RobotChain(arm_bodies()), 9, p), std::invalid_argument);
  p = params();
  p.q_min_rad[2] = 3.0;
  EXPECT_THROW(ArmIK(RobotChain(arm_bodies()), 9, p), std::invalid_argument);
  auto bodies = arm_bodies();
  bodies[4].joint = 1;  // joint 2 on two bodies
  EXPECT_THROW(ArmIK(RobotChain(bodies), 9, params()), std::invalid_argument);
}
