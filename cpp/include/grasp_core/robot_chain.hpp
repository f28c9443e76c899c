// Forward kinematics of a serial/tree robot given as fixed body transforms plus hinge joints.
//
// The chain is exported once from the MuJoCo model (Python side): per body its parent
// (parents come first), its fixed rotation R and offset p relative to the parent, and
// optionally one hinge joint (axis and anchor in the body frame, zero angle q0) driven by
// one entry of the 7-element arm state. Joints at fixed values (the fingers' slides) are
// folded into the fixed offsets by the exporter. The recursion is MuJoCo's:
//   R_b = R_parent R_fixed,  p_b = p_parent + R_parent p_fixed,
//   hinge: a = p_b + R_b anchor;  R_b <- R_b Rot(axis, q - q0);  p_b = a - R_b anchor.
// Speed: the fixed rotations and offsets are mostly sparse (a robot's bodies are turned by
// multiples of 90 degrees); their products skip the exact zeros, which gives the same
// numbers as the full product (a sum of at most two non-zero terms does not depend on the
// order of summation; bodies with denser fixed transforms take the full product).
#pragma once

#include <cstdint>
#include <vector>

#include "grasp_core/types.hpp"

namespace grasp_core {

/// Number of arm joints the chain is driven by.
constexpr int kArmJoints = 7;

struct ChainBody {
  int parent = 0;          ///< index of the parent body (< own index); body 0 is the world
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();   ///< [m]
  int joint = -1;          ///< arm-state index of the hinge of this body, -1 = rigid
  Vec3 axis = Vec3::UnitZ();
  Vec3 anchor = Vec3::Zero();  ///< [m]
  double q0_rad = 0.0;
};

class RobotChain {
 public:
  RobotChain() = default;
  /// Throws std::invalid_argument for a parent not before its child, a joint index outside
  /// [-1, 7), a zero axis or a non-finite value.
  explicit RobotChain(std::vector<ChainBody> bodies);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  const ChainBody& body(int b) const { return bodies_[static_cast<std::size_t>(b)]; }

  /// World poses of every body for the arm state q (7 values); R and p have num_bodies() slots.
  void poses(const double* q, Mat3* R, Vec3* p) const { poses(q, R, p, num_bodies()); }
  /// Poses of the first `count` bodies only (clamped to num_bodies()).
  void poses(const double* q, Mat3* R, Vec3* p, int count) const;
  /// True when no hinge of the chain lies between the world and body b (its pose is constant).
  bool body_fixed(int b) const { return fixed_pose_[static_cast<std::size_t>(b)] != 0; }

  /// A fixed matrix (or vector) as at most two non-zero (row, value) terms per column;
  /// `general` when some column has three (then the full product is taken).
  struct Sparse {
    std::uint8_t count[3] = {0, 0, 0};
    std::uint8_t row[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    double value[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    bool general = false, identity = false, permutation = false;
  };

 private:
  /// One body's step of the recursion, compiled from its ChainBody.
  struct Step {
    int parent = 0, joint = -1;
    double q0_rad = 0.0;
    bool z_hinge = false;      ///< hinge about the body's own z axis through its origin
    double z_sign = 1.0;       ///< +1 / -1: the axis is +z / -z
    Sparse rot, pos;           ///< the fixed R and p
  };

  std::vector<ChainBody> bodies_;
  std::vector<Step> steps_;
  std::vector<std::uint8_t> fixed_pose_;
};

}  // namespace grasp_core
