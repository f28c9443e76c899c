// Bindings of the fused depth-image passes (grasp_core/depth_image.hpp) used by the simulated
// camera. Every array is checked here (dtype, shape, C order, writable where written) and
// rejected with a TypeError / ValueError naming the argument, never read out of bounds; the
// work runs with the GIL released (the arrays are kept alive by the caller's references).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <initializer_list>
#include <sstream>
#include <string>

#include "array_input.hpp"
#include "grasp_core/depth_image.hpp"
#include "grasp_core/normal_draws.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

/// The image geometry from the per-column / per-row coordinates and |r|^2 (kept by `keep`).
DepthImageGeometry geometry(const py::object& x, const py::object& y, const py::object& ray_norm2,
                            float fx, float fy, py::array keep[3]) {
  keep[0] = checked<float>(x, "x", {-1}, false);
  keep[1] = checked<float>(y, "y", {-1}, false);
  const py::ssize_t w = keep[0].shape(0), h = keep[1].shape(0);
  keep[2] = checked<float>(ray_norm2, "ray_norm2", {h, w}, false);
  DepthImageGeometry g;
  g.height = static_cast<int>(h);
  g.width = static_cast<int>(w);
  g.x = static_cast<const float*>(keep[0].data());
  g.y = static_cast<const float*>(keep[1].data());
  g.ray_norm2 = static_cast<const float*>(keep[2].data());
  g.fx = fx;
  g.fy = fy;
  return g;
}

void mask_invalid_and_grazing_py(const py::object& depth, const py::object& invalid,
                                 const py::object& x, const py::object& y,
                                 const py::object& ray_norm2, float fx, float fy, float cos2_max) {
  py::array keep[3];
  const DepthImageGeometry g = geometry(x, y, ray_norm2, fx, fy, keep);
  py::array z = checked<float>(depth, "depth", {g.height, g.width}, true);
  py::array inv = checked<bool>(invalid, "invalid", {g.height, g.width}, true);
  float* zp = static_cast<float*>(z.mutable_data());
  auto* ip = static_cast<std::uint8_t*>(inv.mutable_data());
  py::gil_scoped_release release;
  mask_invalid_and_grazing(g, cos2_max, zp, ip);
}

py::array_t<float> depth_to_world_points_py(const py::object& depth, const py::object& invalid,
                                            const py::object& x, const py::object& y,
                                            const py::object& R, const py::object& t) {
  py::array keep[2] = {checked<float>(x, "x", {-1}, false), checked<float>(y, "y", {-1}, false)};
  DepthImageGeometry g;
  g.width = static_cast<int>(keep[0].shape(0));
  g.height = static_cast<int>(keep[1].shape(0));
  g.x = static_cast<const float*>(keep[0].data());
  g.y = static_cast<const float*>(keep[1].data());
  py::array z = checked<float>(depth, "depth", {g.height, g.width}, true);
  py::array inv = checked<bool>(invalid, "invalid", {g.height, g.width}, false);
  py::array rot = checked<float>(R, "R", {3, 3}, false);
  py::array tr = checked<float>(t, "t", {3}, false);
  py::array_t<float> points({static_cast<py::ssize_t>(g.height) * g.width, static_cast<py::ssize_t>(3)});
  float* zp = static_cast<float*>(z.mutable_data());
  const auto* ip = static_cast<const std::uint8_t*>(inv.data());
  const auto* rp = static_cast<const float*>(rot.data());
  const auto* tp = static_cast<const float*>(tr.data());
  float* out = points.mutable_data();
  {
    py::gil_scoped_release release;
    depth_to_world_points(g, rp, tp, zp, ip, out);
  }
  return points;
}

py::array_t<float> metric_depth_py(const py::object& raw, float c_coef, float d_coef) {
  py::array in = checked<float>(raw, "raw", {-1, -1}, false);
  const py::ssize_t h = in.shape(0), w = in.shape(1);
  py::array_t<float> out({h, w});
  const auto* ip = static_cast<const float*>(in.data());
  float* op = out.mutable_data();
  {
    py::gil_scoped_release release;
    metric_depth(static_cast<int>(h), static_cast<int>(w), ip, c_coef, d_coef, op);
  }
  return out;
}

void add_quadratic_depth_noise_py(const py::object& z, const py::object& noise, float ref_range,
                                  float sigma_at_ref) {
  py::array zs = checked<float>(z, "z", {-1, -1}, false);
  py::array ns = checked<float>(noise, "noise", {zs.shape(0), zs.shape(1)}, true);
  const auto* zp = static_cast<const float*>(zs.data());
  float* np_ = static_cast<float*>(ns.mutable_data());
  const auto n = static_cast<std::size_t>(zs.shape(0) * zs.shape(1));
  py::gil_scoped_release release;
  add_quadratic_depth_noise(n, zp, ref_range, sigma_at_ref, np_);
}

void fill_standard_normal_py(const py::object& out, std::uint64_t seed) {
  py::array o = checked<float>(out, "out", {-1, -1}, true);
  float* op = static_cast<float*>(o.mutable_data());
  const auto n = static_cast<std::size_t>(o.shape(0) * o.shape(1));
  py::gil_scoped_release release;
  fill_standard_normal(seed, n, op);
}

}  // namespace

void bind_depth_image(py::module_& m) {
  m.def("metric_depth", &metric_depth_py, py::arg("raw"), py::arg("c_coef"), py::arg("d_coef"),
        "(H, W) float32 metres along the optical axis from a perspective render's (H, W) float32 "
        "depth buffer (rows bottom to top): float(d_coef / (raw + c_coef)) in float64, rows "
        "flipped to top to bottom (mujoco.Renderer's linearisation).");
  m.def("add_quadratic_depth_noise", &add_quadratic_depth_noise_py, py::arg("z"), py::arg("noise"),
        py::arg("ref_range"), py::arg("sigma_at_ref"),
        "In place on noise (H, W) float32, holding standard normal draws: noise = noise * "
        "(((z / ref_range) ** 2) * sigma_at_ref) + z, float32 operations in this order.");
  m.def("fill_standard_normal", &fill_standard_normal_py, py::arg("out"), py::arg("seed"),
        "In place on out (H, W) float32: standard normal draws of the stream of seed (an unsigned "
        "64-bit integer), row by row; the same seed gives the same draws (the depth camera's "
        "noise, one seed per frame).");
  m.def("mask_invalid_and_grazing", &mask_invalid_and_grazing_py, py::arg("depth"), py::arg("invalid"),
        py::arg("x"), py::arg("y"), py::arg("ray_norm2"), py::arg("fx"), py::arg("fy"),
        py::arg("cos2_max"),
        "In place, on an (H, W) float32 depth and its (H, W) bool invalid mask: depth = NaN where "
        "invalid, then invalid |= grazing (a surface seen at more than the angle whose cos^2 is "
        "cos2_max). x (W,), y (H,): (u - cx) / fx and (v - cy) / fy; ray_norm2 (H, W): "
        "1 + x^2 + y^2; all float32. The float32 operations of the camera's numpy formulation, "
        "in its order.");
  m.def("depth_to_world_points", &depth_to_world_points_py, py::arg("depth"), py::arg("invalid"),
        py::arg("x"), py::arg("y"), py::arg("R"), py::arg("t"),
        "depth = NaN where invalid (in place), then the (H*W, 3) float32 world points "
        "((R[i,0] x + R[i,1] y) + R[i,2]) depth + t[i], row v*W + u for pixel (u, v); R (3, 3) "
        "and t (3,) float32: the camera's world pose.");
}

}  // namespace grasp_bind
