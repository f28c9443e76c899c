// Thinning of a labelled cloud to one point per (voxel, owner) pair: the first point of each
// pair, pairs in increasing key order — what numpy's
// `np.unique(key, return_index=True)[1]` gives over the key below, index for index, computed
// with a radix sort instead of a comparison sort (of the first point of each key only, when
// the cloud's box holds few possible keys: at most 64 per point).
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

}  // namespace grasp_core
