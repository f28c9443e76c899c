// Bindings of the value types and parameter sets.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>

#include "array_input.hpp"
#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {
Plane make_plane(const py::object& n, double c) {
  Plane p;
  Vec3 nv = vec3(n, "n");
  const double norm = nv.norm();
  if (norm < 1e-12) throw py::value_error("n: the plane normal must not be zero");
  if (!std::isfinite(c)) throw py::value_error("c: must be finite");
  nv /= norm;
  if (nv.z() < 0) { nv = -nv; c = -c; }
  if (nv.z() <= 0) throw py::value_error("n: a horizontal-ish plane needs n_z != 0");
  p.n = nv;
  p.c = c / norm;
  return p;
}
}  // namespace

void bind_types(py::module_& m) {
  m.attr("LABEL_INVALID") = kLabelInvalid;
  m.attr("LABEL_ENVIRONMENT") = kLabelEnvironment;

  py::enum_<ViewQuality>(m, "ViewQuality", "View quality of an observation (NADIR > OBLIQUE)")
      .value("OBLIQUE", ViewQuality::OBLIQUE)
      .value("NADIR", ViewQuality::NADIR);

  py::class_<Plane>(m, "Plane", "A plane n.p + c = 0 with |n| = 1 and n_z > 0 (world frame)")
      .def(py::init(&make_plane), py::arg("n"), py::arg("c"),
           "Normalises n and orients it so n_z > 0 (c scaled and flipped accordingly).")
      .def_readonly("n", &Plane::n)
      .def_readonly("c", &Plane::c)
      .def_property_readonly("height_m", &Plane::height_m, "-c / n_z: where it meets the z axis [m]")
      .def("signed_distance",
           [](const Plane& p, const py::object& x) { return p.signed_distance(vec3(x, "p")); },
           py::arg("p"), "n.p + c (positive above) [m]")
      .def("foot", &Plane::foot, "-c n: foot of the origin on the plane")
      .def("tilt_deg", &Plane::tilt_deg, "angle between n and +z [deg]")
      .def("rotation", &Plane::rotation, "rotation taking +z to n (det +1)")
      .def("__repr__", [](const Plane& p) {
        std::ostringstream os;
        os << "Plane(n=[" << p.n.x() << ", " << p.n.y() << ", " << p.n.z() << "], c=" << p.c
           << ", height_m=" << p.height_m() << ")";
        return os.str();
      });

  py::class_<Pose>(m, "Pose", "A rigid pose: x_world = R x_local + t")
      .def(py::init([](const py::object& R, const py::object& t) {
             Pose p;
             p.R = mat3(R, "R");
             p.t = vec3(t, "t");
             if (std::abs(p.R.determinant() - 1.0) > 1e-6 ||
                 !(p.R.transpose() * p.R).isIdentity(1e-6)) {
               throw py::value_error("R: expected a rotation matrix (orthonormal, det +1)");
             }
             return p;
           }),
           py::arg("R"), py::arg("t"))
      .def_static("from_matrix", [](const py::object& T) {
        py::array_t<double, py::array::forcecast> a =
            py::array_t<double, py::array::forcecast>::ensure(T);
        if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
          throw py::value_error("T: expected a 4x4 homogeneous matrix");
        Pose p;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) p.R(i, j) = a.at(i, j);
          p.t(i) = a.at(i, 3);
        }
        if (!p.R.allFinite() || !p.t.allFinite()) throw py::value_error("T: must be finite");
        if (std::abs(p.R.determinant() - 1.0) > 1e-6 || !(p.R.transpose() * p.R).isIdentity(1e-6))
          throw py::value_error("T: the 3x3 block must be a rotation (orthonormal, det +1)");
        return p;
      }, py::arg("T"))
      .def("matrix", [](const Pose& p) {
        Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
        T.topLeftCorner<3, 3>() = p.R;
        T.topRightCorner<3, 1>() = p.t;
        return T;
      }, "4x4 homogeneous matrix")
      .def_readonly("R", &Pose::R)
      .def_readonly("t", &Pose::t);

  py::class_<SceneFilterParams>(m, "SceneFilterParams", "SPEC 1.6 scene filter parameters")
      .def(py::init<>())
      .def_readwrite("plane_dist_thresh", &SceneFilterParams::plane_dist_thresh)
      .def_readwrite("plane_max_tilt_deg", &SceneFilterParams::plane_max_tilt_deg)
      .def_readwrite("plane_ransac_iters", &SceneFilterParams::plane_ransac_iters)
      .def_readwrite("plane_fit_max_points", &SceneFilterParams::plane_fit_max_points)
      .def_readwrite("plane_min_inlier_ratio", &SceneFilterParams::plane_min_inlier_ratio)
      .def_readwrite("plane_max_count", &SceneFilterParams::plane_max_count)
      .def_readwrite("plane_dominance", &SceneFilterParams::plane_dominance)
      .def_readwrite("plane_lock", &SceneFilterParams::plane_lock)
      .def_readwrite("plane_lock_after", &SceneFilterParams::plane_lock_after)
      .def_readwrite("plane_update_tol_deg", &SceneFilterParams::plane_update_tol_deg)
      .def_readwrite("plane_update_tol_m", &SceneFilterParams::plane_update_tol_m)
      .def_readwrite("plane_init_frames", &SceneFilterParams::plane_init_frames)
      .def_readwrite("cluster_eps", &SceneFilterParams::cluster_eps)
      .def_readwrite("cluster_min_points", &SceneFilterParams::cluster_min_points)
      .def_readwrite("cluster_min_extent", &SceneFilterParams::cluster_min_extent)
      .def_readwrite("cluster_max_extent", &SceneFilterParams::cluster_max_extent)
      .def_readwrite("band", &SceneFilterParams::band)
      .def_readwrite("cluster_voxel_m", &SceneFilterParams::cluster_voxel_m)
      .def_readwrite("seed", &SceneFilterParams::seed)
      .def("validate", &SceneFilterParams::validate,
           "Raise ValueError naming the first invalid parameter.");

  py::class_<ObbParams>(m, "ObbParams", "SPEC 2.7 object estimate / guard / tracker parameters")
      .def(py::init<>())
      .def_readwrite("depth_noise_sigma", &ObbParams::depth_noise_sigma)
      .def_readwrite("top_slice_sigmas", &ObbParams::top_slice_sigmas)
      .def_readwrite("top_slice_iters", &ObbParams::top_slice_iters)
      .def_readwrite("n_theta", &ObbParams::n_theta)
      .def_readwrite("width_tol_m", &ObbParams::width_tol_m)
      .def_readwrite("isotropy_ratio_max", &ObbParams::isotropy_ratio_max)
      .def_readwrite("gripper_open", &ObbParams::gripper_open)
      .def_readwrite("min_graspable_width", &ObbParams::min_graspable_width)
      .def_readwrite("min_height", &ObbParams::min_height)
      .def_readwrite("resting_margin", &ObbParams::resting_margin)
      .def_readwrite("side_seen_sigmas", &ObbParams::side_seen_sigmas)
      .def_readwrite("window", &ObbParams::window)
      .def_readwrite("assoc_gate_frac", &ObbParams::assoc_gate_frac)
      .def_readwrite("max_age_s", &ObbParams::max_age_s)
      .def_readwrite("nadir_hold_s", &ObbParams::nadir_hold_s)
      .def_readwrite("nadir_angle_max_deg", &ObbParams::nadir_angle_max_deg)
      .def_readwrite("nadir_min_distance_m", &ObbParams::nadir_min_distance_m)
      .def("validate", &ObbParams::validate,
           "Raise ValueError naming the first invalid parameter.");
}

}  // namespace grasp_bind
