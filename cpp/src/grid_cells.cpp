#include "grasp_core/grid_cells.hpp"

#include <cmath>

namespace grasp_core {

template <typename T>
void points_in_grid_cells(std::size_t n, const T* points, const RotatedGrid& g,
                          std::vector<std::int64_t>* rows, std::vector<std::int64_t>* cells) {
  rows->clear();
  cells->clear();
  for (std::size_t r = 0; r < n; ++r) {
    const double x = static_cast<double>(points[3 * r]);
    const double y = static_cast<double>(points[3 * r + 1]);
    const double z = static_cast<double>(points[3 * r + 2]);
    if (!(x >= g.lo[0] && x <= g.hi[0] && y >= g.lo[1] && y <= g.hi[1]) || !std::isfinite(z)) continue;
    const double d0 = x - g.center[0], d1 = y - g.center[1];
    double u = d0 * g.axes[0] + d1 * g.axes[2];
    double v = d0 * g.axes[1] + d1 * g.axes[3];
    u += g.half[0];
    v += g.half[1];
    const auto i = static_cast<std::int64_t>(std::floor(u / g.cell_m));
    const auto j = static_cast<std::int64_t>(std::floor(v / g.cell_m));
    if (i < 0 || i >= g.shape[0] || j < 0 || j >= g.shape[1]) continue;
    rows->push_back(static_cast<std::int64_t>(r));
    cells->push_back(i);
    cells->push_back(j);
  }
}

template void points_in_grid_cells<float>(std::size_t, const float*, const RotatedGrid&,
                                          std::vector<std::int64_t>*, std::vector<std::int64_t>*);
template void points_in_grid_cells<double>(std::size_t, const double*, const RotatedGrid&,
                                           std::vector<std::int64_t>*, std::vector<std::int64_t>*);

}  // namespace grasp_core
