// Exact Euclidean distance transform of a 3-D occupancy grid in integer arithmetic: for every
// voxel, the squared distance (in voxels) to the nearest occupied voxel — separable lower
// envelopes of parabolas, one pass per axis (Meijster, Roerdink and Hesselink's scheme, with
// integer separators), so every value is exact whatever the grid.
#pragma once

#include <cstdint>
#include <vector>

namespace grasp_core {

/// Squared distances (row-major nx x ny x nz, voxels) from each voxel to the nearest voxel
/// with occupied != 0; every value is -1 when no voxel is occupied.
std::vector<std::int64_t> squared_distance_transform(const std::uint8_t* occupied, int nx, int ny,
                                                     int nz);

}  // namespace grasp_core
