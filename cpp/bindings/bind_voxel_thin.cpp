// Binding of the voxel thinning (grasp_core/voxel_thin.hpp) used by the scene cloud. The
// arrays are checked here (dtype, shape, C order, finite points) and rejected with a
// TypeError / ValueError naming the argument; the work runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "array_input.hpp"
#include "grasp_core/voxel_thin.hpp"

namespace py = pybind11;

namespace grasp_bind {

namespace {

py::array_t<std::int64_t> first_per_voxel_py(const py::object& points, const py::object& owner,
                                             double voxel_m) {
  if (!(voxel_m > 0.0) || !std::isfinite(voxel_m))
    throw py::value_error("voxel_m: expected a positive finite size in metres, got " +
                          std::to_string(voxel_m));
  py::array p = checked<double>(points, "points", {-1, 3}, false);
  const py::ssize_t n = p.shape(0);
  py::array o = checked<std::int64_t>(owner, "owner", {n}, false);
  const auto* pp = static_cast<const double*>(p.data());
  const auto* op = static_cast<const std::int64_t*>(o.data());
  for (py::ssize_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(pp[i]))
      throw py::value_error("points: row " + std::to_string(i / 3) +
                            " is not finite; drop NaN/inf rows before thinning");
  std::vector<std::int64_t> first;
  {
    py::gil_scoped_release release;
    first = grasp_core::first_per_voxel(static_cast<std::size_t>(n), pp, op, voxel_m);
  }
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(first.size()));
  std::copy(first.begin(), first.end(), out.mutable_data());
  return out;
}

}  // namespace

void bind_voxel_thin(py::module_& m) {
  m.def("first_per_voxel", &first_per_voxel_py, py::arg("points"), py::arg("owner"),
        py::arg("voxel_m"),
        "Positions (int64) of the first point of each distinct (voxel, owner) pair of an "
        "(N, 3) float64 cloud of finite points with (N,) int64 owners, in increasing order of "
        "the pair's key ((ix * dy + iy) * dz + iz) * n_owner + owner - min(owner), voxel "
        "indices counted from the cloud's minimum per axis: np.unique(key, return_index=True)[1].");
}

}  // namespace grasp_bind
