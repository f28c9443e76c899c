// Bindings of the planning world's occupancy grid: the voxelisation of the environment points
// (grasp_core/voxel_grid.hpp) and the exact distance transform (grasp_core/squared_edt.hpp).
// The arrays are checked here (dtype, shape, C order) and rejected with a TypeError /
// ValueError naming the argument; the work runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "array_input.hpp"
#include "grasp_core/squared_edt.hpp"
#include "grasp_core/voxel_grid.hpp"

namespace py = pybind11;

namespace grasp_bind {

namespace {

py::array_t<std::int64_t> squared_distance_transform_py(const py::object& occupied) {
  py::array occ = checked<bool>(occupied, "occupied", {-1, -1, -1}, false);
  const py::ssize_t nx = occ.shape(0), ny = occ.shape(1), nz = occ.shape(2);
  if (std::max(nx, std::max(ny, nz)) >= (py::ssize_t{1} << 20))
    throw py::value_error("occupied: a grid side of 2^20 voxels or more is not supported");
  const auto* op = static_cast<const std::uint8_t*>(occ.data());
  std::vector<std::int64_t> sq;
  {
    py::gil_scoped_release release;
    sq = grasp_core::squared_distance_transform(op, static_cast<int>(nx), static_cast<int>(ny),
                                                static_cast<int>(nz));
  }
  py::array_t<std::int64_t> out({nx, ny, nz});
  std::copy(sq.begin(), sq.end(), out.mutable_data());
  return out;
}

py::array_t<float> distance_field_py(const py::object& occupied, double voxel_m) {
  py::array occ = checked<bool>(occupied, "occupied", {-1, -1, -1}, false);
  const py::ssize_t nx = occ.shape(0), ny = occ.shape(1), nz = occ.shape(2);
  if (std::max(nx, std::max(ny, nz)) >= (py::ssize_t{1} << 20))
    throw py::value_error("occupied: a grid side of 2^20 voxels or more is not supported");
  if (!(std::isfinite(voxel_m) && voxel_m > 0))
    throw py::value_error("voxel_m must be a finite size > 0 [m]");
  const auto* op = static_cast<const std::uint8_t*>(occ.data());
  py::array_t<float> out({nx, ny, nz});
  float* dst = out.mutable_data();
  {
    py::gil_scoped_release release;
    grasp_core::distance_field(op, static_cast<int>(nx), static_cast<int>(ny), static_cast<int>(nz), voxel_m,
                               dst);
  }
  return out;
}

std::array<double, 3> corner_of(const py::object& obj, const char* name) {
  py::array a = checked<double>(obj, name, {3}, false);
  const auto* d = static_cast<const double*>(a.data());
  return {d[0], d[1], d[2]};
}

py::tuple voxelize_points_py(const py::object& points, const py::object& lo, const py::object& hi,
                             double voxel_m, std::int64_t pad_voxels, std::int64_t max_voxels) {
  py::array pts = checked<double>(points, "points", {-1, 3}, false);  // (N >= 1)
  const std::array<double, 3> lo3 = corner_of(lo, "lo"), hi3 = corner_of(hi, "hi");
  if (!(std::isfinite(voxel_m) && voxel_m > 0))
    throw py::value_error("voxel_m must be a finite size > 0 [m]");
  if (pad_voxels < 0 || pad_voxels > (std::int64_t{1} << 20))
    throw py::value_error("pad_voxels must be in 0 .. 2^20");
  const auto* p = static_cast<const double*>(pts.data());
  const auto n = static_cast<std::size_t>(pts.shape(0));
  grasp_core::VoxelizedRows rows;
  {
    py::gil_scoped_release release;
    rows = grasp_core::voxelize_rows(p, n, lo3, hi3, voxel_m, pad_voxels);
  }
  const auto m = static_cast<py::ssize_t>(rows.kept.size() / 3);
  py::array_t<double> kept({m, py::ssize_t{3}});
  std::copy(rows.kept.begin(), rows.kept.end(), kept.mutable_data());
  py::array_t<std::int64_t> first(3), shape(3);
  std::copy(rows.first_index.begin(), rows.first_index.end(), first.mutable_data());
  std::copy(rows.shape.begin(), rows.shape.end(), shape.mutable_data());
  const long double n_vox = static_cast<long double>(rows.shape[0]) * rows.shape[1] * rows.shape[2];
  if (m == 0 || n_vox > static_cast<long double>(max_voxels)) return py::make_tuple(kept, first, shape, py::none());
  py::array_t<bool> grid({rows.shape[0], rows.shape[1], rows.shape[2]});
  auto* g = reinterpret_cast<std::uint8_t*>(grid.mutable_data());
  {
    py::gil_scoped_release release;
    std::fill(g, g + static_cast<std::size_t>(n_vox), std::uint8_t{0});
    grasp_core::mark_occupied(rows, g);
  }
  return py::make_tuple(kept, first, shape, grid);
}

}  // namespace

void bind_distance_transform(py::module_& m) {
  m.def("squared_distance_transform", &squared_distance_transform_py, py::arg("occupied"),
        "(nx, ny, nz) int64: for each voxel of a C-ordered bool grid, the exact squared "
        "Euclidean distance in voxels to the nearest True voxel (-1 everywhere when there is "
        "none).");
  m.def("distance_field", &distance_field_py, py::arg("occupied"), py::arg("voxel_m"),
        "(nx, ny, nz) float32: for each voxel of a C-ordered bool grid, the distance [m] to the "
        "nearest True voxel, float32(sqrt(k) * voxel_m) of the exact squared distance k in voxels "
        "(+inf everywhere when there is none).");
  m.def("voxelize_points", &voxelize_points_py, py::arg("points"), py::arg("lo"), py::arg("hi"),
        py::arg("voxel_m"), py::arg("pad_voxels"), py::arg("max_voxels"),
        "(kept (M, 3) float64, first_index (3,) int64, shape (3,) int64, occupied): the finite rows "
        "of an (N, 3) float64 cloud with lo <= p <= hi on every axis (input order), the first voxel "
        "and the size of the grid of their voxels floor((p - lo) / voxel_m) padded by pad_voxels, "
        "and that bool grid with their voxels True; occupied is None when no row is kept or the grid "
        "would have more than max_voxels voxels.");
}

}  // namespace grasp_bind
