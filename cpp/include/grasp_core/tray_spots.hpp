// The cells of a tray grid where a held object and the hand fit, for one TCP rotation (the TCP
// above a cell's centre): the object's cells lie inside the walls and nothing beside it stands
// higher than what it stands on, and every hand sphere clears the walls and contents. Each test
// takes the highest value over a set of cells around every cell, from maxima over runs of
// columns (a sparse table per array). The cells near discs are found with the float64
// operations, in the order, of the numpy formulation in
// grasp_pipeline.orchestration.execution.tray_spots (this file's object is compiled with
// -ffp-contract=off), and maxima are exact: the verdicts are the same whichever computes them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// Discs in the grid's axes: `xy` n x 2 row-major [m], radii `r` [m].
struct Discs {
  const double* xy = nullptr;
  const double* r = nullptr;
  std::size_t n = 0;
};

/// A tray grid of `nu` x `nv` cells (row-major arrays): `contents` the height of what lies in
/// each cell, `heights` that or the walls' height where higher, `inside` 1 on the floor away
/// from the walls; `rim_m` counts for the hand outside the grid.
struct SpotGrid {
  std::int64_t nu = 0, nv = 0;
  const double* contents = nullptr;
  const double* heights = nullptr;
  const std::uint8_t* inside = nullptr;
  double rim_m = 0;
  double cell_m = 0;
};

/// What one rotation puts where: the object's spheres (grown by `spacing_m`), the cells under
/// its points (`under`: n_under x 2 offsets from the TCP's cell, repeats allowed), the hand's
/// spheres (grown by `spacing_m`) with, per sphere, the highest content allowed under it with
/// the object on the floor.
struct SpotStamp {
  Discs object;
  const std::int64_t* under = nullptr;
  std::size_t n_under = 0;
  Discs hand;
  const double* hand_limit = nullptr;
  double spacing_m = 0;
};

/// Offsets (pairs, row-major, in increasing (u, v) order) of the cells (the TCP at the centre
/// of cell (0, 0)) that come within `pad_m` of any of `discs`.
std::vector<std::int64_t> cells_near(const Discs& discs, double pad_m, double cell_m);

/// For every cell (nu x nv, row-major): `ok` 1 where the object and the hand fit with the TCP
/// above it, and `support` the height of what the object stands on there (0: the floor);
/// `tolerance_m`: how much higher than its support a neighbour of the object may stand.
void spot_cells(const SpotGrid& grid, const SpotStamp& stamp, double tolerance_m,
                std::uint8_t* ok, double* support);

}  // namespace grasp_core
