// Binding of the tray's free-cell search for one TCP rotation (grasp_core/tray_spots.hpp). The
// arrays are checked here (dtype, shape, C order) and rejected with a TypeError / ValueError
// naming the argument; the work runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "array_input.hpp"
#include "grasp_core/tray_spots.hpp"

namespace py = pybind11;

namespace grasp_bind {

namespace {

/// `obj` as a C-ordered (n, cols) array of dtype T, n >= 0 (cols 0: a 1-D (n,) array).
template <typename T>
py::array rows_of(const py::object& obj, const char* name, py::ssize_t n, py::ssize_t cols) {
  const std::string want = py::str(py::dtype::of<T>()).cast<std::string>();
  if (!py::isinstance<py::array>(obj) || !has_dtype<T>(py::reinterpret_borrow<py::array>(obj)))
    throw py::type_error(std::string(name) + ": expected a numpy array of dtype " + want);
  py::array a = py::reinterpret_borrow<py::array>(obj);
  const bool shape_ok = cols == 0 ? (a.ndim() == 1 && (n < 0 || a.shape(0) == n))
                                  : (a.ndim() == 2 && a.shape(1) == cols && (n < 0 || a.shape(0) == n));
  if (!shape_ok)
    throw py::value_error(std::string(name) + ": expected shape " +
                          (cols == 0 ? "(n,)" : "(n, " + std::to_string(cols) + ")") +
                          (n < 0 ? "" : " with n = " + std::to_string(n)));
  if (!(a.flags() & py::array::c_style))
    throw py::value_error(std::string(name) + ": expected a C-ordered array (numpy.ascontiguousarray)");
  return a;
}

grasp_core::Discs discs_of(const py::array& xy, const py::array& r) {
  return {static_cast<const double*>(xy.data()), static_cast<const double*>(r.data()),
          static_cast<std::size_t>(xy.shape(0))};
}

py::tuple spot_cells_py(const py::object& contents, const py::object& heights, const py::object& inside,
                        double rim_m, double cell_m, const py::object& object_xy, const py::object& object_r,
                        const py::object& under, const py::object& hand_xy, const py::object& hand_r,
                        const py::object& hand_limit, double spacing_m, double tolerance_m) {
  py::array c = checked<double>(contents, "contents", {-1, -1}, false);
  const py::ssize_t nu = c.shape(0), nv = c.shape(1);
  py::array h = checked<double>(heights, "heights", {nu, nv}, false);
  py::array in = checked<bool>(inside, "inside", {nu, nv}, false);
  py::array oxy = rows_of<double>(object_xy, "object_xy", -1, 2);
  py::array orad = rows_of<double>(object_r, "object_r", oxy.shape(0), 0);
  py::array und = rows_of<std::int64_t>(under, "under", -1, 2);
  py::array hxy = rows_of<double>(hand_xy, "hand_xy", -1, 2);
  py::array hrad = rows_of<double>(hand_r, "hand_r", hxy.shape(0), 0);
  py::array hlim = rows_of<double>(hand_limit, "hand_limit", hxy.shape(0), 0);
  if (!(cell_m > 0.0) || !std::isfinite(cell_m) || !(spacing_m >= 0.0) || !std::isfinite(spacing_m))
    throw py::value_error("cell_m must be a positive size and spacing_m a size >= 0, in metres");
  grasp_core::SpotGrid g;
  g.nu = nu, g.nv = nv, g.rim_m = rim_m, g.cell_m = cell_m;
  g.contents = static_cast<const double*>(c.data());
  g.heights = static_cast<const double*>(h.data());
  g.inside = static_cast<const std::uint8_t*>(in.data());
  grasp_core::SpotStamp s;
  s.object = discs_of(oxy, orad);
  s.under = static_cast<const std::int64_t*>(und.data());
  s.n_under = static_cast<std::size_t>(und.shape(0));
  s.hand = discs_of(hxy, hrad);
  s.hand_limit = static_cast<const double*>(hlim.data());
  s.spacing_m = spacing_m;
  py::array_t<bool> ok({nu, nv});
  py::array_t<double> support({nu, nv});
  auto* okp = reinterpret_cast<std::uint8_t*>(ok.mutable_data());
  double* sp = support.mutable_data();
  {
    py::gil_scoped_release release;
    grasp_core::spot_cells(g, s, tolerance_m, okp, sp);
  }
  return py::make_tuple(ok, support);
}

}  // namespace

void bind_tray_spots(py::module_& m) {
  m.def("tray_spot_cells", &spot_cells_py, py::arg("contents"), py::arg("heights"), py::arg("inside"),
        py::arg("rim_m"), py::arg("cell_m"), py::arg("object_xy"), py::arg("object_r"), py::arg("under"),
        py::arg("hand_xy"), py::arg("hand_r"), py::arg("hand_limit"), py::arg("spacing_m"),
        py::arg("tolerance_m"),
        "(ok (nu, nv) bool, support (nu, nv) float64) of a tray grid (contents, heights: "
        "(nu, nv) float64; inside: (nu, nv) bool) for one TCP rotation: where the object "
        "(discs object_xy (M, 2), object_r (M,) in the grid's axes, grown by spacing_m; the "
        "cells under its points: under (J, 2) int64 offsets) and the hand (discs hand_xy, hand_r, "
        "each with the highest content allowed under it, hand_limit) fit with the TCP above a "
        "cell, and the height of what the object stands on there.");
}

}  // namespace grasp_bind
