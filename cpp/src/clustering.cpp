// method.md §1.4 — Euclidean clustering (PCL semantics) with an exact grid fast path.
// See clustering.hpp for the algorithm and the labelling rules.
#include "grasp_core/clustering.hpp"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>
#include <stdexcept>
#include <utility>

namespace grasp_core {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// Strided read-only view of finite float points.
struct PointView {
  const float* xyz = nullptr;
  std::size_t stride = 3;
  const float* at(int i) const { return xyz + static_cast<std::size_t>(i) * stride; }
};

/// The distance test of PCL's kd-tree (FLANN L2_Simple: float sum of squared differences,
/// strictly below the squared radius), so both paths draw the same edges.
inline bool within(const float* a, const float* b, float eps_sq) {
  float r = 0.0f;
  float d = a[0] - b[0];
  r += d * d;
  d = a[1] - b[1];
  r += d * d;
  d = a[2] - b[2];
  r += d * d;
  return r < eps_sq;
}

/// Union-find with path halving and union by size.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<int> parent_;
  std::vector<int> size_;
};

/// Reference path: pcl::EuclideanClusterExtraction on every distinct point.
/// Returns a component id per point (ids are arbitrary but consistent).
/// Exact duplicates are merged first (they are at distance 0 < eps, so always in one
/// component): PCL's radius search returns every copy for every copy, which made N
/// identical rows cost O(N^2) (100k rows: ~6 min); now they cost O(N log N).
std::vector<int> components_exact(const PointView& pts, const std::vector<int>& finite,
                                  double eps_m) {
  const auto less = [&](int a, int b) {
    const float* p = pts.at(finite[static_cast<std::size_t>(a)]);
    const float* q = pts.at(finite[static_cast<std::size_t>(b)]);
    return std::lexicographical_compare(p, p + 3, q, q + 3);
  };
  std::vector<int> order(finite.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), less);
  std::vector<int> distinct_of(finite.size(), -1);  // point k -> index of its distinct point
  std::vector<int> distinct;                         // one representative k per distinct point
  for (std::size_t j = 0; j < order.size(); ++j) {
    if (j == 0 || less(order[j - 1], order[j])) distinct.push_back(order[j]);
    distinct_of[static_cast<std::size_t>(order[j])] = static_cast<int>(distinct.size()) - 1;
  }

  auto cloud = std::make_shared<Cloud>();
  cloud->resize(distinct.size());
  for (std::size_t k = 0; k < distinct.size(); ++k) {
    const float* p = pts.at(finite[static_cast<std::size_t>(distinct[k])]);
    (*cloud)[k] = pcl::PointXYZ(p[0], p[1], p[2]);
  }
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ece;
  ece.setClusterTolerance(eps_m);
  ece.setMinClusterSize(1);
  ece.setMaxClusterSize(std::numeric_limits<int>::max());
  ece.setSearchMethod(tree);
  ece.setInputCloud(cloud);
  std::vector<pcl::PointIndices> clusters;
  ece.extract(clusters);
  std::vector<int> comp_distinct(distinct.size(), -1);
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (const auto i : clusters[c].indices)
      comp_distinct[static_cast<std::size_t>(i)] = static_cast<int>(c);
  // Defensive: a point PCL did not assign is its own component.
  int next = static_cast<int>(clusters.size());
  for (auto& c : comp_distinct)
    if (c < 0) c = next++;
  std::vector<int> comp(finite.size());
  for (std::size_t k = 0; k < finite.size(); ++k)
    comp[k] = comp_distinct[static_cast<std::size_t>(distinct_of[k])];
  return comp;
}

/// Axis-aligned box of a set of points (float, as the points are).
struct Box {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-std::numeric_limits<float>::infinity());
  void add(const float* p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
};

/// Squared distance from p to box b (0 inside), double.
double sq_dist_point_box(const float* p, const Box& b) {
  double s = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double g = std::max({static_cast<double>(b.lo[a]) - p[a], 0.0,
                               static_cast<double>(p[a]) - b.hi[a]});
    s += g * g;
  }
  return s;
}

/// Smallest and largest distance between any two points of boxes a and b, double.
void box_distance_bounds(const Box& a, const Box& b, double& min_d, double& max_d) {
  double s_min = 0.0, s_max = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({static_cast<double>(a.lo[k]) - b.hi[k], 0.0,
                                 static_cast<double>(b.lo[k]) - a.hi[k]});
    const double span = std::max(static_cast<double>(a.hi[k]) - b.lo[k],
                                 static_cast<double>(b.hi[k]) - a.lo[k]);
    s_min += gap * gap;
    s_max += span * span;
  }
  min_d = std::sqrt(s_min);
  max_d = std::sqrt(s_max);
}

/// Open-addressing hash map cell key -> cell id (linear probing, power-of-two capacity).
/// std::unordered_map cost ~30 ns per lookup here (modulo + pointer chasing), which
/// dominated the clustering of large candidate clouds (~300k neighbour lookups for a wall).
class CellTable {
 public:
  explicit CellTable(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected + 1) cap <<= 1;
    keys_.assign(cap, kEmpty);
    ids_.assign(cap, -1);
    mask_ = cap - 1;
    shift_ = 64;
    for (std::size_t c = cap; c > 1; c >>= 1) --shift_;
  }
  /// Id of `key`, inserting it with `next_id` if absent; `inserted` tells which.
  int find_or_insert(std::uint64_t key, int next_id, bool& inserted) {
    std::size_t i = slot(key);
    while (keys_[i] != kEmpty) {
      if (keys_[i] == key) {
        inserted = false;
        return ids_[i];
      }
      i = (i + 1) & mask_;
    }
    if (2 * (++size_) > keys_.size()) {  // keep the load factor <= 1/2
      grow();
      return find_or_insert(key, next_id, inserted);
    }
    keys_[i] = key;
    ids_[i] = next_id;
    inserted = true;
    return next_id;
  }
  /// Id of `key`, or -1.
  int find(std::uint64_t key) const {
    std::size_t i = slot(key);
    while (keys_[i] != kEmpty) {
      if (keys_[i] == key) return ids_[i];
      i = (i + 1) & mask_;
    }
    return -1;
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // keys use 63 bits
  std::size_t slot(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_) & mask_;
  }
  void grow() {
    std::vector<std::uint64_t> keys;
    std::vector<int> ids;
    keys.swap(keys_);
    ids.swap(ids_);
    keys_.assign(2 * keys.size(), kEmpty);
    ids_.assign(2 * keys.size(), -1);
    mask_ = keys_.size() - 1;
    --shift_;
    size_ = 0;
    bool ins = false;
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) find_or_insert(keys[i], ids[i], ins);
  }

  std::vector<std::uint64_t> keys_;
  std::vector<int> ids_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

constexpr int kKeyBits = 21;                       ///< bits per axis in a cell key
constexpr std::uint64_t kKeyMask = (1ULL << kKeyBits) - 1;

/// Fast path, exact: a uniform grid of edge eps/sqrt(3) (so a cell is connected inside),
/// cells joined by union-find when some point pair across them is within eps.
/// Returns false (caller falls back to the reference path) if the cloud spans more cells
/// than the keys can hold.
bool components_grid(const PointView& pts, const std::vector<int>& finite, double eps_m,
                     std::vector<int>& comp) {
  const std::size_t n = finite.size();
  // Slightly under eps/sqrt(3): two points of one cell are < eps apart even after rounding.
  const double edge = eps_m / std::sqrt(3.0) * (1.0 - 1e-6);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const int i : finite) {
    const float* p = pts.at(i);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], static_cast<double>(p[a]));
      hi[a] = std::max(hi[a], static_cast<double>(p[a]));
    }
  }
  // Cell coordinates live in [2, 2^21 - 3]: the +-2 neighbour offsets never wrap.
  constexpr double kMaxCells = static_cast<double>(kKeyMask) - 4.0;
  for (int a = 0; a < 3; ++a)
    if (!((hi[a] - lo[a]) / edge < kMaxCells)) return false;

  // Cell of every point (ids in order of first appearance), then a counting sort so
  // that each cell's points are contiguous: cell c = order[start[c] .. start[c+1]).
  CellTable cell_of_key(n / 4 + 16);
  std::vector<std::uint64_t> cell_key;
  std::vector<int> cell_of_point(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float* p = pts.at(finite[k]);
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const auto cell = static_cast<std::uint64_t>(std::floor((p[a] - lo[a]) / edge)) + 2;
      key |= std::min(cell, kKeyMask - 2) << (kKeyBits * a);
    }
    bool inserted = false;
    cell_of_point[k] = cell_of_key.find_or_insert(key, static_cast<int>(cell_key.size()), inserted);
    if (inserted) cell_key.push_back(key);
  }
  const int n_cells = static_cast<int>(cell_key.size());
  std::vector<int> start(static_cast<std::size_t>(n_cells) + 1, 0);
  for (const int c : cell_of_point) ++start[static_cast<std::size_t>(c) + 1];
  for (int c = 0; c < n_cells; ++c) start[c + 1] += start[c];
  std::vector<int> order(n);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < n; ++k) order[static_cast<std::size_t>(fill[cell_of_point[k]]++)] = static_cast<int>(k);
  }
  std::vector<Box> box(static_cast<std::size_t>(n_cells));
  for (int c = 0; c < n_cells; ++c)
    for (int k = start[c]; k < start[c + 1]; ++k) box[c].add(pts.at(finite[order[k]]));

  // Half of the 5x5x5 neighbourhood (offsets lexicographically > 0): each pair once.
  // Cells up to 2 apart per axis can hold points within eps (edge = eps/sqrt(3)).
  std::vector<std::int64_t> offsets;
  for (int dz = -2; dz <= 2; ++dz)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        if (std::make_tuple(dz, dy, dx) <= std::make_tuple(0, 0, 0)) continue;
        // Multiplications, not shifts: the offsets are negative.
        constexpr std::int64_t kRow = std::int64_t{1} << kKeyBits;
        offsets.push_back(dx + dy * kRow + dz * kRow * kRow);
      }

  const float eps_sq = static_cast<float>(eps_m * eps_m);
  // Rounding slack for the double-precision box bounds (the final word is the float test).
  const double slack = 1e-6 * (eps_m + 1.0);
  const double eps_sq_prune = (eps_m + slack) * (eps_m + slack);
  DisjointSets sets(static_cast<std::size_t>(n_cells));
  for (int v = 0; v < n_cells; ++v) {
    for (const std::int64_t off : offsets) {
      const auto key_u = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell_key[v]) + off);
      const int u = cell_of_key.find(key_u);
      if (u < 0) continue;
      if (sets.find(u) == sets.find(v)) continue;
      double min_d = 0.0, max_d = 0.0;
      box_distance_bounds(box[v], box[u], min_d, max_d);
      if (min_d > eps_m + slack) continue;  // no pair can be within eps
      bool linked = max_d < eps_m - slack;   // every pair is within eps
      for (int a = start[v]; a < start[v + 1] && !linked; ++a) {
        const float* p = pts.at(finite[order[a]]);
        if (sq_dist_point_box(p, box[u]) > eps_sq_prune) continue;
        for (int b = start[u]; b < start[u + 1]; ++b) {
          if (within(p, pts.at(finite[order[b]]), eps_sq)) {
            linked = true;
            break;
          }
        }
      }
      if (linked) sets.unite(u, v);
    }
  }

  comp.assign(n, -1);
  for (int c = 0; c < n_cells; ++c) {
    const int root = sets.find(c);
    for (int k = start[c]; k < start[c + 1]; ++k) comp[static_cast<std::size_t>(order[k])] = root;
  }
  return true;
}

/// 90th percentile of the heights above `plane` of the given points (nth_element).
double height_p90(const PointView& pts, const std::vector<int>& members, const Plane& plane) {
  std::vector<double> h(members.size());
  for (std::size_t k = 0; k < members.size(); ++k) {
    const float* p = pts.at(members[k]);
    h[k] = plane.signed_distance(Vec3(p[0], p[1], p[2]));
  }
  const std::size_t q = (h.size() * 9) / 10;
  std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(q), h.end());
  return h[q];
}

/// Components -> labels and infos (the shared tail of both clustering paths): min_points,
/// extents on the original points, the optional height rule, compact labels.
void label_partition(const PointView& pts, const std::vector<int>& finite,
                     const std::vector<int>& comp, int min_points, double min_extent_m,
                     double max_extent_m, const HeightRule* height_rule, ClusterResult& out) {

  // Per component: size, first point, AABB on the original points.
  struct Acc {
    int count = 0;
    int first = std::numeric_limits<int>::max();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  };
  // Compact the component ids (they may be sparse roots).
  std::vector<int> dense(finite.size(), -1);
  std::vector<int> comp_dense(finite.size());
  std::vector<Acc> acc;
  for (std::size_t k = 0; k < finite.size(); ++k) {
    int& d = dense[static_cast<std::size_t>(comp[k])];
    if (d < 0) {
      d = static_cast<int>(acc.size());
      acc.emplace_back();
    }
    comp_dense[k] = d;
    Acc& a = acc[static_cast<std::size_t>(d)];
    ++a.count;
    a.first = std::min(a.first, static_cast<int>(k));
    const Eigen::Vector3d p = Eigen::Map<const Eigen::Vector3f>(pts.at(finite[k])).cast<double>();
    a.lo = a.lo.cwiseMin(p);
    a.hi = a.hi.cwiseMax(p);
    a.sum += p;
  }
  out.num_components = static_cast<int>(acc.size());

  std::vector<int> big;  // components with enough points
  for (std::size_t c = 0; c < acc.size(); ++c)
    if (acc[c].count >= min_points) big.push_back(static_cast<int>(c));
  std::vector<char> accepted(acc.size(), 0);
  for (const int c : big) {
    const double extent = (acc[c].hi - acc[c].lo).norm();
    accepted[c] = extent >= min_extent_m && (max_extent_m <= 0.0 || extent <= max_extent_m);
  }
  // The height rule, on the components that pass the other rules.
  const bool rule = height_rule != nullptr && height_rule->sigmas > 0.0;
  std::vector<double> height(acc.size(), 0.0), range(acc.size(), 0.0), need(acc.size(), 0.0);
  std::vector<char> too_low(acc.size(), 0);
  if (rule) {
    std::vector<std::vector<int>> members(acc.size());
    for (const int c : big)
      if (accepted[c]) members[c].reserve(static_cast<std::size_t>(acc[c].count));
    for (std::size_t k = 0; k < finite.size(); ++k) {
      const int c = comp_dense[k];
      if (accepted[c] && acc[c].count >= min_points) members[c].push_back(finite[k]);
    }
    const HeightRule& hr = *height_rule;
    for (const int c : big) {
      if (!accepted[c]) continue;
      range[c] = (acc[c].sum / acc[c].count - hr.camera).norm();
      need[c] = hr.sigmas * hr.noise_sigma_m * std::pow(range[c] / hr.ref_range_m, hr.exponent);
      height[c] = height_p90(pts, members[c], hr.table);
      if (height[c] < need[c]) {
        too_low[c] = 1;
        accepted[c] = 0;
      }
    }
  }
  std::sort(big.begin(), big.end(), [&](int a, int b) {
    if (accepted[a] != accepted[b]) return accepted[a] > accepted[b];
    if (acc[a].count != acc[b].count) return acc[a].count > acc[b].count;
    return acc[a].first < acc[b].first;
  });
  std::vector<int> label_of(acc.size(), kLabelEnvironment);
  for (const int c : big) {
    ClusterInfo info;
    info.num_points = acc[c].count;
    info.min = acc[c].lo;
    info.max = acc[c].hi;
    info.extent_m = (acc[c].hi - acc[c].lo).norm();
    info.accepted = accepted[c] != 0;
    info.height_m = height[c];
    info.range_m = range[c];
    info.min_height_m = need[c];
    info.too_low = too_low[c] != 0;
    if (info.accepted) {
      info.label = out.num_accepted++;
      label_of[c] = info.label;
    }
    out.clusters.push_back(info);
  }
  for (std::size_t k = 0; k < finite.size(); ++k)
    out.labels[static_cast<std::size_t>(finite[k])] = label_of[static_cast<std::size_t>(comp_dense[k])];
}

}  // namespace

ClusterResult euclidean_clusters(const float* xyz, std::size_t n_rows,
                                 std::size_t row_stride_floats, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m,
                                 double max_abs_coordinate_m, const HeightRule* height_rule) {
  if (n_rows > 0 && xyz == nullptr)
    throw std::invalid_argument("euclidean_clusters: null point buffer");
  if (n_rows > 0 && row_stride_floats < 3)
    throw std::invalid_argument("euclidean_clusters: row stride must be >= 3");
  if (!std::isfinite(eps_m) || eps_m <= 0.0)
    throw std::invalid_argument("euclidean_clusters: eps_m must be a finite radius > 0");
  if (n_rows > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("euclidean_clusters: too many points");
  if (!(max_abs_coordinate_m > 0.0 && max_abs_coordinate_m <= kMaxAbsCoordinateLimit_m))
    throw std::invalid_argument("euclidean_clusters: max_abs_coordinate_m must be in (0, 1e9] m");
  min_points = std::max(min_points, 1);

  const PointView pts{xyz, row_stride_floats};
  ClusterResult out;
  out.labels.assign(n_rows, kLabelInvalid);
  std::vector<int> finite;
  finite.reserve(n_rows);
  for (std::size_t i = 0; i < n_rows; ++i) {
    const float* p = pts.at(static_cast<int>(i));
    if (within_bound(p[0], p[1], p[2], max_abs_coordinate_m)) {
      finite.push_back(static_cast<int>(i));
      out.labels[i] = kLabelEnvironment;
    } else if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) {
      ++out.num_out_of_range;
    }
  }
  out.num_invalid = static_cast<int>(n_rows - finite.size());
  if (finite.empty()) return out;

  std::vector<int> comp;
  const bool fast = std::isfinite(voxel_m) && voxel_m > 0.0 &&
                    components_grid(pts, finite, eps_m, comp);
  if (!fast) comp = components_exact(pts, finite, eps_m);
  label_partition(pts, finite, comp, min_points, min_extent_m, max_extent_m, height_rule, out);
  return out;
}

ClusterResult clusters_from_components(const float* xyz, std::size_t n_rows,
                                       std::size_t row_stride_floats, const std::vector<int>& comp,
                                       int min_points, double min_extent_m, double max_extent_m,
                                       const HeightRule* height_rule) {
  if (comp.size() != n_rows)
    throw std::invalid_argument("clusters_from_components: one component id per row expected");
  ClusterResult out;
  out.labels.assign(n_rows, kLabelEnvironment);
  if (n_rows == 0) return out;
  std::vector<int> finite(n_rows);
  std::iota(finite.begin(), finite.end(), 0);
  for (const int c : comp)
    if (c < 0 || static_cast<std::size_t>(c) >= n_rows)
      throw std::invalid_argument("clusters_from_components: component id out of range");
  label_partition(PointView{xyz, row_stride_floats}, finite, comp, std::max(min_points, 1),
                  min_extent_m, max_extent_m, height_rule, out);
  return out;
}

namespace {
/// Double rows as float; a finite row beyond the bound becomes (FLT_MAX, ...) so that it is
/// still counted as out of range (not as non-finite) after the cast.
ClusterResult clusters_of(const PointsD& points, double eps_m, int min_points, double min_extent_m,
                          double max_extent_m, double voxel_m, double max_abs_coordinate_m) {
  std::vector<float> packed(static_cast<std::size_t>(points.rows()) * 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const bool out = points.row(i).allFinite() &&
                     !within_bound(points(i, 0), points(i, 1), points(i, 2), max_abs_coordinate_m);
    for (int a = 0; a < 3; ++a)
      packed[static_cast<std::size_t>(i) * 3 + a] =
          out ? std::numeric_limits<float>::max() : static_cast<float>(points(i, a));
  }
  return euclidean_clusters(packed.data(), static_cast<std::size_t>(points.rows()), 3, eps_m,
                            min_points, min_extent_m, max_extent_m, voxel_m, max_abs_coordinate_m);
}
}  // namespace

ClusterResult euclidean_clusters(const PointsF& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m,
                                 double max_abs_coordinate_m) {
  return euclidean_clusters(points.data(), static_cast<std::size_t>(points.rows()), 3, eps_m,
                            min_points, min_extent_m, max_extent_m, voxel_m, max_abs_coordinate_m);
}

ClusterResult euclidean_clusters(const PointsD& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m,
                                 double max_abs_coordinate_m) {
  return clusters_of(points, eps_m, min_points, min_extent_m, max_extent_m, voxel_m,
                     max_abs_coordinate_m);
}

}  // namespace grasp_core
