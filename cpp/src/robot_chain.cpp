#include "grasp_core/robot_chain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grasp_core {

RobotChain::RobotChain(std::vector<ChainBody> bodies) : bodies_(std::move(bodies)) {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    ChainBody& c = bodies_[b];
    const std::string where = "robot chain body " + std::to_string(b) + ": ";
    if (b > 0 && (c.parent < 0 || static_cast<std::size_t>(c.parent) >= b))
      throw std::invalid_argument(where + "parent must come before the body");
    if (c.joint < -1 || c.joint >= kArmJoints)
      throw std::invalid_argument(where + "joint index must be in [-1, 7)");
    if (!c.R.allFinite() || !c.p.allFinite() || !c.axis.allFinite() || !c.anchor.allFinite() ||
        !std::isfinite(c.q0_rad))
      throw std::invalid_argument(where + "non-finite transform or joint data");
    if (c.joint >= 0) {
      const double n = c.axis.norm();
      if (!(n > 0.0)) throw std::invalid_argument(where + "zero joint axis");
      c.axis /= n;
    }
  }
  if (!bodies_.empty()) bodies_[0].parent = -1;
}

void RobotChain::poses(const double* q, Mat3* R, Vec3* p, int count) const {
  if (bodies_.empty() || count <= 0) return;
  const std::size_t n = std::min(bodies_.size(), static_cast<std::size_t>(count));
  R[0] = bodies_[0].R;
  p[0] = bodies_[0].p;
  for (std::size_t b = 1; b < n; ++b) {
    const ChainBody& c = bodies_[b];
    const Mat3& Rp = R[c.parent];
    Mat3 Rb = Rp * c.R;
    Vec3 pb = p[c.parent] + Rp * c.p;
    if (c.joint >= 0) {
      const double angle = q[c.joint] - c.q0_rad;
      if (c.axis.x() == 0.0 && c.axis.y() == 0.0 && c.anchor.isZero()) {
        // hinge about the body's z axis through its origin (every Panda joint): mix columns
        const double signed_angle = c.axis.z() > 0.0 ? angle : -angle;
        const double cs = std::cos(signed_angle), sn = std::sin(signed_angle);
        const Vec3 c0 = Rb.col(0), c1 = Rb.col(1);
        Rb.col(0) = cs * c0 + sn * c1;
        Rb.col(1) = cs * c1 - sn * c0;
      } else {
        const Vec3 a = pb + Rb * c.anchor;
        Rb = Rb * Eigen::AngleAxisd(angle, c.axis).toRotationMatrix();
        pb = a - Rb * c.anchor;
      }
    }
    R[b] = Rb;
    p[b] = pb;
  }
}

}  // namespace grasp_core
