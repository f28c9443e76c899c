// Bindings of the planning collision checker: RobotCollisionModel (exported once from the
// robot model), CollisionScene (one perceived scene, immutable) and StateChecker.
// Every array is checked here (dtype real, shape, finite) and rejected with a ValueError /
// TypeError naming the argument; the checks run with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "grasp_core/collision_scene.hpp"
#include "grasp_core/robot_collision.hpp"
#include "planning_input.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

using namespace planning_input;

std::shared_ptr<RobotCollisionModel> make_robot(const py::dict& a) {
  auto get = [&](const char* k) -> py::object {
    if (!a.contains(k)) throw py::value_error(std::string("robot model: missing entry '") + k + "'");
    return a[k];
  };
  RobotCollisionSpec s;
  s.bodies = chain_bodies(a);
  const Arr rad = real_array(get("sphere_radius_m"), "sphere_radius_m", {-1});
  const py::ssize_t ns = rad.shape(0);
  s.sphere_body = int_vector(get("sphere_body"), "sphere_body", ns);
  s.sphere_geom = int_vector(get("sphere_geom"), "sphere_geom", ns);
  const Arr cen = real_array(get("sphere_center_m"), "sphere_center_m", {ns, 3});
  const std::vector<int> env = int_vector(get("env_sphere"), "env_sphere", ns);
  const std::vector<int> hand = int_vector(get("hand_sphere"), "hand_sphere", ns);
  for (py::ssize_t i = 0; i < ns; ++i) {
    s.sphere_center.push_back(row3(cen, i));
    s.sphere_radius.push_back(rad.at(i));
    s.env_sphere.push_back(env[static_cast<std::size_t>(i)] != 0);
    s.hand_sphere.push_back(hand[static_cast<std::size_t>(i)] != 0);
  }
  const Arr pi = real_array(get("pair_i"), "pair_i", {-1});
  const std::vector<int> I = int_vector(get("pair_i"), "pair_i", pi.shape(0));
  const std::vector<int> J = int_vector(get("pair_j"), "pair_j", pi.shape(0));
  for (std::size_t k = 0; k < I.size(); ++k) s.pairs.emplace_back(I[k], J[k]);
  const Arr lo = real_array(get("q_min_rad"), "q_min_rad", {kArmJoints});
  const Arr hi = real_array(get("q_max_rad"), "q_max_rad", {kArmJoints});
  for (int j = 0; j < kArmJoints; ++j) { s.q_min_rad[j] = lo.at(j); s.q_max_rad[j] = hi.at(j); }
  s.self_margin_m = finite_arg(get("self_margin_m").cast<double>(), "self_margin_m");
  return translate([&] { return std::make_shared<RobotCollisionModel>(std::move(s)); });
}

std::vector<ObstacleBox> make_boxes(const py::object& c, const py::object& R, const py::object& e) {
  if (c.is_none()) return {};
  const Arr cc = real_array(c, "box_centers_m", {-1, 3});
  const py::ssize_t n = cc.shape(0);
  const Arr rr = real_array(R, "box_rotations", {n, 3, 3});
  const Arr ee = real_array(e, "box_extents_m", {n, 3});
  std::vector<ObstacleBox> out;
  for (py::ssize_t k = 0; k < n; ++k)
    out.push_back(translate([&] { return ObstacleBox(row3(cc, k), mat_at(rr, k), row3(ee, k)); }));
  return out;
}

DistanceField make_field(const py::object& values, const py::object& origin, double voxel_m, double inflation_m) {
  DistanceField f;
  if (values.is_none()) return f;
  py::array raw = py::array::ensure(values);
  if (!raw || raw.ndim() != 3) throw py::value_error("field_m: expected a 3-D array (nx, ny, nz)");
  if (raw.dtype().kind() != 'f') throw py::type_error("field_m: expected float32/float64 values");
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(raw);
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (std::isnan(a.data()[i]) || a.data()[i] < 0.0f) throw py::value_error("field_m: values must be >= 0 (no NaN)");
  const Arr o = real_array(origin, "origin_m", {3});
  if (!(voxel_m > 0.0) || !std::isfinite(voxel_m)) throw py::value_error("voxel_size_m: must be finite and > 0");
  if (!(inflation_m >= 0.0) || !std::isfinite(inflation_m)) throw py::value_error("inflation_m: must be finite and >= 0");
  f.nx = a.shape(0); f.ny = a.shape(1); f.nz = a.shape(2);
  f.values.assign(a.data(), a.data() + a.size());
  f.origin = Vec3(o.at(0), o.at(1), o.at(2));
  f.voxel_m = voxel_m;
  f.inflation_m = inflation_m;
  return f;
}

/// A ClearedRegion from a dict (center_m, rotation, extents_m, points_m, pad_m, fine_m).
ClearedRegion point_region(const py::dict& d, const std::string& what, double inflation) {
  const Arr c = real_array(d["center_m"], (what + " center_m").c_str(), {3});
  const Arr R = real_array(d["rotation"], (what + " rotation").c_str(), {3, 3});
  const Arr e = real_array(d["extents_m"], (what + " extents_m").c_str(), {3});
  const Arr pts = real_array(d["points_m"], (what + " points_m").c_str(), {-1, 3});
  std::vector<Vec3> p;
  p.reserve(static_cast<std::size_t>(pts.shape(0)));
  for (py::ssize_t i = 0; i < pts.shape(0); ++i) p.push_back(row3(pts, i));
  Mat3 Rm;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) Rm(r, k) = R.at(r, k);
  return translate([&] {
    return ClearedRegion(ObstacleBox(Vec3(c.at(0), c.at(1), c.at(2)), Rm, Vec3(e.at(0), e.at(1), e.at(2))),
                         d["pad_m"].cast<double>(), std::move(p), d["fine_m"].cast<double>(), inflation);
  });
}

std::shared_ptr<CollisionScene> make_scene(double margin, double floor_z, bool has_env, const py::object& field,
                                           const py::object& origin, double voxel, double inflation,
                                           const py::object& bc, const py::object& br, const py::object& be,
                                           const py::object& cleared, const py::object& points) {
  auto sc = std::make_shared<CollisionScene>();
  sc->collision_margin_m = finite_arg(margin, "collision_margin_m");
  sc->floor_z_m = finite_arg(floor_z, "floor_z_m");
  sc->has_env = has_env;
  sc->field = make_field(field, origin, voxel, inflation);
  if (!field.is_none() && !has_env) throw py::value_error("field_m given with has_env=False");
  sc->boxes = make_boxes(bc, br, be);
  if (!cleared.is_none()) {
    sc->cleared = point_region(cleared.cast<py::dict>(), "cleared", inflation);
    sc->has_cleared = true;
  }
  if (!points.is_none()) {
    sc->points = point_region(points.cast<py::dict>(), "points", 0.0);
    sc->has_points = true;
  }
  return sc;
}

/// The 7 values of an OMPL RealVectorState (s[0:7] returns a list of floats).
void ompl_values(const py::handle& s, double* q) {
  // deliberately never released: a static py::object would be decref'd after the
  // interpreter is gone (crash at exit)
  static PyObject* const seven = PySlice_New(nullptr, py::int_(kArmJoints).ptr(), nullptr);
  if (seven == nullptr) throw py::error_already_set();
  py::object lst = py::reinterpret_steal<py::object>(PyObject_GetItem(s.ptr(), seven));
  if (!lst) throw py::error_already_set();
  if (!PyList_Check(lst.ptr()) || PyList_GET_SIZE(lst.ptr()) != kArmJoints)
    throw py::type_error("state: expected a 7-D OMPL RealVectorState");
  for (int j = 0; j < kArmJoints; ++j) {
    q[j] = PyFloat_AsDouble(PyList_GET_ITEM(lst.ptr(), j));
    if (q[j] == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  }
}

bool finite7(const double* q) {
  for (int j = 0; j < kArmJoints; ++j)
    if (!std::isfinite(q[j])) return false;
  return true;
}

}  // namespace

void bind_collision(py::module_& m) {
  py::class_<RobotCollisionModel, std::shared_ptr<RobotCollisionModel>>(
      m, "RobotCollisionModel",
      "The robot's kinematic chain (fixed transforms + 7 hinges), collision spheres and "
      "self-collision pairs, exported once from the MuJoCo model (motion/core_checker.py).")
      .def(py::init(&make_robot), py::arg("arrays"))
      .def_property_readonly("num_spheres", &RobotCollisionModel::num_spheres)
      .def_property_readonly("num_bodies", [](const RobotCollisionModel& r) { return r.chain().num_bodies(); })
      .def("body_poses", [](const RobotCollisionModel& r, const py::object& q) {
          const Arr a = real_array(q, "q", {kArmJoints});
          const int nb = r.chain().num_bodies();
          std::vector<Mat3> R(static_cast<std::size_t>(nb));
          std::vector<Vec3> p(static_cast<std::size_t>(nb));
          r.chain().poses(a.data(), R.data(), p.data());
          py::array_t<double> Ro({nb, 3, 3}), po({nb, 3});
          auto rv = Ro.mutable_unchecked<3>();
          auto pv = po.mutable_unchecked<2>();
          for (int b = 0; b < nb; ++b)
            for (int i = 0; i < 3; ++i) {
              pv(b, i) = p[static_cast<std::size_t>(b)][i];
              for (int j = 0; j < 3; ++j) rv(b, i, j) = R[static_cast<std::size_t>(b)](i, j);
            }
          return py::make_tuple(Ro, po);
        }, py::arg("q"), "World rotations (B, 3, 3) and positions (B, 3) of every body for arm state q (7,).");

  py::class_<CollisionScene, std::shared_ptr<CollisionScene>>(
      m, "CollisionScene",
      "One perceived planning scene (immutable): distance field of the occupancy map, object "
      "boxes, floor, margins, the optional target-cleared region and the optional object "
      "points (neighbours modelled by their points; same dict as cleared, inflation 0).")
      .def(py::init(&make_scene), py::arg("collision_margin_m"), py::arg("floor_z_m"),
           py::arg("has_env") = false, py::arg("field_m") = py::none(), py::arg("origin_m") = py::none(),
           py::arg("voxel_size_m") = 1.0, py::arg("inflation_m") = 0.0,
           py::arg("box_centers_m") = py::none(), py::arg("box_rotations") = py::none(),
           py::arg("box_extents_m") = py::none(), py::arg("cleared") = py::none(),
           py::arg("points") = py::none())
      .def_property_readonly("num_boxes", [](const CollisionScene& s) { return s.boxes.size(); });

  py::class_<StateChecker, std::shared_ptr<StateChecker>>(
      m, "StateChecker",
      "Validity of arm states (joint limits, self-collision, map, boxes, floor). Thread-safe; "
      "the GIL is released while checking.")
      .def(py::init([](std::shared_ptr<RobotCollisionModel> r, std::shared_ptr<CollisionScene> s) {
             return translate([&] { return std::make_shared<StateChecker>(r, s); });
           }), py::arg("robot"), py::arg("scene"))
      .def("set_scene", [](StateChecker& c, std::shared_ptr<CollisionScene> s) { c.set_scene(s); }, py::arg("scene"))
      .def_property("allow_target_contact", &StateChecker::allow_target_contact, &StateChecker::set_allow_target_contact)
      .def_property_readonly("checked_states", &StateChecker::checked_states)
      .def("check", [](const StateChecker& c, const py::object& q) {
          const Arr a = real_array(q, "q", {kArmJoints});
          py::gil_scoped_release nogil;
          return c.check(a.data());
        }, py::arg("q"), "True if the state q (7,) rad is valid.")
      .def("check_batch", [](const StateChecker& c, const py::object& Q) {
          const Arr a = real_array(Q, "Q", {-1, kArmJoints});
          const std::size_t n = static_cast<std::size_t>(a.shape(0));
          py::array_t<bool> out(static_cast<py::ssize_t>(n));
          static_assert(sizeof(bool) == 1, "bool arrays are bytes");
          auto* o = reinterpret_cast<std::uint8_t*>(out.mutable_data());
          {
            py::gil_scoped_release nogil;
            c.check_batch(a.data(), n, o);
          }
          return out;
        }, py::arg("Q"), "(N,) bool: validity of each row of Q (N, 7) rad.")
      .def("check_segment", [](const StateChecker& c, const py::object& qa, const py::object& qb,
                               double max_step_rad, bool include_start) {
          const Arr a = real_array(qa, "qa", {kArmJoints});
          const Arr b = real_array(qb, "qb", {kArmJoints});
          if (!(max_step_rad > 0.0) || !std::isfinite(max_step_rad)) throw py::value_error("max_step_rad: must be finite and > 0");
          py::gil_scoped_release nogil;
          return translate([&] { return c.check_segment(a.data(), b.data(), max_step_rad, include_start); });
        }, py::arg("qa"), py::arg("qb"), py::arg("max_step_rad"), py::arg("include_start") = false,
        "True if every state of the straight joint line (step <= max_step_rad per joint) is valid.")
      .def("check_ompl_state", [](const StateChecker& c, const py::handle& s) {
          double q[kArmJoints];
          ompl_values(s, q);
          if (!finite7(q)) return false;
          return c.check(q);
        }, py::arg("state"), "OMPL state validity callback: a 7-D RealVectorState.")
      .def("check_ompl_motion", [](const StateChecker& c, const py::handle& s1, const py::handle& s2, double step) {
          double a[kArmJoints], b[kArmJoints];
          ompl_values(s1, a);
          ompl_values(s2, b);
          if (!finite7(a) || !finite7(b) || !(step > 0.0) || !std::isfinite(step)) return false;
          py::gil_scoped_release nogil;  // an edge is many states; a single state is not worth it
          return c.check_segment(a, b, step, false);
        }, py::arg("s1"), py::arg("s2"), py::arg("max_step_rad"),
        "OMPL motion callback: every state after s1 up to s2 (the start is valid by contract).")
      .def("first_invalid_on_path", [](const StateChecker& c, const py::object& W, double max_step_rad) {
          const Arr w = real_array(W, "waypoints", {-1, kArmJoints});
          if (!(max_step_rad > 0.0) || !std::isfinite(max_step_rad)) throw py::value_error("max_step_rad: must be finite and > 0");
          long long seg = -1, idx = -1;
          {
            py::gil_scoped_release nogil;
            translate([&] { return c.first_invalid_on_path(w.data(), static_cast<std::size_t>(w.shape(0)), max_step_rad, &seg, &idx); });
          }
          return py::make_tuple(seg, idx);
        }, py::arg("waypoints"), py::arg("max_step_rad"),
        "Dense check of the polyline (M, 7) after its first state: (segment, index) of the first "
        "invalid state (index i-1 of the state qa + (qb - qa) i / n), or (-1, -1) when all are valid.")
      .def("sphere_centres", [](const StateChecker& c, const py::object& q) {
          const Arr a = real_array(q, "q", {kArmJoints});
          const int ns = c.robot().num_spheres();
          std::vector<Vec3> out(static_cast<std::size_t>(ns));
          c.sphere_centres(a.data(), out.data());
          py::array_t<double> o({ns, 3});
          auto v = o.mutable_unchecked<2>();
          for (int i = 0; i < ns; ++i)
            for (int k = 0; k < 3; ++k) v(i, k) = out[static_cast<std::size_t>(i)][k];
          return o;
        }, py::arg("q"), "World sphere centres (S, 3) for q (7,).");
}

}  // namespace grasp_bind
