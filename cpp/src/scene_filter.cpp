// SPEC 1.2–1.5 — the per-frame scene filter. See scene_filter.hpp.
//
// Data path per frame (no PCL cloud of the whole frame is ever built):
//   1. one pass over the caller's strided rows: drop NaN/Inf rows and rows beyond the
//      coordinate bound (max_abs_coordinate_m), pack the valid points as contiguous
//      floats (separate x, y, z arrays);
//   2. sequential extraction: each plane searches a <= plane_fit_max_points subsample
//      (PCL RANSAC, plane_fit.cpp), then one tight loop counts its inliers on the whole
//      packed cloud and another drops them from the remainder;
//   3. table choice, persistence update;
//   4. band split into a packed candidate array, Euclidean clustering (clustering.cpp),
//      labels mapped back to the input rows.
#include "grasp_core/scene_filter.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

namespace grasp_core {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// SplitMix64 step: derives independent seeds from (seed, stream).
std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// Valid rows of a frame packed as separate x, y, z arrays (structure of arrays, so the
/// per-point loops over the whole frame vectorise). Valid = finite and every |coordinate|
/// <= max_abs_coordinate_m.
struct Packed {
  // Uninitialised storage: every used slot is written before it is read (saves zeroing
  // ~5 MB per 640x480 frame).
  std::unique_ptr<float[]> x, y, z;
  std::unique_ptr<int[]> rows;  ///< input row of each valid point
  std::size_t n = 0;            ///< number of valid points
  std::size_t out_of_range = 0; ///< finite rows dropped by the coordinate bound
  std::size_t size() const { return n; }
};

template <typename T>
Packed pack_finite(const T* xyz, std::size_t n_rows, std::size_t stride, double bound) {
  if (n_rows > 0 && xyz == nullptr) throw std::invalid_argument("scene filter: null point buffer");
  if (n_rows > 0 && stride < 3) throw std::invalid_argument("scene filter: row stride must be >= 3");
  if (n_rows > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("scene filter: too many points");
  Packed out;
  out.x.reset(new float[n_rows + 1]);
  out.y.reset(new float[n_rows + 1]);
  out.z.reset(new float[n_rows + 1]);
  out.rows.reset(new int[n_rows + 1]);
  std::size_t m = 0, oor = 0;
  for (std::size_t i = 0; i < n_rows; ++i) {
    const T* p = xyz + i * stride;
    // Checked on the input values (a double beyond float range is out of range, not
    // non-finite), before the cast to float.
    const bool fin = std::isfinite(p[0]) & std::isfinite(p[1]) & std::isfinite(p[2]);
    const bool in = within_bound(p[0], p[1], p[2], bound);  // false for NaN/Inf too
    // Branch-free: always write slot m, keep it only if the row is valid.
    out.x[m] = static_cast<float>(p[0]);
    out.y[m] = static_cast<float>(p[1]);
    out.z[m] = static_cast<float>(p[2]);
    out.rows[m] = static_cast<int>(i);
    m += in ? 1 : 0;
    oor += (fin && !in) ? 1 : 0;
  }
  out.n = m;
  out.out_of_range = oor;
  return out;
}

/// Plane coefficients in float for the tight loops over the whole cloud.
struct PlaneF {
  float nx, ny, nz, c;
  explicit PlaneF(const Plane& p)
      : nx(static_cast<float>(p.n.x())), ny(static_cast<float>(p.n.y())),
        nz(static_cast<float>(p.n.z())), c(static_cast<float>(p.c)) {}
};

/// inlier[i] = |d(p_i)| < tau for every packed point; returns the count.
int mark_inliers(const Packed& pk, const PlaneF& pf, float tau, std::vector<std::uint8_t>& inlier) {
  const std::size_t n = pk.size();
  inlier.resize(n);
  const float* x = pk.x.get();
  const float* y = pk.y.get();
  const float* z = pk.z.get();
  std::uint8_t* out = inlier.data();
  for (std::size_t i = 0; i < n; ++i)
    out[i] = std::abs(pf.nx * x[i] + pf.ny * y[i] + pf.nz * z[i] + pf.c) < tau ? 1 : 0;
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) count += out[i];
  return count;
}

/// SPEC 1.2 on packed finite points.
std::vector<PlaneCandidate> extract_packed(const Packed& pk, const SceneFilterParams& params,
                                           std::uint64_t seed) {
  std::vector<PlaneCandidate> planes;
  const std::size_t n = pk.size();
  std::vector<int> remainder(n);
  for (std::size_t i = 0; i < n; ++i) remainder[i] = static_cast<int>(i);
  const float tau = static_cast<float>(params.plane_dist_thresh);
  std::vector<std::uint8_t> inlier;
  PointsD sub;

  for (int k = 0; k < params.plane_max_count && remainder.size() >= 3; ++k) {
    // Subsample without replacement: partial Fisher-Yates over the remainder (its order
    // is irrelevant: it is filtered, not indexed, afterwards).
    std::mt19937_64 rng(derive_seed(seed, 2 * static_cast<std::uint64_t>(k)));
    const std::size_t r = remainder.size();
    const std::size_t m = std::min(r, static_cast<std::size_t>(params.plane_fit_max_points));
    if (m < r) {
      for (std::size_t i = 0; i < m; ++i) {
        std::uniform_int_distribution<std::size_t> pick(i, r - 1);
        std::swap(remainder[i], remainder[pick(rng)]);
      }
    }
    sub.resize(static_cast<Eigen::Index>(m), 3);
    for (std::size_t i = 0; i < m; ++i) {
      const auto j = static_cast<std::size_t>(remainder[i]);
      sub.row(static_cast<Eigen::Index>(i)) << pk.x[j], pk.y[j], pk.z[j];
    }
    const std::optional<PlaneFit> fit =
        fit_plane_ransac(sub, params, derive_seed(seed, 2 * static_cast<std::uint64_t>(k) + 1));
    if (!fit) break;
    if (static_cast<double>(fit->inliers) < params.plane_min_inlier_ratio * static_cast<double>(m))
      break;

    PlaneCandidate cand;
    cand.plane = fit->plane;
    cand.subsample_inliers = fit->inliers;
    cand.subsample_size = static_cast<int>(m);
    cand.refined = fit->refined;
    // SPEC `count`: on the whole frame cloud, never on the shrinking remainder.
    cand.count_whole = mark_inliers(pk, PlaneF(fit->plane), tau, inlier);
    // Drop the plane's inliers from the whole remainder (not only from the subsample).
    // (Branch-free compaction: inliers are interleaved with the rest at random.)
    const std::size_t before = remainder.size();
    std::size_t kept = 0;
    for (std::size_t j = 0; j < before; ++j) {
      const int i = remainder[j];
      remainder[kept] = i;
      kept += inlier[static_cast<std::size_t>(i)] ^ 1u;
    }
    remainder.resize(kept);
    cand.removed = static_cast<int>(before - kept);
    planes.push_back(cand);
  }
  return planes;
}

template <typename T>
std::vector<PlaneCandidate> extract_any(const T* xyz, std::size_t n_rows, std::size_t stride,
                                        const SceneFilterParams& params, std::uint64_t seed) {
  params.validate();
  return extract_packed(pack_finite(xyz, n_rows, stride, params.max_abs_coordinate_m), params, seed);
}

}  // namespace

std::vector<PlaneCandidate> extract_planes(const float* xyz, std::size_t n_rows,
                                           std::size_t row_stride_floats,
                                           const SceneFilterParams& params, std::uint64_t seed) {
  return extract_any(xyz, n_rows, row_stride_floats, params, seed);
}

std::vector<PlaneCandidate> extract_planes(const PointsF& points, const SceneFilterParams& params,
                                           std::uint64_t seed) {
  return extract_any(points.data(), static_cast<std::size_t>(points.rows()), 3, params, seed);
}

std::vector<PlaneCandidate> extract_planes(const PointsD& points, const SceneFilterParams& params,
                                           std::uint64_t seed) {
  return extract_any(points.data(), static_cast<std::size_t>(points.rows()), 3, params, seed);
}

int choose_table(const std::vector<PlaneCandidate>& planes, double dominance) {
  int max_count = 0;
  for (const auto& p : planes) max_count = std::max(max_count, p.count_whole);
  int best = -1;
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const auto& p = planes[k];
    if (static_cast<double>(p.count_whole) < dominance * static_cast<double>(max_count)) continue;
    if (best < 0 || p.plane.height_m() > planes[static_cast<std::size_t>(best)].plane.height_m())
      best = static_cast<int>(k);
  }
  return best;
}

// ---------------------------------------------------------------------------------------

SceneFilter::SceneFilter(const SceneFilterParams& params)
    : params_(params), persistence_(params) {
  params_.validate();
}

void SceneFilter::reset() {
  persistence_.reset();
  frame_index_ = 0;
  out_of_range_reported_ = false;
}

namespace {

/// Steps 2–4 of the data path for one packed frame; `frame_seed` drives the plane search.
/// The out-of-range drop as an event: WARNING the first time in a session, DEBUG after.
void report_out_of_range(const Packed& pk, const SceneFilterParams& params, bool& reported,
                         std::vector<FrameEvent>& events) {
  if (pk.out_of_range == 0) return;
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "dropped %zu point(s) with a coordinate beyond +-%g m (max_abs_coordinate_m); "
                "they are labelled invalid like NaN rows%s",
                pk.out_of_range, params.max_abs_coordinate_m,
                reported ? "" : " (reported once per session; later frames log at debug level)");
  events.push_back(FrameEvent{reported ? FrameEvent::Level::kDebug : FrameEvent::Level::kWarning, buf});
  reported = true;
}

SceneFilterResult run_frame(const Packed& pk, std::size_t n_rows,
                            const SceneFilterParams& params, PlanePersistence& persistence,
                            std::uint64_t frame_seed, Clock::time_point t0, bool& oor_reported) {
  SceneFilterResult res;
  res.band = params.band;
  res.max_abs_coordinate_m = params.max_abs_coordinate_m;
  const std::size_t n_valid = pk.size();
  res.num_valid = static_cast<int>(n_valid);
  res.num_invalid = static_cast<int>(n_rows - n_valid);
  res.num_out_of_range = static_cast<int>(pk.out_of_range);
  report_out_of_range(pk, params, oor_reported, res.events);
  res.labels.assign(n_rows, kLabelInvalid);
  for (std::size_t i = 0; i < n_valid; ++i) res.labels[static_cast<std::size_t>(pk.rows[i])] = kLabelEnvironment;

  // Planes, table choice, persistence.
  const auto t_plane = Clock::now();
  res.planes = extract_packed(pk, params, frame_seed);
  res.table_index = choose_table(res.planes, params.plane_dominance);
  if (res.table_index >= 0) res.fit = res.planes[static_cast<std::size_t>(res.table_index)].plane;
  PersistenceUpdate upd = persistence.update(res.fit);
  res.table = upd.table;
  res.environment_emitted = upd.environment_emitted;
  res.fallback = upd.fallback;
  res.decision = upd.decision;
  res.events.insert(res.events.end(), upd.events.begin(), upd.events.end());
  res.persistence = persistence.state();
  res.ms_plane = ms_since(t_plane);

  // Band split and clustering (only with a table plane; the fallback has no objects).
  const auto t_cluster = Clock::now();
  if (res.table && !res.fallback) {
    const PlaneF pf(*res.table);
    const float band = static_cast<float>(params.band);
    // Above the band: candidate. Below the plane and within the band: environment.
    std::vector<std::uint8_t> above(n_valid);
    for (std::size_t i = 0; i < n_valid; ++i)
      above[i] = pf.nx * pk.x[i] + pf.ny * pk.y[i] + pf.nz * pk.z[i] + pf.c > band ? 1 : 0;
    std::size_t n_cand = 0;
    for (std::size_t i = 0; i < n_valid; ++i) n_cand += above[i];
    std::vector<float> cand_xyz(3 * n_cand + 3);  // +1 slot: branch-free writes below
    std::vector<int> cand_rows(n_cand + 1);
    std::size_t w = 0;
    for (std::size_t i = 0; i < n_valid; ++i) {
      cand_xyz[3 * w] = pk.x[i];
      cand_xyz[3 * w + 1] = pk.y[i];
      cand_xyz[3 * w + 2] = pk.z[i];
      cand_rows[w] = pk.rows[i];
      w += above[i];
      if (w == n_cand) break;  // keeps the spare slot as the only overflow target
    }
    cand_rows.resize(n_cand);
    res.num_candidates = static_cast<int>(cand_rows.size());
    const ClusterResult cl = euclidean_clusters(
        cand_xyz.data(), cand_rows.size(), 3, params.cluster_eps, params.cluster_min_points,
        params.cluster_min_extent, params.cluster_max_extent, params.cluster_voxel_m,
        params.max_abs_coordinate_m);
    for (std::size_t k = 0; k < cand_rows.size(); ++k)
      res.labels[static_cast<std::size_t>(cand_rows[k])] = cl.labels[k];
    for (int id = 0; id < cl.num_accepted; ++id) res.cluster_ids.push_back(id);
    res.clusters = cl.clusters;
  }
  res.ms_cluster = ms_since(t_cluster);
  res.ms_total = ms_since(t0);
  return res;
}

}  // namespace

SceneFilterResult SceneFilter::process(const float* xyz, std::size_t n_rows, std::size_t row_stride) {
  const auto t0 = Clock::now();
  const Packed pk = pack_finite(xyz, n_rows, row_stride, params_.max_abs_coordinate_m);
  return run_frame(pk, n_rows, params_, persistence_, next_frame_seed(), t0, out_of_range_reported_);
}

SceneFilterResult SceneFilter::process(const double* xyz, std::size_t n_rows, std::size_t row_stride) {
  const auto t0 = Clock::now();
  const Packed pk = pack_finite(xyz, n_rows, row_stride, params_.max_abs_coordinate_m);
  return run_frame(pk, n_rows, params_, persistence_, next_frame_seed(), t0, out_of_range_reported_);
}

std::uint64_t SceneFilter::next_frame_seed() {
  return derive_seed(params_.seed, static_cast<std::uint64_t>(frame_index_++));
}

SceneFilterResult SceneFilter::process(const PointsF& points) {
  return process(points.data(), static_cast<std::size_t>(points.rows()), 3);
}

SceneFilterResult SceneFilter::process(const PointsD& points) {
  return process(points.data(), static_cast<std::size_t>(points.rows()), 3);
}

}  // namespace grasp_core
