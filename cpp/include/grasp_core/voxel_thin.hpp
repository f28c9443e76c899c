// Thinning of a labelled cloud to one point per (voxel, owner) pair: the first point of each
// pair, pairs in increasing key order — what numpy's
// `np.unique(key, return_index=True)[1]` gives over the key below, index for index, computed
// with a radix sort instead of a comparison sort, or with no sort when the cloud's box holds
// few possible keys (at most 64 per point): a bit per key marks those met, and a key's rank
// among them places its first point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// Positions of the first point of each distinct (voxel, owner) pair of `n` points
/// (`points`: n x 3 row-major float64, finite; `owner`: n labels), in increasing order of the
/// key ((ix * dy + iy) * dz + iz) * n_owner + (owner - min owner), where
/// i = floor(p / voxel_m) - its minimum over the cloud per axis and d = its maximum + 1.
/// Integer arithmetic wraps as numpy's int64 does. Empty for n == 0.
std::vector<std::int64_t> first_per_voxel(std::size_t n, const double* points,
                                          const std::int64_t* owner, double voxel_m);

/// Who owns a labelled row of a frame (labels as the scene filter gives them: >= 0 an object
/// group, `environment_label` the environment, anything else dropped).
struct RowOwners {
  std::vector<std::int64_t> of_label;  ///< owner of object group g (g < size), else `untracked`
  std::int64_t untracked = -2;         ///< owner of an object group the table does not name
  std::int64_t environment = -1;       ///< owner of the environment rows ...
  bool environment_emitted = false;    ///< ... kept only when the filter emits them
  int environment_label = -1;
};

/// One frame's rows thinned to one per (voxel, owner) pair.
struct ThinnedRows {
  std::vector<double> points;       ///< m x 3 row-major, the kept rows' values as float64
  std::vector<std::int64_t> owner;  ///< m
};

/// The rows of `n` labelled points (`xyz`: row i at xyz + i * row_stride, three values) that
/// have an owner (`owners`) and three finite coordinates, as float64, thinned with
/// first_per_voxel: the first of each (voxel, owner) pair, pairs in key order.
ThinnedRows thin_owned_rows(std::size_t n, const float* xyz, std::size_t row_stride,
                            const std::int32_t* labels, const RowOwners& owners, double voxel_m);
ThinnedRows thin_owned_rows(std::size_t n, const double* xyz, std::size_t row_stride,
                            const std::int32_t* labels, const RowOwners& owners, double voxel_m);

}  // namespace grasp_core
