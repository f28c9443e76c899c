// Bindings of the arm IK refinement (grasp_core::ArmIK): built once from the exported chain
// (motion/core_checker.py) and the motion config's IK tolerances; the loops run with the
// GIL released. Bad arrays raise ValueError / TypeError naming the argument.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "grasp_core/arm_ik.hpp"
#include "planning_input.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

using namespace planning_input;

FlangePose pose_of(const Arr& T, py::ssize_t k) {
  FlangePose P;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) P.R(r, c) = T.data()[k * 16 + r * 4 + c];
    P.p[r] = T.data()[k * 16 + r * 4 + 3];
  }
  return P;
}

std::shared_ptr<ArmIK> make_ik(const py::dict& chain, int flange_body, const py::object& q_min,
                               const py::object& q_max, int iterations, double tol_m, double tol_rad,
                               double accept_m, double accept_rad, double limit_eps_rad) {
  ArmIkParams p;
  const Arr lo = real_array(q_min, "q_min_rad", {kArmJoints});
  const Arr hi = real_array(q_max, "q_max_rad", {kArmJoints});
  for (int j = 0; j < kArmJoints; ++j) { p.q_min_rad[j] = lo.at(j); p.q_max_rad[j] = hi.at(j); }
  p.iterations = iterations;
  p.tol_m = tol_m;
  p.tol_rad = tol_rad;
  p.accept_m = accept_m;
  p.accept_rad = accept_rad;
  p.limit_eps_rad = limit_eps_rad;
  std::vector<ChainBody> bodies = chain_bodies(chain);
  return translate([&] { return std::make_shared<ArmIK>(RobotChain(std::move(bodies)), flange_body, p); });
}

py::array_t<double> matrix44(const FlangePose& P) {
  py::array_t<double> T({4, 4});
  auto v = T.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v(r, c) = r < 3 ? (c < 3 ? P.R(r, c) : P.p[r]) : (c == 3 ? 1.0 : 0.0);
  return T;
}

}  // namespace

void bind_ik(py::module_& m) {
  py::class_<ArmIK, std::shared_ptr<ArmIK>>(
      m, "ArmIK",
      "Gauss-Newton refinement of arm joints to a flange pose on the exported chain "
      "(motion/ik.py's refinement loop in C++): flange_pose, refine_batch, refine_line.")
      .def(py::init(&make_ik), py::arg("chain"), py::arg("flange_body"), py::arg("q_min_rad"),
           py::arg("q_max_rad"), py::arg("iterations"), py::arg("tol_m"), py::arg("tol_rad"),
           py::arg("accept_m"), py::arg("accept_rad"), py::arg("limit_eps_rad"))
      .def("flange_pose", [](const ArmIK& ik, const py::object& q) {
          const Arr a = real_array(q, "q", {kArmJoints});
          return matrix44(ik.flange(a.data()));
        }, py::arg("q"), "Flange pose (4, 4) for arm state q (7,).")
      .def("refine_batch", [](const ArmIK& ik, const py::object& T, const py::object& Q) {
          const Arr t = real_array(T, "T", {4, 4});
          const Arr seeds = real_array(Q, "Q", {-1, kArmJoints});
          const py::ssize_t n = seeds.shape(0);
          py::array_t<double> out({n, static_cast<py::ssize_t>(kArmJoints)});
          py::array_t<bool> ok(n);
          double* o = out.mutable_data();
          bool* k = ok.mutable_data();
          std::copy(seeds.data(), seeds.data() + n * kArmJoints, o);
          {
            py::gil_scoped_release nogil;
            const FlangePose P = pose_of(t, 0);
            for (py::ssize_t i = 0; i < n; ++i) k[i] = ik.refine(P, o + i * kArmJoints);
          }
          return py::make_tuple(out, ok);
        }, py::arg("T"), py::arg("Q"),
        "Refine every seed row of Q (N, 7) towards the flange pose T (4, 4): (refined (N, 7), "
        "kept (N,) bool: inside the limits and verified; kept rows are clipped to the limits).")
      .def("refine_line", [](const ArmIK& ik, const py::object& Ts, const py::object& q0) {
          const Arr t = real_array(Ts, "Ts", {-1, 4, 4});
          const Arr a = real_array(q0, "q0", {kArmJoints});
          const py::ssize_t n = t.shape(0);
          std::vector<double> Q(static_cast<std::size_t>(n * kArmJoints));
          py::ssize_t solved = 0;
          {
            py::gil_scoped_release nogil;
            const double* prev = a.data();
            for (; solved < n; ++solved) {
              double* q = Q.data() + solved * kArmJoints;
              std::copy(prev, prev + kArmJoints, q);
              if (!ik.refine(pose_of(t, solved), q)) break;
              prev = q;
            }
          }
          py::array_t<double> out({solved, static_cast<py::ssize_t>(kArmJoints)});
          std::copy(Q.data(), Q.data() + solved * kArmJoints, out.mutable_data());
          return out;
        }, py::arg("Ts"), py::arg("q0"),
        "Refine the poses Ts (n, 4, 4) in order, each seeded by the previous solution (the first "
        "by q0): the solved prefix (k, 7), k < n when pose k could not be refined and verified.");
}

}  // namespace grasp_bind
