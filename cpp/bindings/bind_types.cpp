// Bindings of the value types and parameter sets.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>

#include "array_input.hpp"
#include "guarded.hpp"
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

  // Setters check the Python value and name the field (TypeError for a wrong type,
  // ValueError for an int beyond the C++ type); ranges are checked by validate().
  py::class_<SceneFilterParams> sfp(m, "SceneFilterParams", "method.md §1.6 scene filter parameters");
  sfp.def(py::init<>());
  float_field(sfp, "plane_dist_thresh", &SceneFilterParams::plane_dist_thresh);
  float_field(sfp, "plane_max_tilt_deg", &SceneFilterParams::plane_max_tilt_deg);
  int_field(sfp, "plane_ransac_iters", &SceneFilterParams::plane_ransac_iters);
  int_field(sfp, "plane_fit_max_points", &SceneFilterParams::plane_fit_max_points);
  float_field(sfp, "plane_min_inlier_ratio", &SceneFilterParams::plane_min_inlier_ratio);
  int_field(sfp, "plane_max_count", &SceneFilterParams::plane_max_count);
  float_field(sfp, "plane_dominance", &SceneFilterParams::plane_dominance);
  bool_field(sfp, "plane_lock", &SceneFilterParams::plane_lock);
  int_field(sfp, "plane_lock_after", &SceneFilterParams::plane_lock_after);
  float_field(sfp, "plane_update_tol_deg", &SceneFilterParams::plane_update_tol_deg);
  float_field(sfp, "plane_update_tol_m", &SceneFilterParams::plane_update_tol_m);
  int_field(sfp, "plane_init_frames", &SceneFilterParams::plane_init_frames);
  float_field(sfp, "cluster_eps", &SceneFilterParams::cluster_eps);
  int_field(sfp, "cluster_min_points", &SceneFilterParams::cluster_min_points);
  float_field(sfp, "cluster_min_extent", &SceneFilterParams::cluster_min_extent);
  float_field(sfp, "cluster_max_extent", &SceneFilterParams::cluster_max_extent);
  float_field(sfp, "band", &SceneFilterParams::band);
  float_field(sfp, "cluster_voxel_m", &SceneFilterParams::cluster_voxel_m);
  seed_field(sfp, "seed", &SceneFilterParams::seed);
  float_field(sfp, "max_abs_coordinate_m", &SceneFilterParams::max_abs_coordinate_m);
  bool_field(sfp, "segment_organized", &SceneFilterParams::segment_organized);
  int_field(sfp, "segment_smooth_radius_px", &SceneFilterParams::segment_smooth_radius_px);
  float_field(sfp, "segment_max_step_m", &SceneFilterParams::segment_max_step_m);
  float_field(sfp, "segment_max_hue_diff_deg", &SceneFilterParams::segment_max_hue_diff_deg);
  float_field(sfp, "segment_min_saturation", &SceneFilterParams::segment_min_saturation);
  float_field(sfp, "segment_min_brightness", &SceneFilterParams::segment_min_brightness);
  int_field(sfp, "segment_absorb_max_points", &SceneFilterParams::segment_absorb_max_points);
  float_field(sfp, "segment_nest_fraction", &SceneFilterParams::segment_nest_fraction);
  float_field(sfp, "segment_nest_min_slope_deg", &SceneFilterParams::segment_nest_min_slope_deg);
  float_field(sfp, "segment_nest_max_slope_deg", &SceneFilterParams::segment_nest_max_slope_deg);
  int_field(sfp, "segment_nest_rings_px", &SceneFilterParams::segment_nest_rings_px);
  float_field(sfp, "depth_noise_sigma_m", &SceneFilterParams::depth_noise_sigma_m);
  float_field(sfp, "depth_noise_ref_range_m", &SceneFilterParams::depth_noise_ref_range_m);
  float_field(sfp, "depth_noise_exponent", &SceneFilterParams::depth_noise_exponent);
  float_field(sfp, "object_min_height_sigmas", &SceneFilterParams::object_min_height_sigmas);
  sfp.def("validate", &SceneFilterParams::validate,
          "Raise ValueError naming the first invalid parameter.");

  py::class_<ObbParams> obb(m, "ObbParams", "method.md §2.7 object estimate / guard / tracker parameters");
  obb.def(py::init<>());
  float_field(obb, "depth_noise_sigma", &ObbParams::depth_noise_sigma);
  float_field(obb, "top_slice_sigmas", &ObbParams::top_slice_sigmas);
  int_field(obb, "top_slice_iters", &ObbParams::top_slice_iters);
  int_field(obb, "n_theta", &ObbParams::n_theta);
  float_field(obb, "width_tol_m", &ObbParams::width_tol_m);
  float_field(obb, "isotropy_ratio_max", &ObbParams::isotropy_ratio_max);
  float_field(obb, "gripper_open", &ObbParams::gripper_open);
  float_field(obb, "min_graspable_width", &ObbParams::min_graspable_width);
  float_field(obb, "min_height", &ObbParams::min_height);
  float_field(obb, "resting_margin", &ObbParams::resting_margin);
  float_field(obb, "side_seen_sigmas", &ObbParams::side_seen_sigmas);
  int_field(obb, "window", &ObbParams::window);
  float_field(obb, "assoc_gate_frac", &ObbParams::assoc_gate_frac);
  float_field(obb, "max_age_s", &ObbParams::max_age_s);
  float_field(obb, "nadir_hold_s", &ObbParams::nadir_hold_s);
  float_field(obb, "nadir_angle_max_deg", &ObbParams::nadir_angle_max_deg);
  float_field(obb, "nadir_min_distance_m", &ObbParams::nadir_min_distance_m);
  obb.def("validate", &ObbParams::validate,
          "Raise ValueError naming the first invalid parameter.");
}

}  // namespace grasp_bind
