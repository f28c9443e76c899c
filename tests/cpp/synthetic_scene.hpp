// Synthetic point clouds for the scene-filter tests (header-only, seeded, world frame z up).
//
// A SceneBuilder accumulates noisy samples of simple surfaces, each point carrying a
// ground-truth tag (kTagNone for table/floor/wall/noise, >= 0 for object k). Noise is
// Gaussian along the surface normal with the given sigma [m]; grid points also get a small
// in-plane jitter so that no two surfaces are sampled on a common lattice.
#pragma once

#include "grasp_core/types.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace grasp_test {

using grasp_core::PointsD;
using grasp_core::PointsF;
using grasp_core::Vec3;

constexpr int kTagNone = -1;
constexpr int kTagNaN = -2;

class SceneBuilder {
 public:
  explicit SceneBuilder(std::uint32_t seed) : rng_(seed) {}

  /// Rectangular patch centred at `centre`, spanned by unit vectors u, v (sizes su, sv [m]),
  /// grid spacing [m], noise sigma [m] along u x v.
  void patch(const Vec3& centre, const Vec3& u, const Vec3& v, double su, double sv,
             double spacing, double sigma, int tag = kTagNone) {
    const Vec3 n = u.cross(v).normalized();
    const int nu = std::max(1, static_cast<int>(std::round(su / spacing)));
    const int nv = std::max(1, static_cast<int>(std::round(sv / spacing)));
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double a = (i + 0.5 + jitter()) * su / nu - su / 2;
        const double b = (j + 0.5 + jitter()) * sv / nv - sv / 2;
        add(centre + a * u + b * v + gauss(sigma) * n, tag);
      }
  }

  /// Horizontal patch (normal +z) at height z, optionally tilted by tilt_deg about the axis
  /// at yaw `tilt_axis_yaw_deg` in the xy plane.
  void horizontal(double cx, double cy, double z, double sx, double sy, double spacing,
                  double sigma, double tilt_deg = 0.0, double tilt_axis_yaw_deg = 0.0,
                  int tag = kTagNone) {
    const Eigen::Matrix3d R = tilt(tilt_deg, tilt_axis_yaw_deg);
    patch(Vec3(cx, cy, z), R * Vec3::UnitX(), R * Vec3::UnitY(), sx, sy, spacing, sigma, tag);
  }

  /// Exactly `count` points uniformly at random on a (possibly tilted) horizontal rectangle.
  void horizontal_random(double cx, double cy, double z, double sx, double sy, int count,
                         double sigma, double tilt_deg = 0.0, double tilt_axis_yaw_deg = 0.0,
                         int tag = kTagNone) {
    const Eigen::Matrix3d R = tilt(tilt_deg, tilt_axis_yaw_deg);
    std::uniform_real_distribution<double> ux(-sx / 2, sx / 2), uy(-sy / 2, sy / 2);
    for (int i = 0; i < count; ++i)
      add(Vec3(cx, cy, z) + R * Vec3(ux(rng_), uy(rng_), gauss(sigma)), tag);
  }

  /// Vertical wall: the plane x = x0 (normal -x, facing the robot), y in [y0, y1], z in [z0, z1].
  void wall_x(double x0, double y0, double y1, double z0, double z1, double spacing,
              double sigma, int tag = kTagNone) {
    patch(Vec3(x0, (y0 + y1) / 2, (z0 + z1) / 2), Vec3::UnitY(), Vec3::UnitZ(), y1 - y0,
          z1 - z0, spacing, sigma, tag);
  }

  /// Box standing on a table at height `base_z`: top face plus the first `n_sides` side faces
  /// in the order +x', -y', -x', +y' (box frame yawed by yaw_deg).
  void box(double cx, double cy, double base_z, double sx, double sy, double sz, double yaw_deg,
           double spacing, double sigma, int n_sides, int tag) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Vec3::UnitZ()).toRotationMatrix();
    const Vec3 ex = R * Vec3::UnitX(), ey = R * Vec3::UnitY(), ez = Vec3::UnitZ();
    const Vec3 c(cx, cy, base_z + sz / 2);
    patch(c + ez * sz / 2, ex, ey, sx, sy, spacing, sigma, tag);
    const Vec3 centres[4] = {c + ex * sx / 2, c - ey * sy / 2, c - ex * sx / 2, c + ey * sy / 2};
    const Vec3 spans[4] = {ey, ex, -ey, -ex};
    const double lens[4] = {sy, sx, sy, sx};
    for (int k = 0; k < std::min(n_sides, 4); ++k)
      patch(centres[k], spans[k], ez, lens[k], sz, spacing, sigma, tag);
  }

  /// Upright cylinder on a table at `base_z`: top disk plus the lateral surface over
  /// `arc_deg` degrees centred on azimuth `arc_centre_deg`.
  void cylinder(double cx, double cy, double base_z, double radius, double height, double spacing,
                double sigma, double arc_deg, double arc_centre_deg, int tag) {
    const double top = base_z + height;
    for (double x = -radius; x <= radius; x += spacing)
      for (double y = -radius; y <= radius; y += spacing) {
        const double px = x + jitter() * spacing, py = y + jitter() * spacing;
        if (px * px + py * py <= radius * radius) add(Vec3(cx + px, cy + py, top + gauss(sigma)), tag);
      }
    const double dphi = spacing / radius;
    const double a0 = (arc_centre_deg - arc_deg / 2) * M_PI / 180.0;
    const double a1 = (arc_centre_deg + arc_deg / 2) * M_PI / 180.0;
    for (double a = a0; a < a1; a += dphi)
      for (double z = base_z + spacing / 2; z < top; z += spacing) {
        const double r = radius + gauss(sigma);
        add(Vec3(cx + r * std::cos(a), cy + r * std::sin(a), z), tag);
      }
  }

  /// `count` points uniformly inside an axis-aligned box (clutter / outliers).
  void uniform_box(const Vec3& lo, const Vec3& hi, int count, int tag = kTagNone) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < count; ++i)
      add(lo + (hi - lo).cwiseProduct(Vec3(u(rng_), u(rng_), u(rng_))), tag);
  }

  /// `count` rows of NaN (and every 3rd one +Inf) — invalid depth pixels.
  void invalid_rows(int count) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < count; ++i) add(Vec3(i % 3 == 0 ? inf : nan, 0.1, nan), kTagNaN);
  }

  /// Random permutation of the rows (camera order is irrelevant to the filter).
  void shuffle() {
    std::vector<std::size_t> perm(pts_.size());
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
    std::shuffle(perm.begin(), perm.end(), rng_);
    std::vector<Vec3> p(pts_.size());
    std::vector<int> t(tags_.size());
    for (std::size_t i = 0; i < perm.size(); ++i) {
      p[i] = pts_[perm[i]];
      t[i] = tags_[perm[i]];
    }
    pts_.swap(p);
    tags_.swap(t);
  }

  std::size_t size() const { return pts_.size(); }
  const std::vector<int>& tags() const { return tags_; }
  const std::vector<Vec3>& points() const { return pts_; }

  PointsD points_d() const {
    PointsD out(static_cast<Eigen::Index>(pts_.size()), 3);
    for (std::size_t i = 0; i < pts_.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = pts_[i].transpose();
    return out;
  }
  PointsF points_f() const { return points_d().cast<float>(); }

  std::mt19937& rng() { return rng_; }

 private:
  static Eigen::Matrix3d tilt(double tilt_deg, double axis_yaw_deg) {
    const double yaw = axis_yaw_deg * M_PI / 180.0;
    const Vec3 axis(std::cos(yaw), std::sin(yaw), 0.0);
    return Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, axis).toRotationMatrix();
  }
  double gauss(double sigma) {
    if (sigma <= 0) return 0.0;
    return std::normal_distribution<double>(0.0, sigma)(rng_);
  }
  double jitter() { return std::uniform_real_distribution<double>(-0.25, 0.25)(rng_); }
  void add(const Vec3& p, int tag) {
    pts_.push_back(p);
    tags_.push_back(tag);
  }

  std::mt19937 rng_;
  std::vector<Vec3> pts_;
  std::vector<int> tags_;
};

/// Reference tabletop of method.md §8: table top at z = 0.200 m, floor at z = 0, a wall at
/// x = 0.85 m below the table height (e.g. a cabinet front seen past the table edge), a blue 5 cm cube near (0.56, -0.03), a red one near (0.46, -0.10) and a green
/// cylinder (r 2.5 cm, h 5 cm) near (0.52, 0.09); 2 mm depth noise. Sized like a 640 x 480
/// depth frame: padded with invalid rows to exactly 307200 rows.
/// Objects are tagged 0 (blue), 1 (red), 2 (green).
inline SceneBuilder reference_tabletop(std::uint32_t seed, double sigma = 0.002,
                                       double object_spacing = 0.001) {
  SceneBuilder b(seed);
  constexpr double kTable = 0.200;
  b.horizontal(0.51, 0.0, kTable, 0.46, 0.44, 0.001, sigma);         // table top, 1 mm
  b.horizontal(0.51, -0.40, 0.0, 0.60, 0.30, 0.0025, sigma);         // floor past the edge
  b.wall_x(0.85, -0.30, 0.30, 0.0, 0.18, 0.0025, sigma);             // a wall below the table top
  b.box(0.56, -0.03, kTable, 0.05, 0.05, 0.05, 10.0, object_spacing, sigma, 2, 0);
  b.box(0.46, -0.10, kTable, 0.05, 0.05, 0.05, -25.0, object_spacing, sigma, 2, 1);
  b.cylinder(0.52, 0.09, kTable, 0.025, 0.05, object_spacing, sigma, 180.0, 180.0, 2);
  const int rows = 640 * 480;
  if (static_cast<int>(b.size()) < rows) b.invalid_rows(rows - static_cast<int>(b.size()));
  b.shuffle();
  return b;
}

}  // namespace grasp_test
