// The perceived obstacles of one planning scene, in the form the state checker queries:
// the occupancy map's distance field, oriented object boxes, the floor plane, and the
// target-cleared region of the final approach, and objects modelled by their points. Immutable once built (shared by checkers).
//
// Semantics follow python/grasp_pipeline/motion/occupancy.py exactly:
// * DistanceField::at(p): the voxel of p is floor((p - origin) / voxel); outside the grid
//   (or for an empty map) +inf, else the stored value (distance between voxel centres, m).
// * ObstacleBox::distance(p): Euclidean distance to the solid box (0 inside).
// * ClearedRegion::distance(p) (only used where the cleared box is within pad of p): the
//   distance to the nearest kept point, +inf when none is closer than pad; the result is
//   reported as (d - fine_rounding) + inflation, like the Python view.
#pragma once

#include <limits>
#include <vector>

#include "grasp_core/types.hpp"

namespace grasp_core {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct DistanceField {
  std::vector<float> values;  ///< C order (x slowest), size nx * ny * nz; empty = no map
  long long nx = 0, ny = 0, nz = 0;
  Vec3 origin = Vec3::Zero();  ///< [m] corner of voxel (0, 0, 0)
  double voxel_m = 0.0;
  double inflation_m = 0.0;

  bool empty() const { return values.empty(); }
  /// Distance-field value of the voxel containing p [m] (+inf outside the grid / empty map).
  double at(const Vec3& p) const {
    if (values.empty()) return kInfinity;
    const double fx = std::floor((p.x() - origin.x()) / voxel_m);
    const double fy = std::floor((p.y() - origin.y()) / voxel_m);
    const double fz = std::floor((p.z() - origin.z()) / voxel_m);
    if (!(fx >= 0.0 && fy >= 0.0 && fz >= 0.0 && fx < static_cast<double>(nx) &&
          fy < static_cast<double>(ny) && fz < static_cast<double>(nz)))
      return kInfinity;
    const long long i = static_cast<long long>(fx), j = static_cast<long long>(fy),
                    k = static_cast<long long>(fz);
    return static_cast<double>(values[static_cast<std::size_t>((i * ny + j) * nz + k)]);
  }
  /// Euclidean distance from p to the grid's box [origin, origin + n * voxel] (0 inside);
  /// +inf for an empty map. A point farther than 0 from the box is outside every voxel.
  double distance_to_grid(const Vec3& p) const {
    if (values.empty()) return kInfinity;
    const double hi[3] = {origin.x() + static_cast<double>(nx) * voxel_m, origin.y() + static_cast<double>(ny) * voxel_m,
                          origin.z() + static_cast<double>(nz) * voxel_m};
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double e = p[k] < origin[k] ? origin[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
      s += e * e;
    }
    return std::sqrt(s);
  }
};

struct ObstacleBox {
  Vec3 center = Vec3::Zero();
  Mat3 R = Mat3::Identity();  ///< columns = box axes in world
  Vec3 half = Vec3::Zero();   ///< half extents [m]
  double bound_radius_m = 0.0;  ///< radius of the sphere around center containing the box

  ObstacleBox() = default;
  ObstacleBox(const Vec3& c, const Mat3& rot, const Vec3& extents);
  double distance(const Vec3& p) const {
    const Vec3 d = p - center;
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
      // (p - c) @ R: column k of R, summed in x, y, z order like numpy
      const double l = d.x() * R(0, k) + d.y() * R(1, k) + d.z() * R(2, k);
      const double h = half[k];
      const double e = l - (l < -h ? -h : (l > h ? h : l));
      s += e * e;
    }
    return std::sqrt(s);
  }
};

/// Environment points kept around the grasp target, for exact nearest-point distances.
class ClearedRegion {
 public:
  ClearedRegion() = default;
  /// box: the (padded) target box; pad_m: the map's query reach; points (kept points, fine
  /// grid); fine_m: their rounding; inflation_m: the map's inflation.
  ClearedRegion(const ObstacleBox& box, double pad_m, std::vector<Vec3> points, double fine_m,
                double inflation_m);

  const ObstacleBox& box() const { return box_; }
  double pad_m() const { return pad_; }
  double fine_m() const { return fine_; }
  /// True when p is close enough to the box for the cleared answer (box distance <= pad).
  bool near(const Vec3& p) const { return box_.distance(p) <= pad_; }
  /// (nearest kept point distance - fine) + inflation, +inf if no point within pad.
  double distance(const Vec3& p) const;
  /// distance(p) - threshold < 0, without finding the nearest point: true when some kept
  /// point at d < pad has (d - fine) + inflation - threshold < 0. The same answer, since that
  /// expression never decreases with d (so the nearest point fails whenever any point does);
  /// only the cells within reach of such a point are visited, and the first one ends it.
  bool blocked(const Vec3& p, double threshold) const;

 private:
  double nearest_sq(const Vec3& p) const;

  ObstacleBox box_;
  double pad_ = 0.0, fine_ = 0.0, inflation_ = 0.0;
  std::vector<Vec3> points_;            ///< sorted by cell
  std::vector<std::size_t> cell_start_; ///< CSR offsets, size ncell + 1
  Vec3 lo_ = Vec3::Zero();
  double cell_m_ = 1.0;
  long long dims_[3] = {0, 0, 0};
};

struct CollisionScene {
  double collision_margin_m = 0.0;
  double floor_z_m = 0.0;
  DistanceField field;
  bool has_env = false;  ///< false: no occupancy map at all (free space)
  std::vector<ObstacleBox> boxes;
  bool has_cleared = false;
  ClearedRegion cleared;
  /// Objects modelled by their points (2.5-D columns under what the camera saw of them),
  /// checked for every environment sphere: blocked where a point lies closer than radius +
  /// margin + the points' grid rounding. Box = the points' bounding box, inflation 0.
  bool has_points = false;
  ClearedRegion points;
};

}  // namespace grasp_core
