// Bindings of method.md §2 (object estimate, PCA box) and method.md §3 (grasp pose, view quality).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <climits>
#include <cmath>

#include "array_input.hpp"
#include "guarded.hpp"
#include "grasp_core/grasp.hpp"
#include "grasp_core/object_estimate.hpp"
#include "grasp_core/pca_box.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

std::vector<double> finite_list(const std::vector<double>& v, const char* name) {
  for (double x : v)
    if (!std::isfinite(x)) throw py::value_error(std::string(name) + ": values must be finite");
  return v;
}

std::optional<double> finite_opt(const std::optional<double>& x, const char* name) {
  if (x && !std::isfinite(*x)) throw py::value_error(std::string(name) + ": must be finite or None");
  return x;
}

int checked_n_theta(const py::object& n_theta) {
  return static_cast<int>(int_arg(n_theta, "n_theta", 2, 100000));
}

}  // namespace

void bind_estimate(py::module_& m) {
  py::class_<PcaBox>(m, "PcaBox", "PCA oriented box (method.md §2.5; diagnostic only)")
      .def_readonly("center", &PcaBox::center)
      .def_readonly("R", &PcaBox::R)
      .def_readonly("extents", &PcaBox::extents)
      .def_readonly("eigenvalues", &PcaBox::eigenvalues);

  m.def("pca_box",
        [](const py::object& points, double bound) -> py::object {
          PointsD pts = points_double(points, "points", nullptr, /*allow_empty=*/true, checked_bound(bound));
          std::string why;
          auto box = pca_box(pts, &why);
          if (!box) return py::none();
          return py::cast(*box);
        },
        py::arg("points"), py::arg("max_abs_coordinate_m") = kDefaultMaxAbsCoordinate_m,
        "PCA box of the rows that are finite and within max_abs_coordinate_m, or None (fewer "
        "than 3 points, coincident, collinear).");
  m.def("pca_box_failure",
        [](const py::object& points, double bound) {
          PointsD pts = points_double(points, "points", nullptr, true, checked_bound(bound));
          std::string why;
          auto box = pca_box(pts, &why);
          return box ? std::string() : why;
        },
        py::arg("points"), py::arg("max_abs_coordinate_m") = kDefaultMaxAbsCoordinate_m,
        "Why pca_box() gives None ('' when it succeeds).");
  m.def("pca_tilt_deg", [](const PcaBox& b, const py::object& n) { return pca_tilt_deg(b, vec3(n, "n")); },
        py::arg("box"), py::arg("n"), "angle(PCA minor axis, n) [deg]");

  py::class_<ObjectEstimate>(m, "ObjectEstimate", "Grasp-ready box of one object (method.md §2)")
      .def_readonly("center", &ObjectEstimate::center)
      .def_readonly("R_box", &ObjectEstimate::R_box)
      .def_readonly("extents", &ObjectEstimate::extents)
      .def_readonly("theta_rad", &ObjectEstimate::theta_rad)
      .def_property_readonly("theta_deg", [](const ObjectEstimate& e) { return e.theta_rad * 180.0 / M_PI; })
      .def_readonly("width_m", &ObjectEstimate::width_m)
      .def_readonly("perp_width_m", &ObjectEstimate::perp_width_m)
      .def_readonly("height_m", &ObjectEstimate::height_m)
      .def_readonly("anisotropy", &ObjectEstimate::anisotropy)
      .def_readonly("yaw_defined", &ObjectEstimate::yaw_defined)
      .def_readonly("pca", &ObjectEstimate::pca)
      .def_readonly("pca_tilt_deg", &ObjectEstimate::pca_tilt_deg)
      .def_readonly("lowest_m", &ObjectEstimate::lowest_m)
      .def_readonly("resting", &ObjectEstimate::resting)
      .def_readonly("height_ok", &ObjectEstimate::height_ok)
      .def_readonly("width_ok", &ObjectEstimate::width_ok)
      .def_readonly("grasp_ok", &ObjectEstimate::grasp_ok)
      .def_readonly("resting_note", &ObjectEstimate::resting_note)
      .def_readonly("notes", &ObjectEstimate::notes)
      .def_readonly("undetermined_notes", &ObjectEstimate::undetermined_notes)
      .def_readonly("num_points", &ObjectEstimate::num_points)
      .def("__repr__", [](const ObjectEstimate& e) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "ObjectEstimate(center=[%.4f, %.4f, %.4f], extents=[%.4f, %.4f, %.4f], "
                      "theta_deg=%.1f, grasp_ok=%s)",
                      e.center.x(), e.center.y(), e.center.z(), e.extents.x(), e.extents.y(),
                      e.extents.z(), e.theta_rad * 180.0 / M_PI, e.grasp_ok ? "True" : "False");
        return std::string(buf);
      });

  py::class_<EstimateResult>(m, "EstimateResult", "An estimate, or why there is none")
      .def_readonly("estimate", &EstimateResult::estimate)
      .def_readonly("failure", &EstimateResult::failure);

  m.def("estimate_object",
        [](const py::object& points, const Plane& plane, const ObbParams& params_in,
           std::optional<double> theta_prev, std::optional<double> band, double bound) {
          const ObbParams params = params_in;  // copied: another thread may assign its fields
          params.validate();
          PointsD pts = points_double(points, "points", nullptr, false, checked_bound(bound));
          finite_opt(theta_prev, "theta_prev");
          finite_opt(band, "band");
          py::gil_scoped_release release;
          return estimate_object(pts, plane, params, theta_prev, band, bound);
        },
        py::arg("points"), py::arg("plane"), py::arg("params"), py::arg("theta_prev") = py::none(),
        py::arg("band") = py::none(), py::arg("max_abs_coordinate_m") = kDefaultMaxAbsCoordinate_m,
        "method.md §2: estimate one cluster above the plane (rows with a NaN/Inf or a |coordinate| > "
        "max_abs_coordinate_m are dropped). No estimate (failure text) for fewer than 3 points, "
        "a failed PCA, or a cluster whose top is below the plane.");

  m.def("in_plane_basis", [](const py::object& n) {
          Vec3 nv = vec3(n, "n");
          if (nv.norm() < 1e-12) throw py::value_error("n: must not be zero");
          Vec3 u, v;
          in_plane_basis(nv, &u, &v);
          return py::make_tuple(u, v);
        }, py::arg("n"), "Deterministic (u, v) with u x v = n.");
  m.def("scan_angle_rad", [](const py::object& t, const py::object& n_theta) {
          const int T = checked_n_theta(n_theta);
          return scan_angle_rad(static_cast<int>(int_arg(t, "t", INT_MIN, INT_MAX)), T);
        }, py::arg("t"), py::arg("n_theta"));
  m.def("width_scan", [](const std::vector<double>& a, const std::vector<double>& b, const py::object& n_theta) {
          if (a.size() != b.size()) throw py::value_error("a, b: expected the same length");
          const int T = checked_n_theta(n_theta);
          return width_scan(finite_list(a, "a"), finite_list(b, "b"), T);
        }, py::arg("a"), py::arg("b"), py::arg("n_theta"), "ext(theta_t) for t = 0..n_theta-1 [m]");
  m.def("extent_along", [](const std::vector<double>& a, const std::vector<double>& b, double theta) {
          if (a.size() != b.size()) throw py::value_error("a, b: expected the same length");
          return extent_along(finite_list(a, "a"), finite_list(b, "b"), theta);
        }, py::arg("a"), py::arg("b"), py::arg("theta_rad"));
  m.def("anisotropy_ratio", [](const std::vector<double>& ext) { return anisotropy_ratio(finite_list(ext, "ext")); },
        py::arg("ext"));

  py::class_<DirectionRun>(m, "DirectionRun", "A run of candidate closing directions (method.md §2.3)")
      .def_readonly("first", &DirectionRun::first)
      .def_readonly("last", &DirectionRun::last)
      .def_readonly("indices", &DirectionRun::indices)
      .def_readonly("theta_rad", &DirectionRun::theta_rad)
      .def_readonly("width_m", &DirectionRun::width_m);
  py::class_<DirectionChoice>(m, "DirectionChoice")
      .def_readonly("theta_rad", &DirectionChoice::theta_rad)
      .def_readonly("width_m", &DirectionChoice::width_m)
      .def_readonly("chosen", &DirectionChoice::chosen)
      .def_readonly("runs", &DirectionChoice::runs);
  m.def("direction_runs", [](const std::vector<double>& ext, double tol) {
          if (!(tol >= 0)) throw py::value_error("width_tol_m: expected >= 0");
          return direction_runs(finite_list(ext, "ext"), tol);
        }, py::arg("ext"), py::arg("width_tol_m"));
  m.def("choose_direction", [](const std::vector<double>& ext, double tol, std::optional<double> prev) {
          if (!(tol >= 0)) throw py::value_error("width_tol_m: expected >= 0");
          return choose_direction(finite_list(ext, "ext"), tol, finite_opt(prev, "theta_prev"));
        }, py::arg("ext"), py::arg("width_tol_m"), py::arg("theta_prev") = py::none());
  m.def("circular_median_mod_pi", [](const std::vector<double>& a, double ref) {
          if (!std::isfinite(ref)) throw py::value_error("reference_rad: must be finite");
          return circular_median_mod_pi(finite_list(a, "angles_rad"), ref);
        }, py::arg("angles_rad"), py::arg("reference_rad"));
  m.def("median", [](const std::vector<double>& v) { return median(finite_list(v, "values")); }, py::arg("values"),
        "Median; an even count gives the mean of the two middle values.");
  m.def("angle_dist_mod_pi", &angle_dist_mod_pi, py::arg("a_rad"), py::arg("b_rad"));
  m.def("wrap_mod_pi", &wrap_mod_pi, py::arg("x_rad"));
  m.def("slice_median_top", [](const std::vector<double>& d, double sigma, double k, const py::object& iters_obj) {
          if (!(sigma > 0 && std::isfinite(sigma))) throw py::value_error("sigma_m: expected a finite sigma > 0");
          if (!(k > 0 && std::isfinite(k))) throw py::value_error("slice_sigmas: expected a finite count > 0");
          const int iters = static_cast<int>(int_arg(iters_obj, "iters", 1, 1000));
          return slice_median_top(finite_list(d, "d"), sigma, k, iters);
        }, py::arg("d"), py::arg("sigma_m"), py::arg("slice_sigmas"), py::arg("iters"));

  py::class_<BestGrasp>(m, "BestGrasp",
                        "Grasp pose: position = contact point, R[:,0] = approach into the object, "
                        "R[:,2] = closing axis; width [m]; score always 0 (geometric method)")
      .def(py::init([](const py::object& R, const py::object& position, double width_m) {
             BestGrasp g;
             g.R = mat3(R, "R");
             g.position = vec3(position, "position");
             if (!(width_m >= 0 && std::isfinite(width_m))) throw py::value_error("width_m: expected >= 0");
             if (std::abs(g.R.determinant() - 1.0) > 1e-6 || !(g.R.transpose() * g.R).isIdentity(1e-6))
               throw py::value_error("R: expected a rotation matrix (orthonormal, det +1)");
             g.width_m = width_m;
             return g;
           }), py::arg("R"), py::arg("position"), py::arg("width_m"))
      .def_readonly("R", &BestGrasp::R)
      .def_readonly("position", &BestGrasp::position)
      .def_readonly("width_m", &BestGrasp::width_m)
      .def_readonly("score", &BestGrasp::score);

  m.def("top_down_rotation", [](const py::object& R_box, const py::object& n) {
          return top_down_rotation(mat3(R_box, "R_box"), vec3(n, "n"));
        }, py::arg("R_box"), py::arg("n"), "[n, normalize(closing x n), closing] or None");
  m.def("best_grasp_from_estimate", &best_grasp_from_estimate, py::arg("estimate"), py::arg("plane"));
  m.def("camera_above_pose", [](const py::object& obj, const Plane& plane, const Pose& ready) {
          return camera_above_pose(vec3(obj, "object"), plane, ready);
        }, py::arg("object"), py::arg("plane"), py::arg("ready_camera_world"));
  m.def("camera_above_flange_target",
        [](const py::object& obj, const Plane& plane, const Pose& ready, const Pose& cam_in_flange) {
          return camera_above_flange_target(vec3(obj, "object"), plane, ready, cam_in_flange);
        }, py::arg("object"), py::arg("plane"), py::arg("ready_camera_world"), py::arg("camera_in_flange"),
        "Flange pose that puts the camera above the object (method.md §3).");

  py::class_<ViewAssessment>(m, "ViewAssessment")
      .def_readonly("quality", &ViewAssessment::quality)
      .def_readonly("angle_deg", &ViewAssessment::angle_deg);
  m.def("assess_view", [](const py::object& obj, const py::object& cam, const py::object& n, double max_deg) {
          if (!(max_deg >= 0 && max_deg < 90)) throw py::value_error("nadir_angle_max_deg: expected [0, 90)");
          return assess_view(vec3(obj, "object"), vec3(cam, "camera_position"), vec3(n, "n"), max_deg);
        }, py::arg("object"), py::arg("camera_position"), py::arg("n"), py::arg("nadir_angle_max_deg"));
}

}  // namespace grasp_bind
