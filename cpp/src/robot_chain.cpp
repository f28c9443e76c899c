#include "grasp_core/robot_chain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grasp_core {

namespace {

RobotChain::Sparse sparse_of(const Eigen::Matrix3d& m, int cols) {
  RobotChain::Sparse s;
  for (int j = 0; j < cols; ++j)
    for (int k = 0; k < 3; ++k) {
      if (m(k, j) == 0.0) continue;
      if (s.count[j] == 2) { s.general = true; continue; }
      s.row[j][s.count[j]] = static_cast<std::uint8_t>(k);
      s.value[j][s.count[j]] = m(k, j);
      ++s.count[j];
    }
  s.identity = cols == 3 && m == Eigen::Matrix3d::Identity();
  s.permutation = !s.general && s.count[0] == 1 && s.count[1] == 1 && s.count[2] == 1;
  return s;
}

/// Column j of M S (M column-major, S sparse, not general): the non-zero terms only
/// (terms equal to zero add nothing, so this equals the full product).
inline void sparse_column(const double* M, const RobotChain::Sparse& s, int j, double* out) {
  const int n = s.count[j];
  const double* a = M + 3 * s.row[j][0];
  const double* b = M + 3 * s.row[j][1];
  const double va = s.value[j][0], vb = s.value[j][1];
  for (int i = 0; i < 3; ++i) out[i] = n == 0 ? 0.0 : (n == 1 ? a[i] * va : a[i] * va + b[i] * vb);
}

/// sin and cos of x for |x| <= kFastTrigMax_rad: x = n pi/2 + r with |r| <= pi/4 (pi/2 in
/// two parts, so r carries no cancellation error), then the Taylor series of sin r (to r^17)
/// and cos r (to r^16), whose remainders are below 1e-17; the results agree with the C
/// library's to about an ulp. Larger angles take the library.
constexpr double kFastTrigMax_rad = 64.0;

inline void fast_sincos(double x, double& s, double& c) {
  if (!(std::abs(x) <= kFastTrigMax_rad)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kPio2Hi = 1.5707963267948966192;      // double nearest pi/2
  constexpr double kPio2Lo = 6.1232339957367658e-17;     // pi/2 - kPio2Hi
  constexpr double kRound = 6755399441055744.0;          // 2^52 + 2^51: rounds to an integer
  const double n = (x * kTwoOverPi + kRound) - kRound;
  const double r = (x - n * kPio2Hi) - n * kPio2Lo;
  const double r2 = r * r;
  const double sr = r + r * r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 +
                    r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800.0 + r2 * (-1.0 / 1307674368000.0 +
                    r2 * (1.0 / 355687428096000.0))))))));
  const double cr = 1.0 + r2 * (-1.0 / 2 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 +
                    r2 * (-1.0 / 3628800 + r2 * (1.0 / 479001600.0 + r2 * (-1.0 / 87178291200.0 +
                    r2 * (1.0 / 20922789888000.0))))))));
  switch (static_cast<long long>(n) & 3) {
    case 0: s = sr; c = cr; break;
    case 1: s = cr; c = -sr; break;
    case 2: s = -sr; c = -cr; break;
    default: s = -cr; c = sr; break;
  }
}

/// Rb = Rp S for a fixed rotation S that is not general (at most two terms per column).
inline void fixed_rotation(const double* Rp, const RobotChain::Sparse& s, double* Rb) {
  if (s.identity) {
    for (int i = 0; i < 9; ++i) Rb[i] = Rp[i];
  } else if (s.permutation) {  // one term per column (turns by multiples of 90 degrees)
    for (int j = 0; j < 3; ++j) {
      const double* a = Rp + 3 * s.row[j][0];
      const double v = s.value[j][0];
      for (int i = 0; i < 3; ++i) Rb[3 * j + i] = a[i] * v;
    }
  } else {
    for (int j = 0; j < 3; ++j) sparse_column(Rp, s, j, Rb + 3 * j);
  }
}

/// pb = pp + Rp o for a fixed offset o that is not general (at most two terms).
inline void fixed_offset(const double* Rp, const double* pp, const RobotChain::Sparse& s, double* pb) {
  const double* a = Rp + 3 * s.row[0][0];
  const double* c = Rp + 3 * s.row[0][1];
  const double v = s.value[0][0], w = s.value[0][1];
  switch (s.count[0]) {
    case 0: for (int i = 0; i < 3; ++i) pb[i] = pp[i] + 0.0; break;
    case 1: for (int i = 0; i < 3; ++i) pb[i] = pp[i] + a[i] * v; break;
    default: for (int i = 0; i < 3; ++i) pb[i] = pp[i] + (a[i] * v + c[i] * w); break;
  }
}

}  // namespace

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
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const ChainBody& c = bodies_[b];
    Step st;
    st.parent = c.parent;
    st.joint = c.joint;
    st.q0_rad = c.q0_rad;
    st.z_hinge = c.joint >= 0 && c.axis.x() == 0.0 && c.axis.y() == 0.0 && c.anchor.isZero();
    st.z_sign = c.axis.z() > 0.0 ? 1.0 : -1.0;
    st.rot = sparse_of(c.R, 3);
    Eigen::Matrix3d pm = Eigen::Matrix3d::Zero();
    pm.col(0) = c.p;
    st.pos = sparse_of(pm, 1);
    steps_.push_back(st);
    fixed_pose_.push_back(c.joint < 0 && (b == 0 || fixed_pose_[static_cast<std::size_t>(c.parent)]));
  }
}

void RobotChain::poses(const double* q, Mat3* R, Vec3* p, int count) const {
  if (bodies_.empty() || count <= 0) return;
  const std::size_t n = std::min(bodies_.size(), static_cast<std::size_t>(count));
  R[0] = bodies_[0].R;
  p[0] = bodies_[0].p;
  for (std::size_t b = 1; b < n; ++b) {
    const Step& st = steps_[b];
    // Plain arrays (column-major) with the same operations, in the same order, as the Eigen
    // expressions they stand for: R_b = R_parent R_fixed, p_b = p_parent + R_parent p_fixed.
    if (st.rot.general) {
      R[b] = R[st.parent] * bodies_[b].R;
    } else {
      fixed_rotation(R[st.parent].data(), st.rot, R[b].data());
    }
    if (st.pos.general) {
      p[b] = p[st.parent] + R[st.parent] * bodies_[b].p;
    } else {
      fixed_offset(R[st.parent].data(), p[st.parent].data(), st.pos, p[b].data());
    }
    if (st.joint < 0) continue;
    const double angle = q[st.joint] - st.q0_rad;
    if (st.z_hinge) {
      // hinge about the body's z axis through its origin (every Panda joint): mix columns
      double cs, sn;
      fast_sincos(st.z_sign > 0.0 ? angle : -angle, sn, cs);
      double* Rb = R[b].data();
      for (int i = 0; i < 3; ++i) {
        const double c0 = Rb[i], c1 = Rb[3 + i];
        Rb[i] = cs * c0 + sn * c1;
        Rb[3 + i] = cs * c1 - sn * c0;
      }
    } else {
      const ChainBody& c = bodies_[b];
      const Vec3 a = p[b] + R[b] * c.anchor;
      R[b] = R[b] * Eigen::AngleAxisd(angle, c.axis).toRotationMatrix();
      p[b] = a - R[b] * c.anchor;
    }
  }
}

}  // namespace grasp_core
