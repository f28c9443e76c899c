#include "grasp_core/voxel_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grasp_core {

namespace {

/// floor(q) as an integer: truncation corrected below zero (no libm call) where q fits.
inline std::int64_t floor_index(double q) {
  if (!(std::fabs(q) < 4.0e18)) return static_cast<std::int64_t>(std::floor(q));
  const auto t = static_cast<std::int64_t>(q);
  return t - (q < static_cast<double>(t) ? 1 : 0);
}

inline bool inside(const double* p, const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  for (int j = 0; j < 3; ++j)  // a NaN fails both tests; an infinity fails the finite test
    if (!(p[j] >= lo[j] && p[j] <= hi[j] && std::isfinite(p[j]))) return false;
  return true;
}

}  // namespace

VoxelizedRows voxelize_rows(const double* points, std::size_t n, const std::array<double, 3>& lo,
                            const std::array<double, 3>& hi, double voxel_m, std::int64_t pad_voxels) {
  VoxelizedRows out;
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i) m += inside(points + 3 * i, lo, hi) ? 1 : 0;
  out.kept.resize(3 * m);
  out.index.resize(3 * m);
  std::array<std::int64_t, 3> mn, mx;
  mn.fill(std::numeric_limits<std::int64_t>::max());
  mx.fill(std::numeric_limits<std::int64_t>::min());
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = points + 3 * i;
    if (!inside(p, lo, hi)) continue;
    for (int j = 0; j < 3; ++j) {
      const std::int64_t c = floor_index((p[j] - lo[j]) / voxel_m);
      out.kept[3 * k + j] = p[j];
      out.index[3 * k + j] = c;
      mn[j] = std::min(mn[j], c);
      mx[j] = std::max(mx[j], c);
    }
    ++k;
  }
  if (m == 0) return out;
  for (int j = 0; j < 3; ++j) {
    out.first_index[j] = mn[j] - pad_voxels;
    out.shape[j] = mx[j] + pad_voxels - out.first_index[j] + 1;
  }
  return out;
}

void mark_occupied(const VoxelizedRows& rows, std::uint8_t* grid) {
  const std::size_t m = rows.index.size() / 3;
  const auto& f = rows.first_index;
  const std::int64_t sy = rows.shape[2], sx = rows.shape[1] * rows.shape[2];
  for (std::size_t k = 0; k < m; ++k) {
    const std::int64_t* c = &rows.index[3 * k];
    grid[(c[0] - f[0]) * sx + (c[1] - f[1]) * sy + (c[2] - f[2])] = 1;
  }
}

}  // namespace grasp_core
