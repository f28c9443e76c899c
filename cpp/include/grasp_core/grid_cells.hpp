// The points of a cloud that fall in the cells of a rotated 2-D grid (a tray floor's square
// cells in the floor's axes), in one pass: a bounding test on world x/y, then the cell index
// of each point kept. Every value is the float64 result of the same operations, in the same
// order, as the numpy formulation in grasp_pipeline.orchestration.execution.tray (this file's
// object is compiled with -ffp-contract=off), so the cells are identical whichever computes
// them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// A grid of `shape[0] x shape[1]` square cells of `cell_m` over a footprint centred on
/// `center` (world x/y) with unit axes as the columns of `axes` (row-major 2 x 2) and half
/// sizes `half` along them; `lo`/`hi`: the world x/y box the points must lie in (inclusive)
/// to be indexed at all.
struct RotatedGrid {
  double center[2] = {0, 0};
  double axes[4] = {1, 0, 0, 1};
  double half[2] = {0, 0};
  double cell_m = 1;
  std::int64_t shape[2] = {1, 1};
  double lo[2] = {0, 0}, hi[2] = {0, 0};
};

/// Points (n x 3 row-major, float or double) in a cell of `grid`, in their order: `rows` the
/// positions of the points with x/y in the box and a finite z whose cell
/// (floor((d . axes[:, j] + half[j]) / cell_m), d = xy - center, d0 a0j + d1 a1j in that order)
/// lies in the grid; `cells` their (i, j) indices, two per row kept.
template <typename T>
void points_in_grid_cells(std::size_t n, const T* points, const RotatedGrid& grid,
                          std::vector<std::int64_t>* rows, std::vector<std::int64_t>* cells);

}  // namespace grasp_core
