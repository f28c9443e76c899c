// Bindings of the contact checks' passes over an object's points (grasp_core/pad_contacts.hpp).
// The arrays are checked here (dtype, shape, C order, column indices in range) and rejected with
// a TypeError / ValueError naming the argument; the work runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "array_input.hpp"
#include "grasp_core/pad_contacts.hpp"

namespace py = pybind11;

namespace grasp_bind {

namespace {

template <typename T>
py::array_t<T> to_array(const std::vector<T>& v) {
  py::array_t<T> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

/// Frame k's column index, each within [0, columns) (named in the error otherwise).
void check_columns(const py::array& col, py::ssize_t columns, const char* name) {
  const auto* c = static_cast<const std::int64_t*>(col.data());
  for (py::ssize_t k = 0; k < col.shape(0); ++k)
    if (c[k] < 0 || c[k] >= columns)
      throw py::value_error(std::string(name) + ": frame " + std::to_string(k) + " reads column " +
                            std::to_string(c[k]) + " of " + std::to_string(columns));
}

/// The validated arrays of a FrameColumns (kept alive by `keep`).
struct Columns {
  grasp_core::FrameColumns f;
  std::vector<py::array> keep;
};

Columns frame_columns(const py::object& xyz, const py::object& column, const py::object& x0) {
  py::array p = checked<float>(xyz, "xyz", {3, -1, -1}, false);
  const py::ssize_t n_cols = p.shape(1), n = p.shape(2);
  py::array c = checked<std::int64_t>(column, "column", {-1}, false);
  const py::ssize_t k = c.shape(0);
  py::array o = checked<double>(x0, "x0", {k}, false);
  check_columns(c, n_cols, "column");
  Columns out;
  const auto* base = static_cast<const float*>(p.data());
  const auto plane = static_cast<std::size_t>(n_cols * n);
  out.f.n_points = static_cast<std::size_t>(n);
  out.f.n_frames = static_cast<std::size_t>(k);
  out.f.x = base, out.f.y = base + plane, out.f.z = base + 2 * plane;
  out.f.column = static_cast<const std::int64_t*>(c.data());
  out.f.x0 = static_cast<const double*>(o.data());
  out.keep = {p, c, o};
  return out;
}

py::tuple depth_bounds_py(const py::object& xyz, const py::object& column, const py::object& x0,
                          double strip_half_width_m, double palm_half_width_m) {
  const Columns c = frame_columns(xyz, column, x0);
  grasp_core::DepthBounds b;
  {
    py::gil_scoped_release release;
    b = grasp_core::pad_depth_bounds(c.f, strip_half_width_m, palm_half_width_m);
  }
  return py::make_tuple(to_array(b.z_first), to_array(b.z_last), to_array(b.z_palm));
}

template <typename T>
grasp_core::Material material_of(const Columns& c, double strip_half_width_m, const py::object& z_tcp,
                                 double half_length_m) {
  py::array z = checked<T>(z_tcp, "z_tcp", {static_cast<py::ssize_t>(c.f.n_frames)}, false);
  const auto* zp = static_cast<const T*>(z.data());
  py::gil_scoped_release release;
  return grasp_core::pad_material<T>(c.f, strip_half_width_m, zp, half_length_m);
}

py::tuple material_py(const py::object& xyz, const py::object& column, const py::object& x0,
                      double strip_half_width_m, const py::object& z_tcp, double half_length_m) {
  const Columns c = frame_columns(xyz, column, x0);
  const grasp_core::Material m = py::isinstance<py::array_t<float>>(z_tcp)
      ? material_of<float>(c, strip_half_width_m, z_tcp, half_length_m)
      : material_of<double>(c, strip_half_width_m, z_tcp, half_length_m);
  return py::make_tuple(to_array(m.y_lo), to_array(m.y_hi), to_array(m.count));
}

py::dict end_dict(const grasp_core::PadEnd& e) {
  py::dict d;
  d["x_lo"] = to_array(e.x_lo), d["x_hi"] = to_array(e.x_hi), d["normal_sum"] = to_array(e.normal_sum);
  d["count"] = to_array(e.count), d["facing"] = to_array(e.facing);
  return d;
}

const float* frame_floats(const py::object& obj, const char* name, std::size_t k, std::vector<py::array>& keep) {
  keep.push_back(checked<float>(obj, name, {static_cast<py::ssize_t>(k)}, false));
  return static_cast<const float*>(keep.back().data());
}

py::dict contact_ends_py(const py::object& xyz, const py::object& column, const py::object& x0,
                         const py::object& closing, const py::object& closing_column, const py::object& z_tcp,
                         const py::object& y_lo, const py::object& y_hi, const py::object& y_mid,
                         const py::object& inner, const py::object& outer, double strip_half_width_m,
                         double half_length_m, double contact_depth_m, double cos_cone,
                         double finger_half_width_m) {
  const Columns c = frame_columns(xyz, column, x0);
  const auto k = c.f.n_frames;
  py::array a = checked<float>(closing, "closing", {-1, static_cast<py::ssize_t>(c.f.n_points)}, false);
  py::array ac = checked<std::int64_t>(closing_column, "closing_column", {static_cast<py::ssize_t>(k)}, false);
  check_columns(ac, a.shape(0), "closing_column");
  py::array z = checked<double>(z_tcp, "z_tcp", {static_cast<py::ssize_t>(k)}, false);
  std::vector<py::array> keep;
  const float* lo = frame_floats(y_lo, "y_lo", k, keep);
  const float* hi = frame_floats(y_hi, "y_hi", k, keep);
  const float* mid = frame_floats(y_mid, "y_mid", k, keep);
  const float* in = frame_floats(inner, "inner", k, keep);
  const float* out_ = frame_floats(outer, "outer", k, keep);
  grasp_core::EndLimits lim;
  lim.strip_half_width_m = strip_half_width_m, lim.half_length_m = half_length_m;
  lim.contact_depth_m = static_cast<float>(contact_depth_m), lim.cos_cone = static_cast<float>(cos_cone);
  lim.finger_half_width_m = finger_half_width_m;
  grasp_core::ContactEnds e;
  {
    py::gil_scoped_release release;
    e = grasp_core::pad_contact_ends(c.f, static_cast<const float*>(a.data()),
                                     static_cast<const std::int64_t*>(ac.data()), lim,
                                     static_cast<const double*>(z.data()), lo, hi, mid, in, out_);
  }
  py::dict d;
  d["upper"] = end_dict(e.upper), d["lower"] = end_dict(e.lower);
  d["blocked_upper"] = to_array(e.blocked_upper), d["blocked_lower"] = to_array(e.blocked_lower);
  return d;
}

}  // namespace

void bind_pad_contacts(py::module_& m) {
  m.def("pad_depth_bounds", &depth_bounds_py, py::arg("xyz"), py::arg("column"), py::arg("x0"),
        py::arg("strip_half_width_m"), py::arg("palm_half_width_m"),
        "(z_first, z_last, z_palm) float32 (K,): per frame the smallest and largest Z of the points "
        "with |X - x0| <= strip_half_width_m (float64) and the smallest Z of those within "
        "palm_half_width_m (inf / -inf: none). xyz: (3, C, N) float32, the points' X, Y, Z in "
        "each of C columns; column (K,) int64: each frame's column; x0 (K,) float64.");
  m.def("pad_material", &material_py, py::arg("xyz"), py::arg("column"), py::arg("x0"),
        py::arg("strip_half_width_m"), py::arg("z_tcp"), py::arg("half_length_m"),
        "(y_lo, y_hi float32, count int64) (K,): per frame the smallest and largest Y and the "
        "count of the points in the pads' strip with |Z - z_tcp| <= half_length_m, computed in "
        "z_tcp's type (float32 or float64).");
  m.def("pad_contact_ends", &contact_ends_py, py::arg("xyz"), py::arg("column"), py::arg("x0"),
        py::arg("closing"), py::arg("closing_column"), py::arg("z_tcp"), py::arg("y_lo"), py::arg("y_hi"),
        py::arg("y_mid"), py::arg("inner"), py::arg("outer"), py::arg("strip_half_width_m"),
        py::arg("half_length_m"), py::arg("contact_depth_m"), py::arg("cos_cone"),
        py::arg("finger_half_width_m"),
        "{'upper', 'lower': {x_lo, x_hi, normal_sum (float32), count, facing (int64)}, "
        "'blocked_upper', 'blocked_lower'}: per frame the contact patches at the material's ends "
        "and the points in each finger's way (grasp_core/pad_contacts.hpp). closing (Q, N) "
        "float32: |n.c| of the points' normals per closing axis, closing_column (K,) int64.");
}

}  // namespace grasp_bind
