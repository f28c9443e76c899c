#include "grasp_core/collision_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grasp_core {

namespace {
/// Grid cells per pad length of the cleared region's point buckets.
constexpr double kCellsPerPad = 4.0;
}  // namespace

ObstacleBox::ObstacleBox(const Vec3& c, const Mat3& rot, const Vec3& extents)
    : center(c), R(rot), half(0.5 * extents) {
  if (!c.allFinite() || !rot.allFinite() || !extents.allFinite())
    throw std::invalid_argument("object box: non-finite center, rotation or extents");
  if ((extents.array() < 0.0).any()) throw std::invalid_argument("object box: negative extents");
  // R may be any matrix numerically; bound |R^T d| clipping generously via the column norms
  bound_radius_m = 0.0;
  for (int k = 0; k < 3; ++k) bound_radius_m += half[k] * R.col(k).norm();
}

ClearedRegion::ClearedRegion(const ObstacleBox& box, double pad_m, std::vector<Vec3> points,
                             double fine_m, double inflation_m)
    : box_(box), pad_(pad_m), fine_(fine_m), inflation_(inflation_m) {
  if (!(std::isfinite(pad_m) && pad_m > 0.0) || !std::isfinite(fine_m) || !std::isfinite(inflation_m))
    throw std::invalid_argument("cleared region: pad must be finite > 0, fine and inflation finite");
  for (const Vec3& p : points)
    if (!p.allFinite()) throw std::invalid_argument("cleared region: non-finite point");
  if (points.empty()) return;
  cell_m_ = pad_m / kCellsPerPad;
  Vec3 hi = points[0];
  lo_ = points[0];
  for (const Vec3& p : points) { lo_ = lo_.cwiseMin(p); hi = hi.cwiseMax(p); }
  for (int k = 0; k < 3; ++k)
    dims_[k] = static_cast<long long>(std::floor((hi[k] - lo_[k]) / cell_m_)) + 1;
  const std::size_t ncell = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
  auto cell_of = [&](const Vec3& p) {
    long long c[3];
    for (int k = 0; k < 3; ++k)
      c[k] = std::min(dims_[k] - 1, static_cast<long long>(std::floor((p[k] - lo_[k]) / cell_m_)));
    return static_cast<std::size_t>((c[0] * dims_[1] + c[1]) * dims_[2] + c[2]);
  };
  std::vector<std::size_t> cell(points.size());
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t i = 0; i < points.size(); ++i) { cell[i] = cell_of(points[i]); ++cell_start_[cell[i] + 1]; }
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  points_.resize(points.size());
  std::vector<std::size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) points_[fill[cell[i]]++] = points[i];
}

double ClearedRegion::nearest_sq(const Vec3& p) const {
  // Rings of cells around p's cell in growing Chebyshev radius; a point in ring k is at
  // least (k - 1) cells away, so stop once that exceeds the best distance or the pad.
  long long c[3];
  for (int k = 0; k < 3; ++k) {
    const double f = std::floor((p[k] - lo_[k]) / cell_m_);
    c[k] = static_cast<long long>(std::max(-1e9, std::min(1e9, f)));
  }
  double best = kInfinity;
  const long long max_ring = static_cast<long long>(std::ceil(pad_ / cell_m_)) + 1;
  for (long long ring = 0; ring <= max_ring; ++ring) {
    const double reach = static_cast<double>(ring - 1) * cell_m_;
    if (ring > 0 && reach > 0.0 && reach * reach > best) break;
    long long lo[3], hi[3];
    bool any = true;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0LL, c[k] - ring);
      hi[k] = std::min(dims_[k] - 1, c[k] + ring);
      if (lo[k] > hi[k]) any = false;
    }
    if (!any) continue;
    for (long long i = lo[0]; i <= hi[0]; ++i)
      for (long long j = lo[1]; j <= hi[1]; ++j)
        for (long long k = lo[2]; k <= hi[2]; ++k) {
          const bool shell = std::llabs(i - c[0]) == ring || std::llabs(j - c[1]) == ring ||
                             std::llabs(k - c[2]) == ring;
          if (!shell) continue;
          const std::size_t cell = static_cast<std::size_t>((i * dims_[1] + j) * dims_[2] + k);
          for (std::size_t n = cell_start_[cell]; n < cell_start_[cell + 1]; ++n) {
            const Vec3& q = points_[n];
            const double dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
            const double d = dx * dx + dy * dy + dz * dz;
            if (d < best) best = d;
          }
        }
  }
  return best;
}

double ClearedRegion::distance(const Vec3& p) const {
  if (points_.empty()) return kInfinity;
  const double sq = nearest_sq(p);
  if (!(sq < kInfinity)) return kInfinity;
  const double d = std::sqrt(sq);
  if (!(d < pad_)) return kInfinity;  // scipy's distance_upper_bound excludes farther points
  return (d - fine_) + inflation_;
}

}  // namespace grasp_core

namespace grasp_core {

bool ClearedRegion::blocked(const Vec3& p, double threshold) const {
  if (points_.empty()) return false;
  // a failing point has d < threshold - inflation + fine (plus rounding) and d < pad
  const double reach = std::min(pad_, threshold - inflation_ + fine_ + 1e-9);
  if (!(reach > 0.0)) return false;
  long long lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double a = std::floor((p[k] - reach - lo_[k]) / cell_m_);
    const double b = std::floor((p[k] + reach - lo_[k]) / cell_m_);
    if (!(b >= 0.0) || a > static_cast<double>(dims_[k] - 1)) return false;  // no cell in reach
    lo[k] = a < 0.0 ? 0 : static_cast<long long>(a);
    hi[k] = std::min(dims_[k] - 1, static_cast<long long>(b));
  }
  const double reach_sq = reach * reach * (1.0 + 1e-12);
  for (long long i = lo[0]; i <= hi[0]; ++i)
    for (long long j = lo[1]; j <= hi[1]; ++j)
      for (long long k = lo[2]; k <= hi[2]; ++k) {
        const std::size_t cell = static_cast<std::size_t>((i * dims_[1] + j) * dims_[2] + k);
        for (std::size_t n = cell_start_[cell]; n < cell_start_[cell + 1]; ++n) {
          const Vec3& q = points_[n];
          const double dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
          const double sq = dx * dx + dy * dy + dz * dz;
          if (!(sq <= reach_sq)) continue;
          const double d = std::sqrt(sq);
          if (d < pad_ && ((d - fine_) + inflation_) - threshold < 0.0) return true;
        }
      }
  return false;
}

}  // namespace grasp_core
