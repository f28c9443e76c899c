// method.md §1.2–1.5 — the per-frame scene filter. See scene_filter.hpp.
//
// Data path per frame (no PCL cloud of the whole frame is ever built; the whole-frame
// arrays live in the filter's SceneFilterWorkspace and are reused from frame to frame):
//   1. one pass over the caller's rows: drop NaN/Inf rows and rows beyond the coordinate
//      bound (max_abs_coordinate_m), pack the valid points as contiguous floats (separate
//      x, y, z arrays) and label the dropped rows invalid (all-valid blocks of a float32
//      (N, 3) array are checked by one vectorised test and copied without compaction);
//   2. sequential extraction: each plane searches a <= plane_fit_max_points subsample
//      (PCL RANSAC, plane_fit.cpp), then one tight loop marks and counts its inliers on the
//      whole packed cloud and another drops them from the remainder;
//   3. table choice, persistence update;
//   4. band split into a packed candidate array (blocks without a point above the band are
//      skipped after a vectorised count), Euclidean clustering (clustering.cpp), labels
//      mapped back to the input rows.
// The loops over the whole frame are built as AVX2 + baseline clones (simd_clones.hpp).
#include "grasp_core/scene_filter.hpp"
#include "simd_clones.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// The valid rows of a frame packed as separate x, y, z arrays (structure of arrays, so the
/// per-point loops over the whole frame vectorise), in input order. A view into a
/// SceneFilterWorkspace. Valid = finite and every |coordinate| <= max_abs_coordinate_m.
struct Packed {
  const float* x = nullptr;
  const float* y = nullptr;
  const float* z = nullptr;
  const int* rows = nullptr;    ///< input row of each valid point; nullptr: row = index
  int row(std::size_t i) const { return rows ? rows[i] : static_cast<int>(i); }
  std::size_t n = 0;            ///< number of valid points
  std::size_t out_of_range = 0; ///< finite rows dropped by the coordinate bound
  std::size_t size() const { return n; }
};

/// Grow `v` to at least `n` elements (never shrinks: the buffers keep their largest size,
/// so frames of a constant size allocate and initialise nothing).
template <typename V>
void ensure_size(V& v, std::size_t n) {
  if (v.size() < n) v.resize(n);
}

/// The largest float f with f <= bound: for a float x, |x| <= f <=> |double(x)| <= bound,
/// so the coordinate bound can be checked in float on float input, exactly.
float float_at_most(double bound) {
  float f = static_cast<float>(bound);
  if (static_cast<double>(f) > bound) f = std::nextafter(f, 0.0f);
  return f;
}

/// Row validity of method.md §1 (finite, every |coordinate| <= bound), checked on the input values:
/// `in` = valid, `finite` = all three finite (a finite row that is not valid is out of range).
/// Float input is checked in float (exact, see float_at_most), double input in double (a
/// double beyond float range is out of range, not non-finite).
struct RowCheck {
  double bound_d;
  float bound_f;
  explicit RowCheck(double bound) : bound_d(bound), bound_f(float_at_most(bound)) {}
  void operator()(const float* p, bool& in, bool& finite) const {
    const float ax = std::abs(p[0]), ay = std::abs(p[1]), az = std::abs(p[2]);
    constexpr float kMax = std::numeric_limits<float>::max();
    in = (ax <= bound_f) & (ay <= bound_f) & (az <= bound_f);
    finite = (ax <= kMax) & (ay <= kMax) & (az <= kMax);
  }
  void operator()(const double* p, bool& in, bool& finite) const {
    in = within_bound(p[0], p[1], p[2], bound_d);
    finite = std::isfinite(p[0]) & std::isfinite(p[1]) & std::isfinite(p[2]);
  }
};

/// Rows per block of pack_finite's fast path.
constexpr std::size_t kPackBlockRows = 256;

/// True when every value of `count` contiguous floats has |v| <= bound (NaN: false).
/// A flat loop without early exit, so that it vectorises.
GRASP_SIMD_CLONES bool all_within(const float* v, std::size_t count, float bound) {
  unsigned int bad = 0;
  for (std::size_t i = 0; i < count; ++i) bad |= (std::abs(v[i]) <= bound) ? 0u : 1u;
  return bad == 0;
}

/// x[j], y[j], z[j] = xyz[3j], xyz[3j + 1], xyz[3j + 2] for j < count: a plain copy. With
/// SSE2 four rows per step by shuffles (the compiler does not vectorise a stride-3 load).
void deinterleave_xyz(const float* __restrict xyz, std::size_t count, float* __restrict x,
                      float* __restrict y, float* __restrict z) {
  std::size_t j = 0;
#if defined(__SSE2__)
  for (; j + 4 <= count; j += 4) {
    const float* p = xyz + 3 * j;
    const __m128 a = _mm_loadu_ps(p);      // x0 y0 z0 x1
    const __m128 b = _mm_loadu_ps(p + 4);  // y1 z1 x2 y2
    const __m128 c = _mm_loadu_ps(p + 8);  // z2 x3 y3 z3
    const __m128 x01 = _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 3, 3, 0));  // x0 x1 x1 x1
    const __m128 x23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));  // x2 x2 x3 x3
    _mm_storeu_ps(x + j, _mm_shuffle_ps(x01, x23, _MM_SHUFFLE(2, 0, 1, 0)));
    const __m128 y01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1));  // y0 y0 y1 y1
    const __m128 y23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3));  // y2 y2 y3 y3
    _mm_storeu_ps(y + j, _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0)));
    const __m128 z01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2));  // z0 z0 z1 z1
    const __m128 z23 = _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0));  // z2 z2 z3 z3
    _mm_storeu_ps(z + j, _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(2, 0, 2, 0)));
  }
#endif
  for (; j < count; ++j) {
    x[j] = xyz[3 * j];
    y[j] = xyz[3 * j + 1];
    z[j] = xyz[3 * j + 2];
  }
}

/// Pack rows [begin, end) one by one (any stride, any validity), appending at m.
template <typename T>
void pack_rows(const T* xyz, std::size_t begin, std::size_t end, std::size_t stride,
               const RowCheck& check, float* xs, float* ys, float* zs, int* rows, int* labels,
               std::size_t& m, std::size_t& oor) {
  for (std::size_t i = begin; i < end; ++i) {
    const T* p = xyz + i * stride;
    bool in = false, fin = false;
    check(p, in, fin);
    // Branch-free: always write slot m, keep it only if the row is valid.
    xs[m] = static_cast<float>(p[0]);
    ys[m] = static_cast<float>(p[1]);
    zs[m] = static_cast<float>(p[2]);
    rows[m] = static_cast<int>(i);
    if (labels) labels[i] = in ? kLabelEnvironment : kLabelInvalid;
    m += in ? 1 : 0;
    oor += (fin && !in) ? 1 : 0;
  }
}

/// Step 1 of the data path: pack the valid rows into `ws` (x, y, z, rows) in one pass and,
/// when `labels` is given (one per input row, filled with kLabelEnvironment by the caller),
/// label the invalid rows kLabelInvalid in the same pass.
/// Fast path for contiguous float rows (a numpy (N, 3) float32 array): blocks of rows that
/// are all valid (the usual case) are checked with one vectorised test and copied without
/// the per-row compaction; other blocks go row by row. Same result either way.
template <typename T>
Packed pack_finite(const T* xyz, std::size_t n_rows, std::size_t stride, double bound,
                   SceneFilterWorkspace& ws, int* labels) {
  if (n_rows > 0 && xyz == nullptr) throw std::invalid_argument("scene filter: null point buffer");
  if (n_rows > 0 && stride < 3) throw std::invalid_argument("scene filter: row stride must be >= 3");
  if (n_rows > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("scene filter: too many points");
  // +1 slot: the branch-free writes of pack_rows always write slot m.
  ensure_size(ws.x, n_rows + 1);
  ensure_size(ws.y, n_rows + 1);
  ensure_size(ws.z, n_rows + 1);
  ensure_size(ws.rows, n_rows + 1);
  float* xs = ws.x.data();
  float* ys = ws.y.data();
  float* zs = ws.z.data();
  int* rows = ws.rows.data();
  const RowCheck check(bound);
  std::size_t m = 0, oor = 0;
  constexpr bool kFloat = std::is_same_v<T, float>;
  // While every row so far was valid, packed index == input row: `rows` is only written
  // from the first invalid row on (a frame without invalid rows never writes it).
  bool identity_rows = true;
  if (!kFloat || stride != 3) {
    identity_rows = false;
    pack_rows(xyz, 0, n_rows, stride, check, xs, ys, zs, rows, labels, m, oor);
  } else {
    for (std::size_t b = 0; b < n_rows; b += kPackBlockRows) {
      const std::size_t e = std::min(n_rows, b + kPackBlockRows);
      const T* block = xyz + 3 * b;
      if (!all_within(reinterpret_cast<const float*>(block), 3 * (e - b), check.bound_f)) {
        if (identity_rows) {
          for (std::size_t j = 0; j < m; ++j) rows[j] = static_cast<int>(j);
          identity_rows = false;
        }
        pack_rows(xyz, b, e, stride, check, xs, ys, zs, rows, labels, m, oor);
        continue;
      }
      const std::size_t count = e - b;
      deinterleave_xyz(reinterpret_cast<const float*>(block), count, xs + m, ys + m, zs + m);
      if (!identity_rows)
        for (std::size_t j = 0; j < count; ++j) rows[m + j] = static_cast<int>(b + j);
      m += count;  // labels: already kLabelEnvironment
    }
  }
  Packed out;
  out.x = xs;
  out.y = ys;
  out.z = zs;
  out.rows = identity_rows ? nullptr : rows;
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
  /// Signed distance of a packed point, in float (the one expression every loop uses).
  float distance(float x, float y, float z) const { return nx * x + ny * y + nz * z + c; }
};

/// inlier[i] = |d(p_i)| < tau for every packed point; returns the count (one pass).
/// The coefficients are copied into locals and the arrays are restrict-qualified: a byte
/// store may alias anything, which otherwise makes the compiler reload the coefficients
/// for every point and keeps the loop from vectorising.
GRASP_SIMD_CLONES int mark_inliers(const Packed& pk, const PlaneF& pf, float tau,
                                   std::uint8_t* __restrict inlier) {
  const std::size_t n = pk.size();
  const float* __restrict x = pk.x;
  const float* __restrict y = pk.y;
  const float* __restrict z = pk.z;
  const float nx = pf.nx, ny = pf.ny, nz = pf.nz, c = pf.c;
  unsigned int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned int in = std::abs(nx * x[i] + ny * y[i] + nz * z[i] + c) < tau ? 1u : 0u;
    inlier[i] = static_cast<std::uint8_t>(in);
    count += in;
  }
  return static_cast<int>(count);
}

/// method.md §1.2 on packed finite points (buffers: ws.remainder, ws.inlier).
std::vector<PlaneCandidate> extract_packed(const Packed& pk, const SceneFilterParams& params,
                                           std::uint64_t seed, SceneFilterWorkspace& ws) {
  std::vector<PlaneCandidate> planes;
  const std::size_t n = pk.size();
  ensure_size(ws.remainder, n);
  ensure_size(ws.inlier, n);
  int* remainder = ws.remainder.data();
  std::uint8_t* inlier = ws.inlier.data();
  for (std::size_t i = 0; i < n; ++i) remainder[i] = static_cast<int>(i);
  std::size_t r = n;  // remainder size
  const float tau = static_cast<float>(params.plane_dist_thresh);
  PointsD sub;

  for (int k = 0; k < params.plane_max_count && r >= 3; ++k) {
    // Subsample without replacement: partial Fisher-Yates over the remainder (its order
    // is irrelevant: it is filtered, not indexed, afterwards).
    std::mt19937_64 rng(derive_seed(seed, 2 * static_cast<std::uint64_t>(k)));
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
    // method.md §1.2 `count`: on the whole frame cloud, never on the shrinking remainder.
    cand.count_whole = mark_inliers(pk, PlaneF(fit->plane), tau, inlier);
    // Drop the plane's inliers from the whole remainder (not only from the subsample).
    // (Branch-free compaction: inliers are interleaved with the rest at random.)
    const std::size_t before = r;
    std::size_t kept = 0;
    for (std::size_t j = 0; j < before; ++j) {
      const int i = remainder[j];
      remainder[kept] = i;
      kept += inlier[static_cast<std::size_t>(i)] ^ 1u;
    }
    r = kept;
    cand.removed = static_cast<int>(before - kept);
    planes.push_back(cand);
  }
  return planes;
}

template <typename T>
std::vector<PlaneCandidate> extract_any(const T* xyz, std::size_t n_rows, std::size_t stride,
                                        const SceneFilterParams& params, std::uint64_t seed) {
  params.validate();
  SceneFilterWorkspace ws;
  const Packed pk = pack_finite(xyz, n_rows, stride, params.max_abs_coordinate_m, ws, nullptr);
  return extract_packed(pk, params, seed, ws);
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

/// Points per block of split_band's vectorised pre-count.
constexpr std::size_t kBandBlockPoints = 256;

/// Number of points i in [begin, end) strictly above the band: d(p_i) > band.
GRASP_SIMD_CLONES unsigned int count_above(const float* __restrict x, const float* __restrict y,
                                          const float* __restrict z, std::size_t begin,
                                          std::size_t end, const PlaneF& pf, float band) {
  const float nx = pf.nx, ny = pf.ny, nz = pf.nz, c = pf.c;
  unsigned int above = 0;
  for (std::size_t i = begin; i < end; ++i) above += (nx * x[i] + ny * y[i] + nz * z[i] + c > band) ? 1u : 0u;
  return above;
}

/// Band split (method.md §1.4): the valid points strictly above the band w.r.t. `table`, packed
/// interleaved into ws.cand_xyz with their input rows in ws.cand_rows, in input order.
/// Returns their number. Object points are a few percent of a frame: each block is first
/// counted by a vectorised loop and only blocks with candidates are compacted.
std::size_t split_band(const Packed& pk, const Plane& table, double band_m,
                       SceneFilterWorkspace& ws) {
  const std::size_t n = pk.size();
  ensure_size(ws.cand_xyz, 3 * n + 3);  // +1 slot: branch-free writes below
  ensure_size(ws.cand_rows, n + 1);
  float* cand = ws.cand_xyz.data();
  int* cand_rows = ws.cand_rows.data();
  const PlaneF pf(table);
  const float nx = pf.nx, ny = pf.ny, nz = pf.nz, c = pf.c;
  const float band = static_cast<float>(band_m);
  const float* __restrict x = pk.x;
  const float* __restrict y = pk.y;
  const float* __restrict z = pk.z;
  std::size_t w = 0;
  for (std::size_t b = 0; b < n; b += kBandBlockPoints) {
    const std::size_t e = std::min(n, b + kBandBlockPoints);
    if (count_above(x, y, z, b, e, pf, band) == 0) continue;
    for (std::size_t i = b; i < e; ++i) {
      cand[3 * w] = x[i];
      cand[3 * w + 1] = y[i];
      cand[3 * w + 2] = z[i];
      cand_rows[w] = pk.row(i);
      w += (nx * x[i] + ny * y[i] + nz * z[i] + c > band) ? 1 : 0;
    }
  }
  return w;
}

/// The candidates' clusters: organized segmentation when the frame is organized (and the
/// camera position known), else Euclidean clustering; with the camera position the
/// range-dependent minimum object height applies to both.
ClusterResult segment_candidates(std::size_t n_cand, std::size_t n_rows,
                                 const SceneFilterParams& params, SceneFilterWorkspace& ws,
                                 const FrameContext& ctx, const Plane& table,
                                 SceneFilterResult& res) {
  std::optional<HeightRule> rule;
  if (ctx.camera_position && params.object_min_height_sigmas > 0.0) {
    rule = HeightRule{table, *ctx.camera_position, params.object_min_height_sigmas,
                      params.depth_noise_sigma_m, params.depth_noise_ref_range_m,
                      params.depth_noise_exponent};
  }
  const HeightRule* hr = rule ? &*rule : nullptr;
  ClusterResult cl;
  if (ctx.image_width > 0 && params.segment_organized && ctx.camera_position) {
    res.organized = true;
    const std::vector<int> comp = organized_components(
        ws.cand_xyz.data(), ws.cand_rows.data(), n_cand, n_rows, ctx.image_width, ctx.rgb,
        *ctx.camera_position, params, ws.organized, &table);
    cl = clusters_from_components(ws.cand_xyz.data(), n_cand, 3, comp, params.cluster_min_points,
                                  params.cluster_min_extent, params.cluster_max_extent, hr);
  } else {
    cl = euclidean_clusters(ws.cand_xyz.data(), n_cand, 3, params.cluster_eps,
                            params.cluster_min_points, params.cluster_min_extent,
                            params.cluster_max_extent, params.cluster_voxel_m,
                            params.max_abs_coordinate_m, hr);
  }
  for (const ClusterInfo& c : cl.clusters) res.num_too_low += c.too_low ? 1 : 0;
  return cl;
}

/// Steps 2–4 of the data path for one packed frame; `frame_seed` drives the plane search.
/// `res.labels` already holds kLabelEnvironment / kLabelInvalid for every input row.
void run_frame(const Packed& pk, std::size_t n_rows, const SceneFilterParams& params,
               PlanePersistence& persistence, std::uint64_t frame_seed, bool& oor_reported,
               SceneFilterWorkspace& ws, const FrameContext& ctx, SceneFilterResult& res) {
  res.band = params.band;
  res.max_abs_coordinate_m = params.max_abs_coordinate_m;
  const std::size_t n_valid = pk.size();
  res.num_valid = static_cast<int>(n_valid);
  res.num_invalid = static_cast<int>(n_rows - n_valid);
  res.num_out_of_range = static_cast<int>(pk.out_of_range);
  report_out_of_range(pk, params, oor_reported, res.events);

  // Planes, table choice, persistence.
  const auto t_plane = Clock::now();
  res.planes = extract_packed(pk, params, frame_seed, ws);
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
  // Above the band: candidate. Below the plane and within the band: environment.
  const auto t_cluster = Clock::now();
  if (res.table && !res.fallback) {
    const std::size_t n_cand = split_band(pk, *res.table, params.band, ws);
    res.num_candidates = static_cast<int>(n_cand);
    const ClusterResult cl = segment_candidates(n_cand, n_rows, params, ws, ctx, *res.table, res);
    const int* cand_rows = ws.cand_rows.data();
    for (std::size_t k = 0; k < n_cand; ++k) {
      const int label = cl.labels[k];
      res.labels[static_cast<std::size_t>(cand_rows[k])] = label;
      if (label >= 0) res.object_rows.push_back(cand_rows[k]);
    }
    for (int id = 0; id < cl.num_accepted; ++id) res.cluster_ids.push_back(id);
    res.clusters = cl.clusters;
  }
  res.ms_cluster = ms_since(t_cluster);
}

/// One frame: pack (and label valid/invalid) every row, then run_frame.
template <typename T>
SceneFilterResult process_frame(const T* xyz, std::size_t n_rows, std::size_t row_stride,
                                const SceneFilterParams& params, PlanePersistence& persistence,
                                std::uint64_t frame_seed, bool& oor_reported,
                                SceneFilterWorkspace& ws, const FrameContext& ctx) {

  const auto t0 = Clock::now();
  SceneFilterResult res;
  res.labels.assign(n_rows, kLabelEnvironment);  // pack_finite marks the invalid rows
  const Packed pk =
      pack_finite(xyz, n_rows, row_stride, params.max_abs_coordinate_m, ws, res.labels.data());
  run_frame(pk, n_rows, params, persistence, frame_seed, oor_reported, ws, ctx, res);
  res.ms_pack = ms_since(t0) - res.ms_plane - res.ms_cluster;
  res.ms_total = ms_since(t0);
  return res;
}

}  // namespace

namespace {
/// std::invalid_argument for a context that does not fit the frame (before the frame counts).
void check_context(std::size_t n_rows, const FrameContext& ctx) {
  if (ctx.image_width < 0 ||
      (ctx.image_width > 0 && n_rows % static_cast<std::size_t>(ctx.image_width) != 0))
    throw std::invalid_argument("image_width: the frame's rows must be height x image_width pixels "
                                "(an organized cloud); pass 0 for an unorganized cloud");
  if (ctx.camera_position && !ctx.camera_position->allFinite())
    throw std::invalid_argument("camera_position must be 3 finite numbers");
}
}  // namespace

SceneFilterResult SceneFilter::process(const float* xyz, std::size_t n_rows, std::size_t row_stride,
                                       const FrameContext& ctx) {
  check_context(n_rows, ctx);
  return process_frame(xyz, n_rows, row_stride, params_, persistence_, next_frame_seed(),
                       out_of_range_reported_, work_, ctx);
}

SceneFilterResult SceneFilter::process(const double* xyz, std::size_t n_rows, std::size_t row_stride,
                                       const FrameContext& ctx) {
  check_context(n_rows, ctx);
  return process_frame(xyz, n_rows, row_stride, params_, persistence_, next_frame_seed(),
                       out_of_range_reported_, work_, ctx);
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
