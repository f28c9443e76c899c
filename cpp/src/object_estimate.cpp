// Object estimate of one cluster (method.md §2.1-2.4, 2.6). See object_estimate.hpp.
#include "grasp_core/object_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace grasp_core {
namespace {

/// A footprint narrower than this counts as zero width (anisotropy = inf) [m].
constexpr double kZeroWidth_m = 1e-12;
/// Rounding slack of the candidate test ext <= min + tol, so that tol = 0 still keeps
/// mathematically equal minima [m].
constexpr double kCandidateSlack_m = 1e-12;
/// in_plane_basis switches from world x to world y when |n . x| reaches this.
constexpr double kBasisSwitchCos = 0.9;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Metres -> "12.3" (millimetres, one decimal).
std::string mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", metres * 1000.0);
  return buf;
}

/// Offset a - ref wrapped into [-pi/2, pi/2).
double wrapped_offset(double a_rad, double ref_rad) {
  return wrap_mod_pi(a_rad - ref_rad + M_PI / 2.0) - M_PI / 2.0;
}

/// Span (max - min) of a cos(theta) + b sin(theta), and its midpoint.
void span_along(const std::vector<double>& a, const std::vector<double>& b, double theta_rad,
                double* span, double* mid) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n == 0) {
    *span = 0.0;
    *mid = 0.0;
    return;
  }
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  double lo = kInf, hi = -kInf;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = a[i] * c + b[i] * s;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  *span = hi - lo;
  *mid = 0.5 * (hi + lo);
}

EstimateResult failure(std::string why) {
  EstimateResult r;
  r.failure = std::move(why);
  return r;
}

}  // namespace

// ---- small numeric helpers ------------------------------------------------------------

double wrap_mod_pi(double x_rad) {
  if (!std::isfinite(x_rad)) return kNaN;
  double r = std::fmod(x_rad, M_PI);
  if (r < 0.0) r += M_PI;
  if (r >= M_PI) r -= M_PI;  // -tiny + pi rounds to pi
  return r;
}

double angle_dist_mod_pi(double a_rad, double b_rad) {
  return std::abs(wrap_mod_pi(a_rad - b_rad + M_PI / 2.0) - M_PI / 2.0);
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  // Selection instead of a full sort: O(n). For an even count the lower middle value is
  // the largest element of the lower half, found after the upper one is in place.
  const std::size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  const double upper = v[k];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k));
  return 0.5 * (lower + upper);
}

double circular_median_mod_pi(const std::vector<double>& angles_rad, double reference_rad) {
  std::vector<double> off;
  off.reserve(angles_rad.size());
  for (double a : angles_rad) off.push_back(wrapped_offset(a, reference_rad));
  if (off.empty()) return wrap_mod_pi(reference_rad);
  return wrap_mod_pi(reference_rad + median(std::move(off)));
}

double slice_median_top(const std::vector<double>& d, double sigma_m, double slice_sigmas,
                        int iters) {
  if (d.empty()) return kNaN;
  double top = *std::max_element(d.begin(), d.end());
  const double depth = slice_sigmas * sigma_m;
  std::vector<double> kept;
  for (int it = 0; it < iters; ++it) {
    kept.clear();
    for (double x : d)
      if (x >= top - depth) kept.push_back(x);
    if (kept.size() < 3) break;
    const double next = median(std::move(kept));  // no copy; kept is refilled above
    if (next == top) break;
    top = next;
  }
  return top;
}

// ---- decomposition and width scan -----------------------------------------------------

void in_plane_basis(const Vec3& n, Vec3* u, Vec3* v) {
  Vec3 nn = n;
  const double len = nn.norm();
  nn = (std::isfinite(len) && len > 0.0) ? Vec3(nn / len) : Vec3(Vec3::UnitZ());
  const Vec3 ref = (std::abs(nn.x()) < kBasisSwitchCos) ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 uu = (ref - ref.dot(nn) * nn).normalized();
  if (u) *u = uu;
  if (v) *v = nn.cross(uu);
}

double scan_angle_rad(int t, int n_theta) {
  return n_theta > 0 ? M_PI * static_cast<double>(t) / static_cast<double>(n_theta) : 0.0;
}

double extent_along(const std::vector<double>& a, const std::vector<double>& b, double theta_rad) {
  double span = 0.0, mid = 0.0;
  span_along(a, b, theta_rad, &span, &mid);
  return span;
}

namespace {

/// A point of the footprint in the (u, v) plane [m].
struct P2 {
  double a, b;
};

/// Lexicographic order on (a, b): the order of Andrew's monotone chain.
bool lex_less(const P2& p, const P2& q) { return p.a < q.a || (p.a == q.a && p.b < q.b); }

/// Average points per bucket of sort_lex().
constexpr std::size_t kPointsPerBucket = 4;
/// Below this many points sort_lex() is a plain std::sort.
constexpr std::size_t kMinBucketSortPoints = 64;

/// Buckets up to this size are insertion-sorted (std::sort's setup dominates tiny ranges).
constexpr std::size_t kInsertionSortMax = 16;

/// Insertion sort of [first, last) by lex_less.
void insertion_sort_lex(std::vector<P2>::iterator first, std::vector<P2>::iterator last) {
  for (auto i = first + 1; i < last; ++i) {
    const P2 p = *i;
    auto j = i;
    for (; j > first && lex_less(p, *(j - 1)); --j) *j = *(j - 1);
    *j = p;
  }
}

/// Sort points by lex_less. A counting sort into buckets of a (the bucket index
/// floor((a - a_min) * scale) is non-decreasing in a: a correctly rounded subtraction and a
/// multiplication by a positive constant are monotone), then std::sort inside each bucket.
/// Points that compare equal are identical, so the result equals std::sort's exactly;
/// footprints are spread evenly in a, so this is ~linear instead of n log n.
void sort_lex(std::vector<P2>& pts, std::vector<P2>& scratch) {
  const std::size_t n = pts.size();
  if (n < kMinBucketSortPoints) {
    std::sort(pts.begin(), pts.end(), lex_less);
    return;
  }
  double lo = pts[0].a, hi = pts[0].a;
  for (const P2& p : pts) {
    lo = std::min(lo, p.a);
    hi = std::max(hi, p.a);
  }
  const std::size_t n_buckets = n / kPointsPerBucket + 1;
  const double scale = static_cast<double>(n_buckets - 1) / (hi - lo);
  if (!(hi > lo) || !std::isfinite(scale)) {
    std::sort(pts.begin(), pts.end(), lex_less);
    return;
  }
  const auto bucket_of = [&](const P2& p) {
    return std::min(n_buckets - 1, static_cast<std::size_t>((p.a - lo) * scale));
  };
  std::vector<std::size_t> start(n_buckets + 1, 0);
  for (const P2& p : pts) ++start[bucket_of(p) + 1];
  for (std::size_t k = 0; k < n_buckets; ++k) start[k + 1] += start[k];
  scratch.resize(n);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (const P2& p : pts) scratch[fill[bucket_of(p)]++] = p;
  }
  for (std::size_t k = 0; k < n_buckets; ++k) {
    const auto first = scratch.begin() + static_cast<std::ptrdiff_t>(start[k]);
    const auto last = scratch.begin() + static_cast<std::ptrdiff_t>(start[k + 1]);
    if (last - first <= 1) continue;
    if (last - first <= static_cast<std::ptrdiff_t>(kInsertionSortMax)) {
      insertion_sort_lex(first, last);
    } else {
      std::sort(first, last, lex_less);
    }
  }
  pts.swap(scratch);
}

/// Vertices of the 2-D convex hull of (a, b) (Andrew's monotone chain), as two coordinate
/// lists. The max and min of a*cos + b*sin over a point set are attained at hull vertices,
/// and the vertices are original points, so spans over the hull equal spans over all
/// points exactly -- at a fraction of the cost (a 5 cm top face: ~3k points, ~40 vertices).
/// The points are sorted as (a, b) values, not through an index array: points that compare
/// equal are identical, so the order, and hence the hull, is the same either way.
void convex_hull_2d(const std::vector<double>& a, const std::vector<double>& b,
                    std::vector<double>* ha, std::vector<double>* hb) {
  const std::size_t n = std::min(a.size(), b.size());
  std::vector<P2> pts(n), scratch;
  for (std::size_t i = 0; i < n; ++i) pts[i] = P2{a[i], b[i]};
  sort_lex(pts, scratch);
  if (n < 3) {
    for (const P2& p : pts) { ha->push_back(p.a); hb->push_back(p.b); }
    return;
  }
  auto cross = [](const P2& o, const P2& p, const P2& q) {
    return (p.a - o.a) * (q.b - o.b) - (p.b - o.b) * (q.a - o.a);
  };
  std::vector<P2> hull(2 * n);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  for (const P2& p : hull) { ha->push_back(p.a); hb->push_back(p.b); }
}

}  // namespace

std::vector<double> width_scan(const std::vector<double>& a, const std::vector<double>& b,
                               int n_theta) {
  std::vector<double> ext(static_cast<std::size_t>(std::max(n_theta, 0)), 0.0);
  std::vector<double> ha, hb;
  convex_hull_2d(a, b, &ha, &hb);
  for (int t = 0; t < n_theta; ++t) ext[t] = extent_along(ha, hb, scan_angle_rad(t, n_theta));
  return ext;
}

double anisotropy_ratio(const std::vector<double>& ext) {
  if (ext.empty()) return kInf;
  const auto [lo, hi] = std::minmax_element(ext.begin(), ext.end());
  if (!(*lo > kZeroWidth_m)) return kInf;
  return *hi / *lo;
}

// ---- direction choice -----------------------------------------------------------------

std::vector<DirectionRun> direction_runs(const std::vector<double>& ext, double width_tol_m) {
  const int T = static_cast<int>(ext.size());
  if (T == 0) return {};
  const double mn = *std::min_element(ext.begin(), ext.end());
  std::vector<bool> cand(T);
  for (int t = 0; t < T; ++t) cand[t] = ext[t] <= mn + width_tol_m + kCandidateSlack_m;

  // Maximal segments [start, end] of consecutive candidates, in index order.
  std::vector<std::pair<int, int>> seg;
  for (int t = 0; t < T; ++t) {
    if (!cand[t]) continue;
    if (!seg.empty() && seg.back().second == t - 1)
      seg.back().second = t;
    else
      seg.emplace_back(t, t);
  }
  std::vector<std::vector<int>> members;
  const bool wraps = seg.size() >= 2 && seg.front().first == 0 && seg.back().second == T - 1;
  for (std::size_t k = 0; k < seg.size(); ++k) {
    if (wraps && k == 0) continue;  // merged into the last segment below
    std::vector<int> idx;
    for (int t = seg[k].first; t <= seg[k].second; ++t) idx.push_back(t);
    if (wraps && k + 1 == seg.size())
      for (int t = seg.front().first; t <= seg.front().second; ++t) idx.push_back(t);
    members.push_back(std::move(idx));
  }

  std::vector<DirectionRun> runs;
  for (auto& idx : members) {
    DirectionRun r;
    r.first = idx.front();
    r.last = idx.back();
    std::vector<double> ang;
    r.width_m = kInf;
    for (int t : idx) {
      ang.push_back(scan_angle_rad(t, T));
      r.width_m = std::min(r.width_m, ext[t]);
    }
    // Reference = the run's first angle in circular order; offsets wrapped into
    // [-pi/2, pi/2) make the result independent of the order inside a merged run.
    r.theta_rad = circular_median_mod_pi(ang, ang.front());
    r.indices = std::move(idx);
    runs.push_back(std::move(r));
  }
  std::stable_sort(runs.begin(), runs.end(), [](const DirectionRun& x, const DirectionRun& y) {
    return x.theta_rad < y.theta_rad;
  });
  return runs;
}

DirectionChoice choose_direction(const std::vector<double>& ext, double width_tol_m,
                                 std::optional<double> theta_prev) {
  DirectionChoice out;
  out.runs = direction_runs(ext, width_tol_m);
  if (out.runs.empty()) return out;
  int best = 0;
  if (theta_prev && std::isfinite(*theta_prev)) {
    double best_d = kInf;
    for (int k = 0; k < static_cast<int>(out.runs.size()); ++k) {
      const double dk = angle_dist_mod_pi(out.runs[k].theta_rad, *theta_prev);
      if (dk < best_d) {  // strict: ties keep the smaller theta (runs are sorted)
        best_d = dk;
        best = k;
      }
    }
  } else {
    double min_w = kInf;
    for (const auto& r : out.runs) min_w = std::min(min_w, r.width_m);
    for (int k = 0; k < static_cast<int>(out.runs.size()); ++k) {
      if (out.runs[k].width_m <= min_w + width_tol_m + kCandidateSlack_m) {
        best = k;  // first qualifying = smallest theta
        break;
      }
    }
  }
  out.chosen = best;
  out.theta_rad = out.runs[best].theta_rad;
  out.width_m = out.runs[best].width_m;
  return out;
}

// ---- guards ---------------------------------------------------------------------------

void apply_size_guards(ObjectEstimate& est, const ObbParams& p) {
  est.height_ok = est.height_m >= p.min_height;
  est.width_ok = est.width_m >= p.min_graspable_width && est.width_m <= p.gripper_open;
  est.notes.clear();
  if (!est.resting_note.empty()) est.notes.push_back(est.resting_note);
  if (!est.height_ok)
    est.notes.push_back("too low: " + mm(est.height_m) + " mm (min " + mm(p.min_height) + " mm)");
  if (!est.width_ok)
    est.notes.push_back("width not graspable: " + mm(est.width_m) + " mm (" +
                        mm(p.min_graspable_width) + "\u2013" + mm(p.gripper_open) + " mm)");
  est.grasp_ok = est.resting && est.height_ok && est.width_ok;
}

// ---- the estimate ---------------------------------------------------------------------

PreparedEstimate prepare_estimate(const PointsD& pts, const Plane& plane, const ObbParams& p,
                                  double max_abs_coordinate_m) {
  PreparedEstimate prep;
  const double n_len = plane.n.norm();
  if (!std::isfinite(n_len) || !(n_len > 0.0) || !std::isfinite(plane.c)) {
    prep.failure = "invalid plane: normal must be finite and non-zero";
    return prep;
  }
  const Vec3 n = plane.n / n_len;
  const double c = plane.c / n_len;

  // Defensive: the caller filters NaN/Inf and absurd coordinates, but never let one row
  // poison the estimate (a coordinate near float max overflows the covariance).
  PointsD P(pts.rows(), 3);
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < pts.rows(); ++i)
    if (within_bound(pts(i, 0), pts(i, 1), pts(i, 2), max_abs_coordinate_m)) P.row(m++) = pts.row(i);
  P.conservativeResize(m, 3);
  if (m < 3) {
    prep.failure = "too few points: " + std::to_string(m) + " (need 3)";
    return prep;
  }

  ObjectEstimate& e = prep.partial;
  e.num_points = static_cast<int>(m);
  std::string why;
  const auto pca = pca_box(P, &why);
  if (!pca) {
    prep.failure = why;
    return prep;
  }
  e.pca = *pca;
  e.pca_tilt_deg = pca_tilt_deg(e.pca, n);

  // 2.1 decomposition about p0 = -c n.
  Vec3 u, v;
  in_plane_basis(n, &u, &v);
  const Vec3 p0 = -c * n;
  std::vector<double> a(m), b(m), d(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Vec3 q = P.row(i).transpose() - p0;
    a[i] = q.dot(u);
    b[i] = q.dot(v);
    d[i] = q.dot(n);
  }
  // 2.4 height first: a cluster whose top is below the plane is no object on it (ours).
  e.height_m = slice_median_top(d, p.depth_noise_sigma, p.top_slice_sigmas, p.top_slice_iters);
  if (!(e.height_m >= 0.0)) {
    prep.failure = "not above the plane: its top (slice median) is " + mm(-e.height_m) +
                   " mm below the plane; an object estimate needs points above the plane "
                   "(are the points and the plane in the same frame?)";
    return prep;
  }
  e.lowest_m = *std::min_element(d.begin(), d.end());

  // 2.2 width scan (the direction choice of 2.3 depends on theta_prev: finish_estimate).
  prep.ext = width_scan(a, b, p.n_theta);
  e.anisotropy = anisotropy_ratio(prep.ext);
  e.yaw_defined = e.anisotropy >= p.isotropy_ratio_max;
  prep.n = n;
  prep.u = u;
  prep.v = v;
  prep.p0 = p0;
  prep.a = std::move(a);
  prep.b = std::move(b);
  return prep;
}

EstimateResult finish_estimate(const PreparedEstimate& prep, const ObbParams& p,
                               std::optional<double> theta_prev, std::optional<double> band) {
  if (!prep.failure.empty()) return failure(prep.failure);
  ObjectEstimate e = prep.partial;
  const Vec3& n = prep.n;
  const Vec3& u = prep.u;
  const Vec3& v = prep.v;

  // 2.3 closing direction.
  const DirectionChoice choice = choose_direction(prep.ext, p.width_tol_m, theta_prev);
  e.theta_rad = choice.theta_rad;

  // 2.4 box in the (theta, theta + 90 deg) basis, slice-median height, centre.
  const double th = e.theta_rad;
  double mid_w = 0.0, mid_p = 0.0;
  span_along(prep.a, prep.b, th, &e.width_m, &mid_w);
  span_along(prep.a, prep.b, th + M_PI / 2.0, &e.perp_width_m, &mid_p);
  const Vec3 e_th = std::cos(th) * u + std::sin(th) * v;
  const Vec3 e_perp = -std::sin(th) * u + std::cos(th) * v;
  e.R_box.col(0) = e_th;
  e.R_box.col(1) = e_perp;
  e.R_box.col(2) = n;
  e.center = prep.p0 + mid_w * e_th + mid_p * e_perp + 0.5 * e.height_m * n;
  e.extents = Vec3(e.width_m, e.perp_width_m, e.height_m);

  // 2.6 guards.
  // Sides are visible when points reach more than side_seen_sigmas * sigma below the top
  // slice (ours). The method's literal "max d - min d > 3 sigma" compares the range of thousands
  // of noisy samples (about 7 sigma for a flat top alone at N ~ 2500) with 3 sigma, so
  // every noisy top-only view would count as "sides seen" and a resting cube seen from
  // directly above would be refused as floating. Measuring from the slice-median top and
  // adding the slice depth keeps the noise band of the top face out of the judgement.
  const double below_top = e.height_m - e.lowest_m;
  const double side_limit = (p.top_slice_sigmas + p.side_seen_sigmas) * p.depth_noise_sigma;
  const bool sides_seen = below_top > side_limit;
  e.resting = true;
  if (!band) {
    e.undetermined_notes.push_back("resting undetermined: band unknown; treated as resting");
  } else if (!sides_seen) {
    e.undetermined_notes.push_back("resting undetermined: only the top is seen (lowest point " +
                                   mm(below_top) + " mm below the top, sides need > " +
                                   mm(side_limit) + " mm); treated as resting");
  } else {
    const double limit = *band + p.resting_margin;
    e.resting = e.lowest_m <= limit;
    if (!e.resting)
      e.resting_note = "floating/stacked: lowest point " + mm(e.lowest_m) +
                       " mm above plane (band + margin = " + mm(limit) + " mm)";
  }
  apply_size_guards(e, p);

  EstimateResult r;
  r.estimate = std::move(e);
  return r;
}

EstimateResult estimate_object(const PointsD& pts, const Plane& plane, const ObbParams& p,
                               std::optional<double> theta_prev, std::optional<double> band,
                               double max_abs_coordinate_m) {
  return finish_estimate(prepare_estimate(pts, plane, p, max_abs_coordinate_m), p, theta_prev, band);
}

}  // namespace grasp_core
