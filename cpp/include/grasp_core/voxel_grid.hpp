// The planning world's occupancy grid from environment points: the rows inside a workspace box,
// their voxel indices, and the padded grid of the occupied voxels. The indices are
// floor((p - lo) / voxel) in float64, operation for operation what numpy computes, so the grid
// is the one of the array formulation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// The rows of an (n, 3) cloud inside a box, with the voxel grid that spans them.
struct VoxelizedRows {
  std::vector<double> kept;                   ///< (m, 3) the finite rows inside the box, in input order
  std::vector<std::int64_t> index;            ///< (m, 3) their voxel indices from the box's corner
  std::array<std::int64_t, 3> first_index{};  ///< the grid's first voxel (the indices' minimum - pad)
  std::array<std::int64_t, 3> shape{};        ///< the grid's voxels per axis (0 when m == 0)
};

/// The finite rows of `points` (n rows of 3, C order) with lo[j] <= p[j] <= hi[j] on every axis,
/// their voxel indices floor((p - lo) / voxel_m), and the grid of those voxels padded by
/// `pad_voxels` on every side.
VoxelizedRows voxelize_rows(const double* points, std::size_t n, const std::array<double, 3>& lo,
                            const std::array<double, 3>& hi, double voxel_m, std::int64_t pad_voxels);

/// Marks (1) the voxels of `rows` in `grid` (rows.shape, C order, zeroed by the caller).
void mark_occupied(const VoxelizedRows& rows, std::uint8_t* grid);

}  // namespace grasp_core
