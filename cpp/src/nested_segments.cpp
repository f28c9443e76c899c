// (ours) Joining a segment nested in another one. See nested_segments.hpp.
#include "grasp_core/nested_segments.hpp"

#include "grasp_core/union_find.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace grasp_core {
namespace {

constexpr int kDu[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
constexpr int kDv[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
constexpr int kMinRingPixels = 8;  ///< a ring with fewer pixels does not count
constexpr int kMaxPasses = 3;      ///< a cap in a ring in a shoulder: one level joins per pass

/// The candidate at the k-th 8-neighbour of pixel `row`, -1 for none (also off the image).
int neighbour(const int* pix, int row, int k, int width, int height) {
  const int u = row % width + kDu[k], v = row / width + kDv[k];
  if (u < 0 || u >= width || v < 0 || v >= height) return -1;
  return pix[v * width + u];
}

/// The segments as they are before a pass (buffers in NestedWorkspace).
struct Segments {
  const std::vector<int>& root;                  ///< per candidate: its segment (root)
  const std::vector<int>& size;                  ///< per root: its number of candidates
  const std::vector<std::array<int, 4>>& box;    ///< per root: u_min, v_min, u_max, v_max of its pixels
  std::vector<Vec3>& lo;                         ///< per root: its points' 3-D box, lower corner
  std::vector<Vec3>& hi;                         ///< per root: upper corner
};

Segments collect(const float* xyz, const int* cand_rows, std::size_t n_cand, int width,
                 std::vector<int>& parent, NestedWorkspace& ws) {
  ws.root.resize(n_cand);
  ws.size.assign(n_cand, 0);
  ws.box.assign(n_cand, {1 << 30, 1 << 30, -1, -1});
  ws.lo.assign(n_cand, Vec3::Constant(1e30));
  ws.hi.assign(n_cand, Vec3::Constant(-1e30));
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int r = find_root(parent, static_cast<int>(k));
    const auto ur = static_cast<std::size_t>(r);
    ws.root[k] = r;
    ++ws.size[ur];
    std::array<int, 4>& b = ws.box[ur];
    const int u = cand_rows[k] % width, v = cand_rows[k] / width;
    b = {std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v)};
    const Vec3 p(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
    ws.lo[ur] = ws.lo[ur].cwiseMin(p);
    ws.hi[ur] = ws.hi[ur].cwiseMax(p);
  }
  return Segments{ws.root, ws.size, ws.box, ws.lo, ws.hi};
}

/// Joins `inner` into `outer` unless their union's 3-D box diagonal exceeds `max_extent_m`
/// (method.md §1.4's cluster extent rule: a join must not turn an object into a rejected cluster);
/// joins made earlier in the pass count. Returns whether it joined.
bool join_within_extent(Segments& s, std::vector<int>& parent, int inner, int outer, double max_extent_m) {
  const auto a = static_cast<std::size_t>(find_root(parent, inner));
  const auto b = static_cast<std::size_t>(find_root(parent, outer));
  if (a == b) return false;
  const Vec3 lo = s.lo[a].cwiseMin(s.lo[b]), hi = s.hi[a].cwiseMax(s.hi[b]);
  if (max_extent_m > 0.0 && (hi - lo).norm() > max_extent_m) return false;
  unite(parent, static_cast<int>(a), static_cast<int>(b));
  const auto r = static_cast<std::size_t>(find_root(parent, static_cast<int>(a)));
  s.lo[r] = lo;
  s.hi[r] = hi;
  return true;
}

bool inside(const std::array<int, 4>& a, const std::array<int, 4>& b) {
  return a[0] >= b[0] - 1 && a[1] >= b[1] - 1 && a[2] <= b[2] + 1 && a[3] <= b[3] + 1;
}

/// (inner, outer) segment pairs where the inner one is nested in the outer one: the outer one
/// takes at least `fraction` of the image-neighbour pairs from the inner one to other segments
/// (pairs to non-candidate pixels — the table around, holes below the band — and to segments of
/// fewer than `min_points` points — slivers left over — do not count) and the inner one's pixel
/// box lies within the outer one's (1 px slack).
std::vector<std::pair<int, int>> nested_pairs(const Segments& s, const int* cand_rows, std::size_t n_cand,
                                              int width, int height, const int* pix, double fraction,
                                              int min_points, NestedWorkspace& ws) {
  ws.leaving.assign(n_cand, 0);
  ws.into.clear();  // (segment, the segment a leaving pair leads into)
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int a = s.root[k];
    const int u0 = cand_rows[k] % width, v0 = cand_rows[k] / width;
    for (int e = 0; e < 8; ++e) {
      const int u = u0 + kDu[e], v = v0 + kDv[e];
      if (u < 0 || u >= width || v < 0 || v >= height) continue;
      const int j = pix[v * width + u];
      if (j < 0) continue;
      const int b = s.root[static_cast<std::size_t>(j)];
      if (b == a || s.size[static_cast<std::size_t>(b)] < min_points) continue;
      ++ws.leaving[static_cast<std::size_t>(a)];
      ws.into.emplace_back(a, b);
    }
  }
  std::sort(ws.into.begin(), ws.into.end());
  const auto& into = ws.into;
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < into.size();) {
    std::size_t e = i;
    while (e < into.size() && into[e] == into[i]) ++e;
    const auto [a, b] = into[i];
    if (static_cast<double>(e - i) >= fraction * ws.leaving[static_cast<std::size_t>(a)] &&
        inside(s.box[static_cast<std::size_t>(a)], s.box[static_cast<std::size_t>(b)]))
      out.emplace_back(a, b);
    i = e;
  }
  return out;
}

/// The frame's geometry the rings need.
struct Image {
  const float* xyz;
  const int* cand_rows;
  const int* pix;
  int width, height;
  const Plane& table;
};

/// The candidates of segment `seg`.
std::vector<int> members(const Segments& s, int seg) {
  std::vector<int> out;
  out.reserve(static_cast<std::size_t>(s.size[static_cast<std::size_t>(seg)]));
  for (std::size_t k = 0; k < s.root.size(); ++k)
    if (s.root[k] == seg) out.push_back(static_cast<int>(k));
  return out;
}

Vec3 centroid(const Image& im, const std::vector<int>& members) {
  Vec3 c = Vec3::Zero();
  for (int k : members) c += Vec3(im.xyz[3 * k], im.xyz[3 * k + 1], im.xyz[3 * k + 2]);
  return c / static_cast<double>(members.size());
}

/// |d height / d distance| of the one-pixel rings of segment `into` grown from the candidates `from`
/// (distance: horizontal, from `centre`; least squares over the rings' means), or 0 when
/// fewer than two rings have enough pixels.
double ring_slope(const Segments& s, const Image& im, const std::vector<int>& from, int into, const Vec3& centre,
                  int rings, std::vector<int>& mark, int stamp) {
  std::vector<int> front = from, next;
  const Vec3& n = im.table.n;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int used = 0;
  for (int r = 0; r < rings && !front.empty(); ++r) {
    next.clear();
    double h = 0, d = 0;
    for (int k : front)
      for (int e = 0; e < 8; ++e) {
        const int j = neighbour(im.pix, im.cand_rows[k], e, im.width, im.height);
        if (j < 0 || s.root[static_cast<std::size_t>(j)] != into || mark[static_cast<std::size_t>(j)] == stamp) continue;
        mark[static_cast<std::size_t>(j)] = stamp;
        next.push_back(j);
        const Vec3 q = Vec3(im.xyz[3 * j], im.xyz[3 * j + 1], im.xyz[3 * j + 2]) - centre;
        h += im.table.signed_distance(q + centre);
        d += (q - q.dot(n) * n).norm();
      }
    std::swap(front, next);
    if (static_cast<int>(front.size()) < kMinRingPixels) continue;
    const double x = d / front.size(), y = h / front.size();
    sx += x; sy += y; sxx += x * x; sxy += x * y;
    ++used;
  }
  const double var = used < 2 ? 0.0 : sxx - sx * sx / used;
  if (var <= 1e-12) return 0.0;
  return std::abs((sxy - sx * sy / used) / var);
}

/// Whether the surface joining a nested pair slopes within [lo, hi] (tangents): the outer
/// segment's rings around the inner one (a bottle's shoulder around its cap) or the inner
/// one's rings inside the outer one (a bowl's inner wall inside its rim).
bool sloped_between(const Segments& s, const Image& im, int inner, int outer, double lo, double hi,
                    int rings, std::vector<int>& mark, int& stamp) {
  const std::vector<int> in = members(s, inner), out = members(s, outer);
  const Vec3 c = centroid(im, in);
  for (const auto& [from, into] : {std::pair(&in, outer), std::pair(&out, inner)}) {
    const double slope = ring_slope(s, im, *from, into, c, rings, mark, ++stamp);
    if (slope >= lo && slope <= hi) return true;
  }
  return false;
}


/// One pass over the segments as they are; returns the number of joins made.
int join_pass(const float* xyz, const int* cand_rows, std::size_t n_cand, int width, int height,
              const Plane& table, const SceneFilterParams& params, const int* pix, std::vector<int>& parent,
              NestedWorkspace& ws) {
  Segments s = collect(xyz, cand_rows, n_cand, width, parent, ws);
  const int small = std::max(params.segment_absorb_max_points, params.cluster_min_points);
  const auto pairs = nested_pairs(s, cand_rows, n_cand, width, height, pix, params.segment_nest_fraction, small, ws);
  if (pairs.empty()) return 0;
  const Image im{xyz, cand_rows, pix, width, height, table};
  const double lo = std::tan(params.segment_nest_min_slope_deg * M_PI / 180.0);
  const double hi = std::tan(params.segment_nest_max_slope_deg * M_PI / 180.0);
  std::vector<int>& mark = ws.mark;
  mark.assign(n_cand, 0);
  std::vector<std::pair<int, int>> joins;
  int stamp = 0;
  for (const auto& [inner, outer] : pairs)
    if (sloped_between(s, im, inner, outer, lo, hi, params.segment_nest_rings_px, mark, stamp))
      joins.emplace_back(inner, outer);
  int joined = 0;
  for (const auto& [a, b] : joins) joined += join_within_extent(s, parent, a, b, params.cluster_max_extent) ? 1 : 0;
  return joined;
}

}  // namespace

void join_nested_segments(const float* xyz, const int* cand_rows, std::size_t n_cand, int width,
                          int height, const Plane& table, const SceneFilterParams& params,
                          const int* pix, std::vector<int>& parent, NestedWorkspace& ws) {
  if (params.segment_nest_fraction <= 0.0 || n_cand == 0) return;
  for (int pass = 0; pass < kMaxPasses; ++pass)
    if (join_pass(xyz, cand_rows, n_cand, width, height, table, params, pix, parent, ws) == 0) return;
}

}  // namespace grasp_core
