// Basic value types shared by every part of the perception core.
//
// Frames and conventions follow method.md §0: everything is in `world` (z up),
// a plane is (n, c) with n.p + c = 0, |n| = 1 and n_z > 0, rotations have det +1.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <vector>

namespace grasp_core {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// N x 3 points, one point per row (row-major so a numpy (N,3) array maps onto it).
using PointsF = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
using PointsD = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Per-point label values used by the scene filter (object labels are >= 0).
constexpr int kLabelInvalid = -2;      ///< NaN / Inf input row (dropped before processing)
constexpr int kLabelEnvironment = -1;  ///< table, floor, walls, band, rejected clusters

/// (ours) Default sane coordinate bound [m]: a point with any |coordinate| above it is
/// dropped and counted like a NaN row (SceneFilterParams::max_abs_coordinate_m, and the
/// max_abs_coordinate_m argument of the fine-grained functions). A workspace is metres
/// across; values near float max are sensor garbage that overflow the geometry (a kd-tree
/// split midpoint of two points at 3.4e38 is +inf, which aborts FLANN).
constexpr double kDefaultMaxAbsCoordinate_m = 1000.0;
/// Largest bound validate() accepts [m]: with it, sums and midpoints of coordinates in
/// float stay far from overflow.
constexpr double kMaxAbsCoordinateLimit_m = 1.0e9;

/// True when p is finite and every |coordinate| <= bound (NaN bound: nothing is in).
template <typename T>
inline bool within_bound(T x, T y, T z, double bound) {
  const double b = bound;
  return std::abs(static_cast<double>(x)) <= b && std::abs(static_cast<double>(y)) <= b &&
         std::abs(static_cast<double>(z)) <= b;
}

/// A plane n.p + c = 0 with |n| = 1 and n_z > 0.
struct Plane {
  Vec3 n = Vec3::UnitZ();
  double c = 0.0;

  /// Height where the plane meets the world z axis: h = -c / n_z  [m].
  double height_m() const { return -c / n.z(); }
  /// Signed distance of p (positive above the plane) [m].
  double signed_distance(const Vec3& p) const { return n.dot(p) + c; }
  /// Foot of the origin on the plane: -c * n.
  Vec3 foot() const { return -c * n; }
  /// Angle between the normal and world +z [deg].
  double tilt_deg() const;
  /// Rotation taking +z to n (the published plane orientation, det +1).
  Mat3 rotation() const;
};

/// A rigid pose: x_world = R * x_local + t.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
};

/// View quality of one observation (method.md §3). Ordered: NADIR > OBLIQUE.
enum class ViewQuality : int { OBLIQUE = 0, NADIR = 1 };

}  // namespace grasp_core
