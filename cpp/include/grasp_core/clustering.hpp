// SPEC 1.4 — Euclidean clustering of object candidates, with extent filters.
//
// Semantics are PCL's Euclidean cluster extraction: clusters are the connected components
// of the graph joining points at distance <= eps. With voxel_m == 0 the components are
// computed by pcl::EuclideanClusterExtraction on every point (the reference). With
// voxel_m > 0 the SAME partition is computed faster (see euclidean_clusters()).
#pragma once

#include "grasp_core/types.hpp"

#include <cstddef>
#include <vector>

namespace grasp_core {

/// One connected component that had at least min_points points.
struct ClusterInfo {
  int label = kLabelEnvironment;  ///< id given to its points if accepted, else kLabelEnvironment
  int num_points = 0;             ///< original points in the component
  double extent_m = 0.0;          ///< diagonal of its axis-aligned box ||max - min|| [m]
  Vec3 min = Vec3::Zero();        ///< AABB corners [m]
  Vec3 max = Vec3::Zero();
  bool accepted = false;          ///< min_extent <= extent <= max_extent (max <= 0: no upper bound)
};

struct ClusterResult {
  /// One per input point: an accepted cluster id >= 0, kLabelEnvironment (noise or a
  /// rejected cluster) or kLabelInvalid (non-finite row).
  std::vector<int> labels;
  /// Every component with >= min_points points: accepted ones first (label 0, 1, ...),
  /// then the rejected ones; each group ordered by decreasing size, ties by lowest point index.
  std::vector<ClusterInfo> clusters;
  int num_accepted = 0;    ///< accepted clusters; their labels are 0 .. num_accepted-1
  int num_components = 0;  ///< all connected components (including noise)
};

/// Euclidean clustering of the finite rows of an N x 3 strided float array
/// (row i at xyz + i * row_stride_floats; row_stride_floats >= 3, else std::invalid_argument).
///
/// Labels are compact: accepted clusters get 0 .. K-1 by decreasing point count (ties:
/// lowest first point index), so the labelling is a deterministic function of the partition.
///
/// Fast path (voxel_m > 0), exact w.r.t. the per-point semantics:
///  1. hash the points into voxels of leaf min(voxel_m, eps/sqrt(3)) (the cap makes any
///     two points of one voxel <= eps apart, so a voxel is always connected inside);
///  2. a PCL kd-tree over the voxel centroids proposes voxel pairs whose centroids are
///     within eps + 2 r_max (r_max = largest point-to-centroid distance of any voxel), a
///     necessary condition for any point pair within eps;
///  3. a proposed pair is joined (union-find) at once if its centroid distance is
///     <= eps - 2 r_max (then every point pair is within eps), otherwise only if an
///     explicit check finds one point pair within eps;
///  4. component labels are mapped back to every original point; cluster_min_points and
///     the extents are evaluated on the original points.
/// eps_m must be > 0 (else std::invalid_argument); min_points < 1 acts as 1.
ClusterResult euclidean_clusters(const float* xyz, std::size_t n_rows,
                                 std::size_t row_stride_floats, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m);
/// Convenience overloads (same semantics).
ClusterResult euclidean_clusters(const PointsF& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m);
ClusterResult euclidean_clusters(const PointsD& points, double eps_m, int min_points,
                                 double min_extent_m, double max_extent_m, double voxel_m);

}  // namespace grasp_core
