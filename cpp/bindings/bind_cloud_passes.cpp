// Bindings of the passes over whole clouds that the orchestration runs per frame: the voxel
// thinning of the scene cloud (grasp_core/voxel_thin.hpp), the tray grid's cells
// (grasp_core/grid_cells.hpp) and thin products of points times axes
// (grasp_core/thin_matmul.hpp). The arrays are checked here (dtype, shape, C order, finite
// where required) and rejected with a TypeError / ValueError naming the argument; the work
// runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "array_input.hpp"
#include "grasp_core/grid_cells.hpp"
#include "grasp_core/thin_matmul.hpp"
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

/// A vector's values as a numpy array of `shape` that owns them (no copy).
template <typename T>
py::array_t<T> owning_array(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(values));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), owner);
}

template <typename F>
grasp_core::ThinnedRows thin_owned_rows_of(const py::object& points, const py::object& labels,
                                           const grasp_core::RowOwners& owners, double voxel_m) {
  py::array p = checked<F>(points, "points", {-1, 3}, false);
  const py::ssize_t n = p.shape(0);
  py::array l = checked<std::int32_t>(labels, "labels", {n}, false);
  const auto* pp = static_cast<const F*>(p.data());
  const auto* lp = static_cast<const std::int32_t*>(l.data());
  py::gil_scoped_release release;
  return grasp_core::thin_owned_rows(static_cast<std::size_t>(n), pp, 3, lp, owners, voxel_m);
}

py::tuple thin_owned_rows_py(const py::object& points, const py::object& labels,
                             std::vector<std::int64_t> owner_of_label, bool environment_emitted,
                             std::int64_t environment_owner, std::int64_t untracked_owner,
                             int environment_label, double voxel_m) {
  if (!(voxel_m > 0.0) || !std::isfinite(voxel_m))
    throw py::value_error("voxel_m: expected a positive finite size in metres, got " +
                          std::to_string(voxel_m));
  if (py::isinstance<py::array>(points)) {  // a frame without rows: nothing to keep
    const auto a = py::reinterpret_borrow<py::array>(points);
    if (a.ndim() == 2 && a.shape(0) == 0 && a.shape(1) == 3)
      return py::make_tuple(py::array_t<double>(std::vector<py::ssize_t>{0, 3}),
                            py::array_t<std::int64_t>(std::vector<py::ssize_t>{0}));
  }
  grasp_core::RowOwners owners;
  owners.of_label = std::move(owner_of_label);
  owners.untracked = untracked_owner;
  owners.environment = environment_owner;
  owners.environment_emitted = environment_emitted;
  owners.environment_label = environment_label;
  grasp_core::ThinnedRows rows = py::isinstance<py::array_t<float>>(points)
      ? thin_owned_rows_of<float>(points, labels, owners, voxel_m)
      : thin_owned_rows_of<double>(points, labels, owners, voxel_m);
  const auto m = static_cast<py::ssize_t>(rows.owner.size());
  return py::make_tuple(owning_array(std::move(rows.points), {m, 3}), owning_array(std::move(rows.owner), {m}));
}

/// Two finite float64 values from a sequence / array (named in errors).
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

void pair_of(const py::object& obj, const char* name, double out[2]) {
  py::array a = checked<double>(DoubleArray::ensure(obj), name, {2}, false);
  const auto* p = static_cast<const double*>(a.data());
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
    throw py::value_error(std::string(name) + ": expected two finite values");
  out[0] = p[0], out[1] = p[1];
}

template <typename T>
void grid_cells_of(const py::array& pts, const grasp_core::RotatedGrid& g,
                   std::vector<std::int64_t>* rows, std::vector<std::int64_t>* cells) {
  const auto* p = static_cast<const T*>(pts.data());
  const auto n = static_cast<std::size_t>(pts.shape(0));
  py::gil_scoped_release release;
  grasp_core::points_in_grid_cells<T>(n, p, g, rows, cells);
}

py::tuple points_in_grid_cells_py(const py::object& points, const py::object& center,
                                  const py::object& axes, const py::object& half, double cell_m,
                                  std::int64_t nu, std::int64_t nv, const py::object& lo,
                                  const py::object& hi) {
  grasp_core::RotatedGrid g;
  pair_of(center, "center", g.center);
  pair_of(half, "half", g.half);
  pair_of(lo, "lo", g.lo);
  pair_of(hi, "hi", g.hi);
  py::array ax = checked<double>(DoubleArray::ensure(axes), "axes", {2, 2}, false);
  std::copy_n(static_cast<const double*>(ax.data()), 4, g.axes);
  if (!(cell_m > 0.0) || !std::isfinite(cell_m) || nu < 1 || nv < 1)
    throw py::value_error("cell_m must be a positive size in metres and the shape at least 1 x 1");
  g.cell_m = cell_m, g.shape[0] = nu, g.shape[1] = nv;
  std::vector<std::int64_t> rows, cells;
  const bool f32 = py::isinstance<py::array_t<float>>(points);
  py::array pts = f32 ? checked<float>(points, "points", {-1, 3}, false)
                      : checked<double>(points, "points", {-1, 3}, false);
  if (f32)
    grid_cells_of<float>(pts, g, &rows, &cells);
  else
    grid_cells_of<double>(pts, g, &rows, &cells);
  py::array_t<std::int64_t> r(static_cast<py::ssize_t>(rows.size()));
  py::array_t<std::int64_t> c({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(2)});
  std::copy(rows.begin(), rows.end(), r.mutable_data());
  std::copy(cells.begin(), cells.end(), c.mutable_data());
  return py::make_tuple(r, c);
}

template <typename T>
py::array thin_matmul_of(const py::object& a_obj, const py::object& b_obj) {
  py::array a = checked<T>(a_obj, "a", {-1, -1}, false);
  const py::ssize_t m = a.shape(0), k = a.shape(1);
  py::array b = checked<T>(b_obj, "b", {k, -1}, false);
  const py::ssize_t n = b.shape(1);
  py::array_t<T> out({m, n});
  const auto* ap = static_cast<const T*>(a.data());
  const auto* bp = static_cast<const T*>(b.data());
  T* op = out.mutable_data();
  py::gil_scoped_release release;
  grasp_core::thin_matmul<T>(static_cast<std::size_t>(m), static_cast<std::size_t>(k),
                             static_cast<std::size_t>(n), ap, bp, op);
  return out;
}

py::array thin_matmul_py(const py::object& a, const py::object& b) {
  if (py::isinstance<py::array_t<float>>(a)) return thin_matmul_of<float>(a, b);
  return thin_matmul_of<double>(a, b);
}

}  // namespace

void bind_cloud_passes(py::module_& m) {
  m.def("first_per_voxel", &first_per_voxel_py, py::arg("points"), py::arg("owner"),
        py::arg("voxel_m"),
        "Positions (int64) of the first point of each distinct (voxel, owner) pair of an "
        "(N, 3) float64 cloud of finite points with (N,) int64 owners, in increasing order of "
        "the pair's key ((ix * dy + iy) * dz + iz) * n_owner + owner - min(owner), voxel "
        "indices counted from the cloud's minimum per axis: np.unique(key, return_index=True)[1].");
  m.def("thin_owned_rows", &thin_owned_rows_py, py::arg("points"), py::arg("labels"),
        py::arg("owner_of_label"), py::arg("environment_emitted"), py::arg("environment_owner"),
        py::arg("untracked_owner"), py::arg("environment_label"), py::arg("voxel_m"),
        "(points (M, 3) float64, owner (M,) int64): the rows of an (N, 3) float32/float64 "
        "frame cloud with (N,) int32 scene-filter labels that have an owner — an object group "
        "g >= 0 owned by owner_of_label[g] (untracked_owner past its end), the environment label "
        "owned by environment_owner when environment_emitted — and finite coordinates, thinned "
        "to the first row of each (voxel, owner) pair in first_per_voxel's key order.");
  m.def("thin_matmul", &thin_matmul_py, py::arg("a"), py::arg("b"),
        "a (M, K) @ b (K, N), both C-ordered float32 or both float64, on the calling thread, "
        "each element summed in order k = 0, 1, ... without fused multiply-add: the same "
        "values on every machine and thread count.");
  m.def("points_in_grid_cells", &points_in_grid_cells_py, py::arg("points"), py::arg("center"),
        py::arg("axes"), py::arg("half"), py::arg("cell_m"), py::arg("nu"), py::arg("nv"),
        py::arg("lo"), py::arg("hi"),
        "(rows, cells): the positions (M,) int64 of the points of an (N, 3) float32/float64 "
        "cloud with x/y within [lo, hi] and a finite z whose cell of the rotated grid "
        "(floor((d0 axes[0, j] + d1 axes[1, j] + half[j]) / cell_m), d = xy - center) lies in "
        "nu x nv, in their order, and those cells (M, 2) int64.");
}

}  // namespace grasp_bind
