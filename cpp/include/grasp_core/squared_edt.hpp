// Exact Euclidean distance transform of a 3-D occupancy grid in integer arithmetic: for every
// voxel, the squared distance (in voxels) to the nearest occupied voxel — separable lower
// envelopes of parabolas, one pass per axis (Meijster, Roerdink and Hesselink's scheme, with
// integer separators), so every value is exact whatever the grid. The binary axis (z, the
// contiguous one) takes two sweeps; the strided x axis runs on transposed slabs.
#pragma once

#include <cstdint>
#include <vector>

namespace grasp_core {

/// Squared distances (row-major nx x ny x nz, voxels) from each voxel to the nearest voxel
/// with occupied != 0; every value is -1 when no voxel is occupied.
std::vector<std::int64_t> squared_distance_transform(const std::uint8_t* occupied, int nx, int ny,
                                                     int nz);

/// The distance field [m] of the same grid as float32, written to out[0 .. nx*ny*nz):
/// ``float(sqrt(double(k)) * voxel_m)`` of each voxel's squared distance k (the values numpy
/// gives for ``(sqrt(k) * voxel_m).astype(float32)``); +infinity everywhere when no voxel is
/// occupied.
void distance_field(const std::uint8_t* occupied, int nx, int ny, int nz, double voxel_m, float* out);

}  // namespace grasp_core
