// Binding of the exact squared distance transform (grasp_core/squared_edt.hpp) used by the
// planning world's occupancy map. The grid is checked here (bool, 3-D, C order, non-empty)
// and rejected with a TypeError / ValueError naming the argument; the work runs with the GIL
// released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "array_input.hpp"
#include "grasp_core/squared_edt.hpp"

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

}  // namespace

void bind_distance_transform(py::module_& m) {
  m.def("squared_distance_transform", &squared_distance_transform_py, py::arg("occupied"),
        "(nx, ny, nz) int64: for each voxel of a C-ordered bool grid, the exact squared "
        "Euclidean distance in voxels to the nearest True voxel (-1 everywhere when there is "
        "none).");
}

}  // namespace grasp_bind
