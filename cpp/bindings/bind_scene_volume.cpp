// Bindings of the scene volume (grasp_core::SceneVolume): log-odds occupancy over a world box,
// integrated from depth images. Every array is checked at this edge (dtype, shape, finite
// poses) and rejected with a TypeError / ValueError naming the argument; the work runs with
// the GIL released under the object's mutex (guarded.hpp).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "array_input.hpp"
#include "guarded.hpp"
#include "grasp_core/scene_volume.hpp"
#include "planning_input.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

using planning_input::Arr;
using planning_input::real_array;

/// A (H, W) float32 depth image read in place when its rows are float32 with adjacent
/// pixels; float64 (or odd strides) is copied to float32.
struct DepthView {
  py::array keep;
  const float* data = nullptr;
  std::size_t row_stride = 0;  ///< in floats
  int height = 0, width = 0;
};

DepthView depth_view(const py::object& obj) {
  if (!py::isinstance<py::array>(obj))
    throw py::type_error("depth: expected a numpy array of shape (H, W) with dtype float32, got " +
                         describe(obj) + " (convert with numpy.asarray(depth, dtype=numpy.float32))");
  py::array arr = py::reinterpret_borrow<py::array>(obj);
  const bool f32 = has_dtype<float>(arr);
  if (!f32 && !has_dtype<double>(arr))
    throw py::type_error("depth: expected dtype float32 (or float64), got " +
                         py::str(arr.dtype()).cast<std::string>() + " (convert with .astype(numpy.float32))");
  if (arr.ndim() != 2 || arr.shape(0) == 0 || arr.shape(1) == 0) {
    std::ostringstream os;
    os << "depth: expected a non-empty image of shape (H, W) [m], got shape (";
    for (py::ssize_t i = 0; i < arr.ndim(); ++i) os << (i ? ", " : "") << arr.shape(i);
    os << (arr.ndim() == 1 ? ",)" : ")");
    throw py::value_error(os.str());
  }
  if (arr.shape(0) > 100000 || arr.shape(1) > 100000)
    throw py::value_error("depth: image larger than 100000 pixels on a side");
  const py::ssize_t item = static_cast<py::ssize_t>(sizeof(float));
  const bool in_place = f32 && arr.strides(1) == item && arr.strides(0) % item == 0 &&
                        arr.strides(0) >= item * arr.shape(1);
  if (!in_place) arr = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(arr);
  DepthView v;
  v.keep = arr;
  v.data = static_cast<const float*>(arr.data());
  v.height = static_cast<int>(arr.shape(0));
  v.width = static_cast<int>(arr.shape(1));
  v.row_stride = static_cast<std::size_t>(arr.strides(0) / item);
  return v;
}

PinholeCamera pinhole(const py::object& K_obj, int width, int height) {
  const Arr K = real_array(K_obj, "K", {3, 3});
  if (K.at(0, 1) != 0 || K.at(1, 0) != 0 || K.at(2, 0) != 0 || K.at(2, 1) != 0 || K.at(2, 2) != 1)
    throw py::value_error("K: expected pinhole intrinsics [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]");
  PinholeCamera c;
  c.width = width;
  c.height = height;
  c.fx = K.at(0, 0);
  c.fy = K.at(1, 1);
  c.cx = K.at(0, 2);
  c.cy = K.at(1, 2);
  if (!(c.fx > 0 && c.fy > 0)) throw py::value_error("K: the focal lengths fx, fy must be > 0");
  return c;
}

Pose pose44(const py::object& T_obj, const char* name) {
  const Arr T = real_array(T_obj, name, {4, 4});
  if (T.at(3, 0) != 0 || T.at(3, 1) != 0 || T.at(3, 2) != 0 || T.at(3, 3) != 1)
    throw py::value_error(std::string(name) + ": expected a homogeneous matrix (last row 0 0 0 1)");
  Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.R(r, c) = T.at(r, c);
    p.t(r) = T.at(r, 3);
  }
  if (std::abs(p.R.determinant() - 1.0) > 1e-6 || !(p.R.transpose() * p.R).isIdentity(1e-6))
    throw py::value_error(std::string(name) + ": the 3x3 block must be a rotation (orthonormal, det +1)");
  return p;
}

double positive(const py::object& v, const char* name) {
  const double x = float_arg(v, name);
  if (!(x > 0 && std::isfinite(x))) throw py::value_error(std::string(name) + ": expected a finite value > 0");
  return x;
}

int image_size(const py::object& v, const char* name) {
  return static_cast<int>(int_arg(v, name, 1, 100000));
}

py::array_t<double> centres_array(const std::vector<Vec3>& c) {
  py::array_t<double> out({static_cast<py::ssize_t>(c.size()), static_cast<py::ssize_t>(3)});
  double* o = out.mutable_data();
  for (std::size_t i = 0; i < c.size(); ++i)
    for (int a = 0; a < 3; ++a) o[3 * i + a] = c[i][a];
  return out;
}

template <typename V>
py::array_t<V> vector_array(const std::vector<V>& v) {
  py::array_t<V> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

void bind_params(py::module_& m) {
  py::class_<SceneVolumeParams> p(m, "SceneVolumeParams",
                                  "Parameters of a SceneVolume (config/volume.yaml); ranges: validate()");
  p.def(py::init<>());
  p.def_property("box_min_m", [](const SceneVolumeParams& s) { return s.box_min_m; },
                 [](SceneVolumeParams& s, const py::object& v) { s.box_min_m = vec3(v, "SceneVolumeParams.box_min_m"); },
                 "world box, lower corner (x, y, z) [m]");
  p.def_property("box_max_m", [](const SceneVolumeParams& s) { return s.box_max_m; },
                 [](SceneVolumeParams& s, const py::object& v) { s.box_max_m = vec3(v, "SceneVolumeParams.box_max_m"); },
                 "world box, upper corner [m] (rounded up to whole voxels)");
  float_field(p, "voxel_m", &SceneVolumeParams::voxel_m);
  float_field(p, "truncation_m", &SceneVolumeParams::truncation_m);
  float_field(p, "logodds_hit", &SceneVolumeParams::logodds_hit);
  float_field(p, "logodds_miss", &SceneVolumeParams::logodds_miss);
  float_field(p, "logodds_min", &SceneVolumeParams::logodds_min);
  float_field(p, "logodds_max", &SceneVolumeParams::logodds_max);
  p.def("validate", [](const SceneVolumeParams& s) { s.validate(); },
        "raise ValueError naming the first parameter out of range");
}

}  // namespace

void bind_scene_volume(py::module_& m) {
  m.attr("VOXEL_UNKNOWN") = static_cast<int>(VoxelState::kUnknown);
  m.attr("VOXEL_FREE") = static_cast<int>(VoxelState::kFree);
  m.attr("VOXEL_OCCUPIED") = static_cast<int>(VoxelState::kOccupied);
  m.attr("VOXEL_OUTSIDE") = static_cast<int>(VoxelState::kOutside);
  bind_params(m);

  py::class_<VolumeIntegration>(m, "VolumeIntegration", "What one SceneVolume.integrate() call did")
      .def_readonly("voxels_in_view", &VolumeIntegration::voxels_in_view,
                    "voxels whose centre projected into the image (up to the far bound)")
      .def_readonly("voxels_free", &VolumeIntegration::voxels_free, "of those: free evidence")
      .def_readonly("voxels_occupied", &VolumeIntegration::voxels_occupied, "of those: occupied evidence")
      .def_readonly("valid_pixels", &VolumeIntegration::valid_pixels,
                    "depth pixels finite, > 0 and <= max_range_m")
      .def_readonly("ms", &VolumeIntegration::ms, "wall time of the call [ms]");

  py::class_<VolumeCounts>(m, "VolumeCounts", "Voxel states counted over a query box")
      .def_readonly("unknown", &VolumeCounts::unknown)
      .def_readonly("free", &VolumeCounts::free)
      .def_readonly("occupied", &VolumeCounts::occupied)
      .def_readonly("outside", &VolumeCounts::outside, "lattice cells of the query box outside the volume")
      .def("__repr__", [](const VolumeCounts& c) {
        std::ostringstream os;
        os << "VolumeCounts(unknown=" << c.unknown << ", free=" << c.free << ", occupied=" << c.occupied
           << ", outside=" << c.outside << ")";
        return os.str();
      });

  using G = Guarded<SceneVolume>;
  py::class_<G>(m, "SceneVolume",
                "Log-odds occupancy over a world box, carved by every depth ray: each place is "
                "VOXEL_UNKNOWN (never seen), VOXEL_FREE, VOXEL_OCCUPIED, or VOXEL_OUTSIDE the box. "
                "Thread-safe: calls are serialised by a mutex (the GIL is released meanwhile).")
      .def(py::init([](const SceneVolumeParams& p) {
             const SceneVolumeParams copy = p;
             copy.validate();
             return G::make(copy);
           }), py::arg("params"))
      .def("integrate",
           [](const G& g, const py::object& depth, const py::object& K, const py::object& T_world_camera,
              const py::object& max_range_m) {
             const DepthView d = depth_view(depth);
             const PinholeCamera cam = pinhole(K, d.width, d.height);
             const Pose T = pose44(T_world_camera, "T_world_camera");
             const double range = positive(max_range_m, "max_range_m");
             return locked(g, [&](SceneVolume& v) { return v.integrate(d.data, cam, d.row_stride, T, range); });
           },
           py::arg("depth"), py::arg("K"), py::arg("T_world_camera"), py::arg("max_range_m"),
           "Integrate one depth image (H, W) float32 [m along the optical axis; NaN, <= 0 or "
           "> max_range_m: no measurement] taken with intrinsics K (3, 3) from the optical frame "
           "T_world_camera (4, 4): voxels in front of the measured surface by more than "
           "truncation_m gain free evidence, those within +-truncation_m occupied evidence, those "
           "behind nothing.")
      .def("classify",
           [](const G& g, const py::object& points) {
             const Arr a = real_array(points, "points", {-1, 3}, false);
             py::array_t<std::int8_t> out(a.shape(0));
             std::int8_t* o = out.mutable_data();
             locked(g, [&](SceneVolume& v) {
               v.classify(a.data(), static_cast<std::size_t>(a.shape(0)), 3, o);
               return 0;
             });
             return out;
           },
           py::arg("points"),
           "int8 state of each point (N, 3) [m, world]: VOXEL_UNKNOWN, VOXEL_FREE, VOXEL_OCCUPIED; "
           "VOXEL_OUTSIDE outside the box and for NaN rows.")
      .def("occupied_centres",
           [](const G& g, const py::object& lo, const py::object& hi) {
             const Vec3 l = vec3(lo, "box_min"), h = vec3(hi, "box_max");
             return centres_array(locked(g, [&](SceneVolume& v) { return v.occupied_centres(l, h); }));
           },
           py::arg("box_min"), py::arg("box_max"),
           "(M, 3) centres of the occupied voxels whose centre lies in the box [m].")
      .def("states_in_box",
           [](const G& g, const py::object& lo, const py::object& hi) {
             const Vec3 l = vec3(lo, "box_min"), h = vec3(hi, "box_max");
             std::vector<Vec3> c;
             std::vector<std::int8_t> s;
             locked(g, [&](SceneVolume& v) {
               v.states_in_box(l, h, &c, &s);
               return 0;
             });
             return py::make_tuple(centres_array(c), vector_array(s));
           },
           py::arg("box_min"), py::arg("box_max"),
           "(centres (M, 3), states (M,) int8) of every voxel whose centre lies in the box.")
      .def("count_states",
           [](const G& g, const py::object& lo, const py::object& hi) {
             const Vec3 l = vec3(lo, "box_min"), h = vec3(hi, "box_max");
             return locked(g, [&](SceneVolume& v) { return v.count_states(l, h); });
           },
           py::arg("box_min"), py::arg("box_max"),
           "VolumeCounts over the lattice cells whose centre lies in the box.")
      .def("visible",
           [](const G& g, const py::object& points, const py::object& K, const py::object& width,
              const py::object& height, const py::object& T_world_camera, const py::object& min_range_m,
              const py::object& max_range_m) {
             const Arr a = real_array(points, "points", {-1, 3}, false);
             const PinholeCamera cam = pinhole(K, image_size(width, "width"), image_size(height, "height"));
             const Pose T = pose44(T_world_camera, "T_world_camera");
             const double lo = float_arg(min_range_m, "min_range_m");
             const double hi = positive(max_range_m, "max_range_m");
             if (!(lo >= 0 && lo < hi)) throw py::value_error("min_range_m: expected 0 <= min_range_m < max_range_m");
             const std::vector<std::uint8_t> vis = locked(g, [&](SceneVolume& v) {
               return v.visible(a.data(), static_cast<std::size_t>(a.shape(0)), 3, cam, T, lo, hi);
             });
             py::array_t<bool> out(static_cast<py::ssize_t>(vis.size()));
             bool* o = out.mutable_data();
             for (std::size_t i = 0; i < vis.size(); ++i) o[i] = vis[i] != 0;
             return out;
           },
           py::arg("points"), py::arg("K"), py::arg("width"), py::arg("height"), py::arg("T_world_camera"),
           py::arg("min_range_m"), py::arg("max_range_m"),
           "(N,) bool: would a camera (K, width x height px) at T_world_camera see each point? Its "
           "depth within [min_range_m, max_range_m], inside the image, and no OCCUPIED voxel on the "
           "line from the camera centre to it (UNKNOWN voxels do not block).")
      .def("reset", [](const G& g) { locked(g, [](SceneVolume& v) { v.reset(); return 0; }); },
           "forget everything: every voxel UNKNOWN")
      .def("reset_box",
           [](const G& g, const py::object& lo, const py::object& hi) {
             const Vec3 l = vec3(lo, "box_min"), h = vec3(hi, "box_max");
             locked(g, [&](SceneVolume& v) { v.reset_box(l, h); return 0; });
           },
           py::arg("box_min"), py::arg("box_max"), "forget the voxels whose centre lies in the box")
      .def_property_readonly("params", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return SceneVolumeParams(v.params()); });
           }, "a copy of the parameters")
      .def_property_readonly("shape", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return std::vector<int>{v.nx(), v.ny(), v.nz()}; });
           }, "voxels along x, y, z")
      .def_property_readonly("box_min_m", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return Vec3(v.box_min()); });
           }, "lower corner of the grid [m]")
      .def_property_readonly("box_max_m", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return Vec3(v.box_max()); });
           }, "upper corner of the grid [m] (box_min_m + shape * voxel_m)")
      .def_property_readonly("memory_bytes", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return v.memory_bytes(); });
           }, "bytes of the voxel array")
      .def_property_readonly("frames_integrated", [](const G& g) {
             return locked(g, [](SceneVolume& v) { return v.frames_integrated(); });
           }, "integrate() calls since construction or the last reset()");
}

}  // namespace grasp_bind
