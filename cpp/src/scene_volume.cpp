// (ours) The scene volume: projective log-odds occupancy (see scene_volume.hpp).
#include "grasp_core/scene_volume.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace grasp_core {

namespace {

constexpr double kMaxBoxCoordinate_m = kDefaultMaxAbsCoordinate_m;
/// Voxels nearer the camera than this along the optical axis are not projected.
constexpr double kNearZ_m = 1e-3;

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

/// Shrink [*lo, *hi] to the integers k with a + b k >= 0.
void clip_linear(double a, double b, int* lo, int* hi) {
  if (std::abs(b) < 1e-12) {
    if (a < 0) *hi = *lo - 1;
    return;
  }
  const double r = -a / b;
  if (b > 0) {
    const double k = std::ceil(r - 1e-9);
    if (k > *lo) *lo = k > *hi ? *hi + 1 : static_cast<int>(k);
  } else {
    const double k = std::floor(r + 1e-9);
    if (k < *hi) *hi = k < *lo ? *lo - 1 : static_cast<int>(k);
  }
}

void check_camera(const PinholeCamera& c) {
  if (c.width <= 0 || c.height <= 0) fail("depth image: expected a positive size, got " +
                                          num(c.height) + " x " + num(c.width));
  if (!(std::isfinite(c.fx) && std::isfinite(c.fy) && c.fx > 0 && c.fy > 0))
    fail("K: the focal lengths fx, fy must be finite and > 0");
  if (!(std::isfinite(c.cx) && std::isfinite(c.cy))) fail("K: cx, cy must be finite");
}

void check_pose(const Pose& T) {
  if (!T.R.allFinite() || !T.t.allFinite()) fail("T_world_camera: must be finite, got NaN/Inf");
  if (std::abs(T.R.determinant() - 1.0) > 1e-6 || !(T.R.transpose() * T.R).isIdentity(1e-6))
    fail("T_world_camera: the 3x3 block must be a rotation (orthonormal, det +1)");
}

void check_box(const Vec3& lo, const Vec3& hi, const char* what) {
  if (!lo.allFinite() || !hi.allFinite()) fail(std::string(what) + ": must be finite");
  if (lo.cwiseAbs().maxCoeff() > kMaxBoxCoordinate_m || hi.cwiseAbs().maxCoeff() > kMaxBoxCoordinate_m)
    fail(std::string(what) + ": coordinates must be within +-" + num(kMaxBoxCoordinate_m) + " m");
}

}  // namespace

void SceneVolumeParams::validate() const {
  check_box(box_min_m, box_max_m, "SceneVolumeParams.box_min_m/box_max_m");
  if (!(voxel_m >= 0.001 && voxel_m <= 0.1))
    fail("SceneVolumeParams.voxel_m: expected [0.001, 0.1] m, got " + num(voxel_m));
  for (int a = 0; a < 3; ++a)
    if (!(box_max_m[a] - box_min_m[a] >= voxel_m))
      fail("SceneVolumeParams.box_max_m: must exceed box_min_m by at least one voxel on every axis");
  if (!(truncation_m >= 0.5 * voxel_m && truncation_m <= 1.0))
    fail("SceneVolumeParams.truncation_m: expected [voxel_m / 2, 1] m, got " + num(truncation_m));
  if (!(logodds_hit > 0 && std::isfinite(logodds_hit)))
    fail("SceneVolumeParams.logodds_hit: expected a finite value > 0");
  if (!(logodds_miss < 0 && std::isfinite(logodds_miss)))
    fail("SceneVolumeParams.logodds_miss: expected a finite value < 0");
  if (!(logodds_max >= logodds_hit && std::isfinite(logodds_max)))
    fail("SceneVolumeParams.logodds_max: expected a finite value >= logodds_hit");
  if (!(logodds_min <= logodds_miss && std::isfinite(logodds_min)))
    fail("SceneVolumeParams.logodds_min: expected a finite value <= logodds_miss");
  double count = 1.0;
  for (int a = 0; a < 3; ++a) count *= std::ceil((box_max_m[a] - box_min_m[a]) / voxel_m - 1e-9);
  if (count > static_cast<double>(kMaxVolumeVoxels))
    fail("SceneVolumeParams: the box holds " + num(count) + " voxels, over the limit of " +
         num(static_cast<double>(kMaxVolumeVoxels)) + "; use a smaller box or larger voxels");
}

SceneVolume::SceneVolume(const SceneVolumeParams& params) : params_(params) {
  params_.validate();
  origin_ = params_.box_min_m;
  const Vec3 size = params_.box_max_m - params_.box_min_m;
  nx_ = static_cast<int>(std::ceil(size.x() / params_.voxel_m - 1e-9));
  ny_ = static_cast<int>(std::ceil(size.y() / params_.voxel_m - 1e-9));
  nz_ = static_cast<int>(std::ceil(size.z() / params_.voxel_m - 1e-9));
  logodds_.assign(static_cast<std::size_t>(nx_) * ny_ * nz_, std::numeric_limits<float>::quiet_NaN());
}

Vec3 SceneVolume::box_max() const {
  return origin_ + params_.voxel_m * Vec3(nx_, ny_, nz_);
}

Vec3 SceneVolume::centre(int ix, int iy, int iz) const {
  return origin_ + params_.voxel_m * Vec3(ix + 0.5, iy + 0.5, iz + 0.5);
}

bool SceneVolume::cell_of(const Vec3& p, int* ix, int* iy, int* iz) const {
  if (!p.allFinite()) return false;
  const Vec3 f = (p - origin_) / params_.voxel_m;
  const int n[3] = {nx_, ny_, nz_};
  int* out[3] = {ix, iy, iz};
  for (int a = 0; a < 3; ++a) {
    const double c = std::floor(f[a]);
    if (!(c >= 0 && c < n[a])) return false;
    *out[a] = static_cast<int>(c);
  }
  return true;
}

bool SceneVolume::occupied_at(std::size_t i) const {
  return logodds_[i] > 0.f;  // NaN (unknown) compares false
}

SceneVolume::IndexRange SceneVolume::cells_in(const Vec3& lo, const Vec3& hi) const {
  IndexRange r{{0, 0, 0}, {-1, -1, -1}, true};
  const int n[3] = {nx_, ny_, nz_};
  for (int a = 0; a < 3; ++a) {
    const double l = std::ceil((lo[a] - origin_[a]) / params_.voxel_m - 0.5);
    const double h = std::floor((hi[a] - origin_[a]) / params_.voxel_m - 0.5);
    const double cl = std::max(l, 0.0), ch = std::min(h, n[a] - 1.0);
    if (!(cl <= ch)) return r;
    r.lo[a] = static_cast<int>(cl);
    r.hi[a] = static_cast<int>(ch);
  }
  r.empty = false;
  return r;
}

VolumeIntegration SceneVolume::integrate(const float* depth, const PinholeCamera& cam,
                                         std::size_t row_stride, const Pose& T, double max_range_m) {
  const auto t_start = std::chrono::steady_clock::now();
  check_camera(cam);
  check_pose(T);
  if (depth == nullptr) fail("depth image: null buffer");
  if (row_stride < static_cast<std::size_t>(cam.width)) fail("depth image: row stride below the width");
  if (!(max_range_m > 0 && std::isfinite(max_range_m))) fail("max_range_m: expected a finite value > 0");
  VolumeIntegration out;
  ++frames_;
  const float max_range = static_cast<float>(max_range_m);
  float dmax = 0.f;
  for (int v = 0; v < cam.height; ++v) {
    const float* row = depth + static_cast<std::size_t>(v) * row_stride;
    for (int u = 0; u < cam.width; ++u) {
      const float d = row[u];
      if (d > 0.f && d <= max_range) {  // NaN compares false
        ++out.valid_pixels;
        dmax = std::max(dmax, d);
      }
    }
  }
  auto finish = [&]() {
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
    return out;
  };
  if (out.valid_pixels == 0) return finish();
  const double trunc = params_.truncation_m, far = dmax + trunc;
  const double W = cam.width, H = cam.height;
  // World bounding box of the frustum up to `far`: the camera centre and the far corners.
  Vec3 lo = T.t, hi = T.t;
  for (double u : {-0.5, W - 0.5})
    for (double v : {-0.5, H - 0.5}) {
      const Vec3 pw = T.R * Vec3((u - cam.cx) / cam.fx * far, (v - cam.cy) / cam.fy * far, far) + T.t;
      lo = lo.cwiseMin(pw);
      hi = hi.cwiseMax(pw);
    }
  const IndexRange r = cells_in(lo, hi);
  if (r.empty) return finish();
  const Mat3 Rcw = T.R.transpose();
  const Vec3 tcw = -Rcw * T.t;
  const Vec3 dx = Rcw.col(0) * params_.voxel_m;  // camera-frame step of one voxel along world x
  const double fx = cam.fx, fy = cam.fy, cx = cam.cx, cy = cam.cy;
  const float hit = static_cast<float>(params_.logodds_hit), miss = static_cast<float>(params_.logodds_miss);
  const float lmin = static_cast<float>(params_.logodds_min), lmax = static_cast<float>(params_.logodds_max);
  for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz) {
    for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy) {
      const Vec3 p0 = Rcw * centre(r.lo[0], iy, iz) + tcw;
      int klo = 0, khi = r.hi[0] - r.lo[0];
      // The row's voxels inside the frustum: each bound is linear in k (a + b k >= 0).
      clip_linear(p0.z() - kNearZ_m, dx.z(), &klo, &khi);
      clip_linear(far - p0.z(), -dx.z(), &klo, &khi);
      clip_linear(fx * p0.x() + (cx + 0.5) * p0.z(), fx * dx.x() + (cx + 0.5) * dx.z(), &klo, &khi);
      clip_linear((W - 0.5 - cx) * p0.z() - fx * p0.x(), (W - 0.5 - cx) * dx.z() - fx * dx.x(), &klo, &khi);
      clip_linear(fy * p0.y() + (cy + 0.5) * p0.z(), fy * dx.y() + (cy + 0.5) * dx.z(), &klo, &khi);
      clip_linear((H - 0.5 - cy) * p0.z() - fy * p0.y(), (H - 0.5 - cy) * dx.z() - fy * dx.y(), &klo, &khi);
      float* cells = logodds_.data() + index(r.lo[0], iy, iz);
      for (int k = klo; k <= khi; ++k) {
        const double x = p0.x() + k * dx.x(), y = p0.y() + k * dx.y(), z = p0.z() + k * dx.z();
        if (!(z > kNearZ_m)) continue;
        const double inv = 1.0 / z;
        const double fu = fx * x * inv + cx + 0.5, fv = fy * y * inv + cy + 0.5;  // nearest pixel + 0.5
        if (!(fu >= 0.0 && fv >= 0.0)) continue;  // (a truncating cast is floor from here on)
        const int u = static_cast<int>(fu), v = static_cast<int>(fv);
        if (u >= cam.width || v >= cam.height) continue;
        ++out.voxels_in_view;
        const float d = depth[static_cast<std::size_t>(v) * row_stride + u];
        if (!(d > 0.f && d <= max_range)) continue;
        const double diff = d - z;  // > 0: the voxel is in front of the measured surface
        float delta;
        if (diff > trunc) {
          delta = miss;
          ++out.voxels_free;
        } else if (diff >= -trunc) {
          delta = hit;
          ++out.voxels_occupied;
        } else {
          continue;
        }
        float& l = cells[k];
        const float base = std::isnan(l) ? 0.f : l;
        l = std::min(lmax, std::max(lmin, base + delta));
      }
    }
  }
  return finish();
}

void SceneVolume::classify(const double* xyz, std::size_t n, std::size_t stride, std::int8_t* out) const {
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = xyz + i * stride;
    int ix, iy, iz;
    if (!cell_of(Vec3(p[0], p[1], p[2]), &ix, &iy, &iz)) {
      out[i] = static_cast<std::int8_t>(VoxelState::kOutside);
      continue;
    }
    const float l = logodds_[index(ix, iy, iz)];
    out[i] = static_cast<std::int8_t>(std::isnan(l) ? VoxelState::kUnknown
                                      : l > 0.f    ? VoxelState::kOccupied
                                                   : VoxelState::kFree);
  }
}

std::vector<Vec3> SceneVolume::occupied_centres(const Vec3& lo, const Vec3& hi) const {
  check_box(lo, hi, "box_min/box_max");
  std::vector<Vec3> out;
  const IndexRange r = cells_in(lo, hi);
  if (r.empty) return out;
  for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz)
    for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy)
      for (int ix = r.lo[0]; ix <= r.hi[0]; ++ix)
        if (occupied_at(index(ix, iy, iz))) out.push_back(centre(ix, iy, iz));
  return out;
}

void SceneVolume::states_in_box(const Vec3& lo, const Vec3& hi, std::vector<Vec3>* centres,
                                std::vector<std::int8_t>* states) const {
  check_box(lo, hi, "box_min/box_max");
  centres->clear();
  states->clear();
  const IndexRange r = cells_in(lo, hi);
  if (r.empty) return;
  for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz)
    for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy)
      for (int ix = r.lo[0]; ix <= r.hi[0]; ++ix) {
        const float l = logodds_[index(ix, iy, iz)];
        centres->push_back(centre(ix, iy, iz));
        states->push_back(static_cast<std::int8_t>(std::isnan(l) ? VoxelState::kUnknown
                                                   : l > 0.f    ? VoxelState::kOccupied
                                                                : VoxelState::kFree));
      }
}

VolumeCounts SceneVolume::count_states(const Vec3& lo, const Vec3& hi) const {
  check_box(lo, hi, "box_min/box_max");
  VolumeCounts c;
  double total = 1.0;  // lattice cells of the query box, inside the grid or not
  for (int a = 0; a < 3; ++a) {
    const double l = std::ceil((lo[a] - origin_[a]) / params_.voxel_m - 0.5);
    const double h = std::floor((hi[a] - origin_[a]) / params_.voxel_m - 0.5);
    total *= std::max(0.0, h - l + 1.0);
  }
  const IndexRange r = cells_in(lo, hi);
  if (!r.empty) {
    for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz)
      for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy)
        for (int ix = r.lo[0]; ix <= r.hi[0]; ++ix) {
          const float l = logodds_[index(ix, iy, iz)];
          if (std::isnan(l)) ++c.unknown;
          else if (l > 0.f) ++c.occupied;
          else ++c.free;
        }
  }
  c.outside = static_cast<std::int64_t>(total) - (c.unknown + c.free + c.occupied);
  return c;
}

bool SceneVolume::ray_blocked(const Vec3& from, const Vec3& to) const {
  const Vec3 d = to - from;
  const Vec3 top = box_max();
  double t0 = 0.0, t1 = 1.0;  // the part of the segment inside the grid
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (from[a] < origin_[a] || from[a] > top[a]) return false;
      continue;
    }
    double ta = (origin_[a] - from[a]) / d[a], tb = (top[a] - from[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  int target[3] = {-1, -1, -1};
  cell_of(to, &target[0], &target[1], &target[2]);
  const Vec3 p = from + t0 * d;
  const int n[3] = {nx_, ny_, nz_};
  const double vox = params_.voxel_m;
  int c[3], step[3];
  double tmax[3], tdelta[3];
  for (int a = 0; a < 3; ++a) {
    c[a] = std::min(n[a] - 1, std::max(0, static_cast<int>(std::floor((p[a] - origin_[a]) / vox))));
    if (d[a] > 0) {
      step[a] = 1;
      tmax[a] = (origin_[a] + (c[a] + 1) * vox - from[a]) / d[a];
      tdelta[a] = vox / d[a];
    } else if (d[a] < 0) {
      step[a] = -1;
      tmax[a] = (origin_[a] + c[a] * vox - from[a]) / d[a];
      tdelta[a] = -vox / d[a];
    } else {
      step[a] = 0;
      tmax[a] = tdelta[a] = std::numeric_limits<double>::infinity();
    }
  }
  while (true) {
    if (c[0] == target[0] && c[1] == target[1] && c[2] == target[2]) return false;
    if (occupied_at(index(c[0], c[1], c[2]))) return true;
    const int a = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
    if (tmax[a] > t1) return false;
    c[a] += step[a];
    if (c[a] < 0 || c[a] >= n[a]) return false;
    tmax[a] += tdelta[a];
  }
}

std::vector<std::uint8_t> SceneVolume::visible(const double* xyz, std::size_t n, std::size_t stride,
                                               const PinholeCamera& cam, const Pose& T,
                                               double min_range_m, double max_range_m) const {
  check_camera(cam);
  check_pose(T);
  if (!(min_range_m >= 0 && max_range_m > min_range_m && std::isfinite(max_range_m)))
    fail("min_range_m/max_range_m: expected 0 <= min_range_m < max_range_m, finite");
  const Mat3 Rcw = T.R.transpose();
  const Vec3 tcw = -Rcw * T.t;
  std::vector<std::uint8_t> out(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double* q = xyz + i * stride;
    const Vec3 p(q[0], q[1], q[2]);
    if (!p.allFinite()) continue;
    const Vec3 pc = Rcw * p + tcw;
    if (!(pc.z() >= min_range_m && pc.z() <= max_range_m)) continue;
    const double u = cam.fx * pc.x() / pc.z() + cam.cx, v = cam.fy * pc.y() / pc.z() + cam.cy;
    if (!(u >= -0.5 && u < cam.width - 0.5 && v >= -0.5 && v < cam.height - 0.5)) continue;
    out[i] = ray_blocked(T.t, p) ? 0 : 1;
  }
  return out;
}

void SceneVolume::reset() {
  std::fill(logodds_.begin(), logodds_.end(), std::numeric_limits<float>::quiet_NaN());
  frames_ = 0;
}

void SceneVolume::reset_box(const Vec3& lo, const Vec3& hi) {
  check_box(lo, hi, "box_min/box_max");
  const IndexRange r = cells_in(lo, hi);
  if (r.empty) return;
  for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz)
    for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy)
      std::fill_n(logodds_.begin() + static_cast<std::ptrdiff_t>(index(r.lo[0], iy, iz)),
                  r.hi[0] - r.lo[0] + 1, std::numeric_limits<float>::quiet_NaN());
}

}  // namespace grasp_core
