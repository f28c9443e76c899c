#include <cstdio>
#include <cstdlib>
// SPEC 1.4 — Euclidean clustering (PCL semantics) with an exact voxel fast path.
// See clustering.hpp for the algorithm and the labelling rules.
#include "grasp_core/clustering.hpp"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
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

/// Reference path: pcl::EuclideanClusterExtraction on every point.
/// Returns a component id per point (ids are arbitrary but consistent).
std::vector<int> components_exact(const PointView& pts, const std::vector<int>& finite,
                                  double eps_m) {
  auto cloud = std::make_shared<Cloud>();
  cloud->resize(finite.size());
  for (std::size_t k = 0; k < finite.size(); ++k) {
    const float* p = pts.at(finite[k]);
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
  std::vector<int> comp(finite.size(), -1);
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (const auto i : clusters[c].indices) comp[static_cast<std::size_t>(i)] = static_cast<int>(c);
  // Defensive: a point PCL did not assign is its own component.
  int next = static_cast<int>(clusters.size());
  for (auto& c : comp)
    if (c < 0) c = next++;
  return comp;
}

/// Fast path (exact): voxels + PCL kd-tree over voxel centroids + explicit pair checks.
/// Returns std::nullopt-like empty vector if the cloud is too large for the voxel keys.
bool components_voxel(const PointView& pts, const std::vector<int>& finite, double eps_m,
                      double voxel_m, std::vector<int>& comp) {
  const std::size_t n = finite.size();
  // Leaf capped so that two points of one voxel are always within eps (diagonal < eps).
  const double leaf = std::min(voxel_m, eps_m / std::sqrt(3.0) * (1.0 - 1e-6));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const int i : finite) {
    const float* p = pts.at(i);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], static_cast<double>(p[a]));
      hi[a] = std::max(hi[a], static_cast<double>(p[a]));
    }
  }
  constexpr double kMaxCells = static_cast<double>(1 << 21);  // 21 bits per axis in the key
  for (int a = 0; a < 3; ++a)
    if (!((hi[a] - lo[a]) / leaf < kMaxCells - 1.0)) return false;

  // Sort points by voxel key: each voxel is a contiguous run.
  std::vector<std::pair<std::uint64_t, int>> keyed(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float* p = pts.at(finite[k]);
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const auto cell = static_cast<std::uint64_t>(std::floor((p[a] - lo[a]) / leaf));
      key |= cell << (21 * a);
    }
    keyed[k] = {key, static_cast<int>(k)};
  }
  std::sort(keyed.begin(), keyed.end());

  std::vector<int> order(n);          // point (index into finite) in voxel order
  std::vector<int> start;             // voxel v = order[start[v] .. start[v+1])
  for (std::size_t k = 0; k < n; ++k) {
    order[k] = keyed[k].second;
    if (k == 0 || keyed[k].first != keyed[k - 1].first) start.push_back(static_cast<int>(k));
  }
  const int n_vox = static_cast<int>(start.size());
  start.push_back(static_cast<int>(n));

  // Centroids and radii (largest point-to-centroid distance) per voxel.
  auto centroids = std::make_shared<Cloud>();
  centroids->resize(static_cast<std::size_t>(n_vox));
  std::vector<double> radius(static_cast<std::size_t>(n_vox), 0.0);
  double r_max = 0.0;
  for (int v = 0; v < n_vox; ++v) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = start[v]; k < start[v + 1]; ++k)
      c += Eigen::Map<const Eigen::Vector3f>(pts.at(finite[order[k]])).cast<double>();
    c /= static_cast<double>(start[v + 1] - start[v]);
    double r = 0.0;
    for (int k = start[v]; k < start[v + 1]; ++k)
      r = std::max(r, (Eigen::Map<const Eigen::Vector3f>(pts.at(finite[order[k]])).cast<double>() - c).norm());
    (*centroids)[static_cast<std::size_t>(v)] = pcl::PointXYZ(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()));
    radius[static_cast<std::size_t>(v)] = r;
    r_max = std::max(r_max, r);
  }

  // Voxel adjacency: a kd-tree over the centroids proposes pairs, exact checks decide.
  const float eps_sq = static_cast<float>(eps_m * eps_m);
  // Float slack on the proposal radius so that rounding can never hide a true edge.
  const double slack = 1e-5 * (eps_m + 2.0 * r_max) + 1e-6;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(/*sorted=*/false);
  tree.setInputCloud(centroids);
  DisjointSets sets(static_cast<std::size_t>(n_vox));
  pcl::Indices nbr;
  std::vector<float> nbr_sq;
  for (int v = 0; v < n_vox; ++v) {
    const pcl::PointXYZ& cv = (*centroids)[static_cast<std::size_t>(v)];
    tree.radiusSearch(cv, eps_m + 2.0 * r_max + slack, nbr, nbr_sq);
    for (std::size_t j = 0; j < nbr.size(); ++j) {
      const int u = nbr[j];
      if (u <= v) continue;  // each pair once
      if (sets.find(u) == sets.find(v)) continue;
      const double d = std::sqrt(static_cast<double>(nbr_sq[j]));
      const double ru = radius[static_cast<std::size_t>(u)], rv = radius[static_cast<std::size_t>(v)];
      if (d > eps_m + ru + rv + slack) continue;  // no point pair can be within eps
      bool linked = d + ru + rv + slack < eps_m;   // every point pair is within eps
      for (int a = start[v]; a < start[v + 1] && !linked; ++a) {
        const float* p = pts.at(finite[order[a]]);
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

  if (getenv("SF_DEBUG")) fprintf(stderr, "n=%zu vox=%d rmax=%.4f leaf=%.4f\n", n, n_vox, r_max, leaf);
  comp.assign(n, -1);
  for (int v = 0; v < n_vox; ++v) {
    const int root = sets.find(v);
    for (int k = start[v]; k < start[v + 1]; ++k) comp[static_cast<std::size_t>(order[k])] = root;
  }
  return true;
}

}  // namespace

ClusterResult euclidean_clusters(const float* xyz, std::size_t n_rows,
                                 std::size_t row_stride_floats, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m) {
  if (n_rows > 0 && xyz == nullptr)
    throw std::invalid_argument("euclidean_clusters: null point buffer");
  if (n_rows > 0 && row_stride_floats < 3)
    throw std::invalid_argument("euclidean_clusters: row stride must be >= 3");
  if (!std::isfinite(eps_m) || eps_m <= 0.0)
    throw std::invalid_argument("euclidean_clusters: eps_m must be a finite radius > 0");
  if (n_rows > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("euclidean_clusters: too many points");
  min_points = std::max(min_points, 1);

  const PointView pts{xyz, row_stride_floats};
  ClusterResult out;
  out.labels.assign(n_rows, kLabelInvalid);
  std::vector<int> finite;
  finite.reserve(n_rows);
  for (std::size_t i = 0; i < n_rows; ++i) {
    const float* p = pts.at(static_cast<int>(i));
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) {
      finite.push_back(static_cast<int>(i));
      out.labels[i] = kLabelEnvironment;
    }
  }
  if (finite.empty()) return out;

  std::vector<int> comp;
  const bool fast = std::isfinite(voxel_m) && voxel_m > 0.0 &&
                    components_voxel(pts, finite, eps_m, voxel_m, comp);
  if (!fast) comp = components_exact(pts, finite, eps_m);

  // Per component: size, first point, AABB on the original points.
  struct Acc {
    int count = 0;
    int first = std::numeric_limits<int>::max();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
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
    if (info.accepted) {
      info.label = out.num_accepted++;
      label_of[c] = info.label;
    }
    out.clusters.push_back(info);
  }
  for (std::size_t k = 0; k < finite.size(); ++k)
    out.labels[static_cast<std::size_t>(finite[k])] = label_of[static_cast<std::size_t>(comp_dense[k])];
  return out;
}

namespace {
template <typename Points>
ClusterResult clusters_of(const Points& points, double eps_m, int min_points, double min_extent_m,
                          double max_extent_m, double voxel_m) {
  std::vector<float> packed(static_cast<std::size_t>(points.rows()) * 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int a = 0; a < 3; ++a) packed[static_cast<std::size_t>(i) * 3 + a] = static_cast<float>(points(i, a));
  return euclidean_clusters(packed.data(), static_cast<std::size_t>(points.rows()), 3, eps_m,
                            min_points, min_extent_m, max_extent_m, voxel_m);
}
}  // namespace

ClusterResult euclidean_clusters(const PointsF& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m) {
  return euclidean_clusters(points.data(), static_cast<std::size_t>(points.rows()), 3, eps_m,
                            min_points, min_extent_m, max_extent_m, voxel_m);
}

ClusterResult euclidean_clusters(const PointsD& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m) {
  return clusters_of(points, eps_m, min_points, min_extent_m, max_extent_m, voxel_m);
}

}  // namespace grasp_core
