#include "grasp_core/types.hpp"

#include <algorithm>
#include <cmath>

namespace grasp_core {

double Plane::tilt_deg() const {
  const double cz = std::clamp(n.z() / n.norm(), -1.0, 1.0);
  return std::acos(cz) * 180.0 / M_PI;
}

Mat3 Plane::rotation() const {
  // Shortest rotation taking +z onto n (n_z > 0, so never the antipodal case).
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), n.normalized()).toRotationMatrix();
}

}  // namespace grasp_core
