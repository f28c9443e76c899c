// Forward kinematics of a serial/tree robot given as fixed body transforms plus hinge joints.
//
// The chain is exported once from the MuJoCo model (Python side): per body its parent
// (parents come first), its fixed rotation R and offset p relative to the parent, and
// optionally one hinge joint (axis and anchor in the body frame, zero angle q0) driven by
// one entry of the 7-element arm state. Joints at fixed values (the fingers' slides) are
// folded into the fixed offsets by the exporter. The recursion is MuJoCo's:
//   R_b = R_parent R_fixed,  p_b = p_parent + R_parent p_fixed,
//   hinge: a = p_b + R_b anchor;  R_b <- R_b Rot(axis, q - q0);  p_b = a - R_b anchor.
#pragma once

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

 private:
  std::vector<ChainBody> bodies_;
};

}  // namespace grasp_core
