// Argument conversion shared by the planning bindings (collision checker, arm IK): every
// array is checked (real dtype, shape, finite) and rejected with a ValueError / TypeError
// naming the argument; C++ std::invalid_argument becomes ValueError.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "grasp_core/robot_chain.hpp"

namespace grasp_bind {
namespace planning_input {

namespace py = pybind11;
using grasp_core::Mat3;
using grasp_core::Vec3;

using Arr = py::array_t<double, py::array::c_style | py::array::forcecast>;

inline std::string shape_str(const py::array& a) {
  std::ostringstream os;
  os << "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) os << (i ? ", " : "") << a.shape(i);
  os << (a.ndim() == 1 ? ",)" : ")");
  return os.str();
}

/// A real (bool excluded) float64 C-contiguous copy/view with the expected shape; -1 = any.
inline Arr real_array(const py::handle& obj, const char* name, std::vector<py::ssize_t> shape, bool finite = true) {
  py::array raw;
  try {
    raw = py::array::ensure(obj);
  } catch (...) {
  }
  if (!raw) throw py::type_error(std::string(name) + ": expected an array of numbers");
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected real numbers, got dtype " +
                         py::str(raw.dtype()).cast<std::string>());
  bool ok = raw.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t k = 0; ok && k < shape.size(); ++k) ok = shape[k] < 0 || raw.shape(static_cast<py::ssize_t>(k)) == shape[k];
  if (!ok) {
    std::ostringstream os;
    os << name << ": expected shape (";
    for (std::size_t k = 0; k < shape.size(); ++k) {
      os << (k ? ", " : "");
      if (shape[k] < 0) os << "N"; else os << shape[k];
    }
    os << (shape.size() == 1 ? ",)" : ")") << ", got " << shape_str(raw);
    throw py::value_error(os.str());
  }
  Arr a = Arr::ensure(raw);
  if (!a) throw py::type_error(std::string(name) + ": cannot convert to float64");
  if (finite) {
    const double* d = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i)
      if (!std::isfinite(d[i])) throw py::value_error(std::string(name) + ": must be finite, got NaN/Inf");
  }
  return a;
}

inline std::vector<int> int_vector(const py::handle& obj, const char* name, py::ssize_t n) {
  Arr a = real_array(obj, name, {n});
  std::vector<int> out(static_cast<std::size_t>(a.size()));
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    const double v = a.data()[i];
    if (v != std::floor(v) || std::abs(v) > 1e9) throw py::value_error(std::string(name) + ": expected integers");
    out[static_cast<std::size_t>(i)] = static_cast<int>(v);
  }
  return out;
}

inline Vec3 row3(const Arr& a, py::ssize_t i) { return Vec3(a.at(i, 0), a.at(i, 1), a.at(i, 2)); }
inline Mat3 mat_at(const Arr& a, py::ssize_t i) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = a.at(i, r, c);
  return m;
}

inline double finite_arg(double v, const char* name) {
  if (!std::isfinite(v)) throw py::value_error(std::string(name) + ": must be finite");
  return v;
}

template <typename Fn>
auto translate(Fn&& fn) {
  try {
    return fn();
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}


/// The chain rows of an exported robot (motion/core_checker.py: body_parent, body_rotation,
/// body_position, body_joint, joint_axis, joint_anchor, joint_q0_rad) from a dict.
inline std::vector<grasp_core::ChainBody> chain_bodies(const py::dict& a) {
  auto get = [&](const char* k) -> py::object {
    if (!a.contains(k)) throw py::value_error(std::string("robot model: missing entry '") + k + "'");
    return a[k];
  };
  const Arr parent = real_array(get("body_parent"), "body_parent", {-1});
  const py::ssize_t nb = parent.shape(0);
  const std::vector<int> par = int_vector(get("body_parent"), "body_parent", nb);
  const std::vector<int> joint = int_vector(get("body_joint"), "body_joint", nb);
  const Arr rot = real_array(get("body_rotation"), "body_rotation", {nb, 3, 3});
  const Arr pos = real_array(get("body_position"), "body_position", {nb, 3});
  const Arr axis = real_array(get("joint_axis"), "joint_axis", {nb, 3});
  const Arr anchor = real_array(get("joint_anchor"), "joint_anchor", {nb, 3});
  const Arr q0 = real_array(get("joint_q0_rad"), "joint_q0_rad", {nb});
  std::vector<grasp_core::ChainBody> out;
  for (py::ssize_t b = 0; b < nb; ++b)
    out.push_back(grasp_core::ChainBody{par[static_cast<std::size_t>(b)], mat_at(rot, b), row3(pos, b),
                                        joint[static_cast<std::size_t>(b)], row3(axis, b), row3(anchor, b), q0.at(b)});
  return out;
}

}  // namespace planning_input
}  // namespace grasp_bind
