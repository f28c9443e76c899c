// Synthetic single-object clouds for the estimate / grasp / tracker tests (header-only).
//
// Objects are built in a local frame (z = 0 on the table, z up), yawed about the table
// normal, placed at (x, y) on the table and, optionally, on a tilted table. Depth noise is
// Gaussian along the local z axis (the depth direction of a view from above), seeded.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "grasp_core/object_estimate.hpp"
#include "grasp_core/types.hpp"

namespace grasp_test {

using grasp_core::Mat3;
using grasp_core::Plane;
using grasp_core::PointsD;
using grasp_core::Vec3;

constexpr double kDeg = M_PI / 180.0;

/// Where an object stands: table frame (height, tilt) + object pose on it.
struct Placement {
  double table_z_m = 0.2;          ///< table origin height [m]
  Mat3 table_tilt = Mat3::Identity();  ///< rotation of the table frame (tilted tables)
  double x_m = 0.5, y_m = 0.0;     ///< object position in the table frame [m]
  double yaw_rad = 0.0;            ///< object yaw about the table normal [rad]
  double lift_m = 0.0;             ///< gap under the object (floating / stacked) [m]
};

inline Mat3 rot_z(double yaw_rad) {
  return Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
}

/// The table plane of a placement: n = tilt * z through (0, 0, table_z).
inline Plane table_plane(const Placement& pl) {
  Plane p;
  p.n = pl.table_tilt.col(2);
  p.c = -p.n.dot(Vec3(0, 0, pl.table_z_m));
  return p;
}

/// Local object point -> world point.
inline Vec3 to_world(const Vec3& local, const Placement& pl) {
  const Vec3 on_table = rot_z(pl.yaw_rad) * local + Vec3(pl.x_m, pl.y_m, pl.lift_m);
  return Vec3(0, 0, pl.table_z_m) + pl.table_tilt * on_table;
}

inline PointsD place(const std::vector<Vec3>& local, const Placement& pl) {
  PointsD out(static_cast<Eigen::Index>(local.size()), 3);
  for (std::size_t i = 0; i < local.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = to_world(local[i], pl).transpose();
  return out;
}

/// Adds N(0, sigma) to local z of every point (depth noise of a view from above).
inline void add_z_noise(std::vector<Vec3>& pts, double sigma_m, unsigned seed) {
  if (sigma_m <= 0.0) return;
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, sigma_m);
  for (auto& p : pts) p.z() += g(rng);
}

/// Number of grid steps covering [0, len] at spacing (at least 1).
inline int steps(double len_m, double spacing_m) {
  return std::max(1, static_cast<int>(std::lround(len_m / spacing_m)));
}

/// Top face sx x sy at height h, grid-sampled. corner_radius_m > 0 drops the corner points
/// outside quarter circles: the corner loss a real depth camera shows at depth edges.
inline std::vector<Vec3> rect_top(double sx_m, double sy_m, double h_m, double spacing_m,
                                  double corner_radius_m = 0.0) {
  std::vector<Vec3> pts;
  const int nx = steps(sx_m, spacing_m), ny = steps(sy_m, spacing_m);
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const double x = -sx_m / 2 + sx_m * i / nx, y = -sy_m / 2 + sy_m * j / ny;
      if (corner_radius_m > 0.0) {
        const double dx = std::max(std::abs(x) - (sx_m / 2 - corner_radius_m), 0.0);
        const double dy = std::max(std::abs(y) - (sy_m / 2 - corner_radius_m), 0.0);
        if (dx * dx + dy * dy > corner_radius_m * corner_radius_m * (1.0 + 1e-9)) continue;
      }
      pts.emplace_back(x, y, h_m);
    }
  }
  return pts;
}

/// The +x side face of an sx x sy x sz box (x = sx/2, y across, z from 0 to sz).
inline std::vector<Vec3> box_side_plus_x(double sx_m, double sy_m, double sz_m,
                                         double spacing_m) {
  std::vector<Vec3> pts;
  const int ny = steps(sy_m, spacing_m), nz = steps(sz_m, spacing_m);
  for (int j = 0; j <= ny; ++j)
    for (int k = 0; k < nz; ++k)  // k < nz: the top edge belongs to the top face
      pts.emplace_back(sx_m / 2, -sy_m / 2 + sy_m * j / ny, sz_m * k / nz);
  return pts;
}

/// Top disk of a cylinder of radius r at height h, grid-sampled.
inline std::vector<Vec3> disk_top(double r_m, double h_m, double spacing_m) {
  std::vector<Vec3> pts;
  const int n = steps(r_m, spacing_m);
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      const double x = r_m * i / n, y = r_m * j / n;
      if (x * x + y * y <= r_m * r_m) pts.emplace_back(x, y, h_m);
    }
  return pts;
}

/// A box seen obliquely: its top face plus its +x side face, with z noise.
inline std::vector<Vec3> box_top_and_side(double sx_m, double sy_m, double sz_m,
                                          double spacing_m, double noise_m, unsigned seed) {
  std::vector<Vec3> pts = rect_top(sx_m, sy_m, sz_m, spacing_m);
  const auto side = box_side_plus_x(sx_m, sy_m, sz_m, spacing_m);
  pts.insert(pts.end(), side.begin(), side.end());
  add_z_noise(pts, noise_m, seed);
  return pts;
}

/// A hand-made estimate for tracker tests (n = +z, guards all true).
inline grasp_core::ObjectEstimate make_estimate(const Vec3& center, double theta_rad = 0.0,
                                                double width_m = 0.05,
                                                double perp_width_m = 0.05,
                                                double height_m = 0.05,
                                                double anisotropy = 1.3) {
  grasp_core::ObjectEstimate e;
  e.center = center;
  e.theta_rad = theta_rad;
  e.width_m = width_m;
  e.perp_width_m = perp_width_m;
  e.height_m = height_m;
  e.anisotropy = anisotropy;
  e.yaw_defined = true;
  e.R_box = rot_z(theta_rad);  // in_plane_basis(+z) = (x, y)
  e.extents = Vec3(width_m, perp_width_m, height_m);
  e.num_points = 100;
  return e;
}

}  // namespace grasp_test
