// Thread safety and argument checks of the stateful bindings.
//
// Thread safety (the choice: serialise, not refuse). The stateful core objects
// (Perception, SceneFilter, PlanePersistence, Tracker) are not thread-safe in C++. In
// Python each one is a Guarded<T>: shared ownership of its *root* object plus the root's
// mutex. Views of sub-objects (Perception.scene_filter, Perception.tracker,
// SceneFilter.persistence) alias into the root: they keep it alive and share its mutex, so
// a read through a view never races a process() on the owner. Every method runs through
// locked(): the GIL is released *before* waiting for the mutex and the work inside never
// touches a Python object, so a thread never holds the mutex while waiting for the GIL
// (no deadlock) and other Python threads run meanwhile. Calls from several threads on one
// object are therefore serialised in arrival order of the mutex (no FIFO guarantee).
#pragma once

#include <pybind11/pybind11.h>

#include <climits>
#include <cstdint>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>

namespace grasp_bind {

namespace py = pybind11;

template <typename T>
struct Guarded {
  std::shared_ptr<T> obj;             ///< the object (an alias into the root for views)
  std::shared_ptr<std::mutex> mutex;  ///< the root object's lock

  template <typename... Args>
  static Guarded make(Args&&... args) {
    return Guarded{std::make_shared<T>(std::forward<Args>(args)...), std::make_shared<std::mutex>()};
  }
  /// A view of `member` (a sub-object of *obj): shares ownership and the lock of the root.
  template <typename U>
  Guarded<U> view(U& member) const {
    return Guarded<U>{std::shared_ptr<U>(obj, &member), mutex};
  }
};

/// Run fn(object) with the object's mutex held and the GIL released (see the file comment).
/// fn must not touch Python objects; its result is converted after the GIL is back.
template <typename T, typename Fn>
auto locked(const Guarded<T>& g, Fn&& fn) {
  py::gil_scoped_release nogil;
  const std::lock_guard<std::mutex> lock(*g.mutex);
  return fn(*g.obj);
}

// ---- argument checks: a Python value -> a C++ scalar, or an error naming the argument ----

inline std::string repr_of(const py::handle& h) {
  std::string r = py::repr(h).cast<std::string>();
  return r.size() > 60 ? r.substr(0, 57) + "..." : r;
}

inline bool is_bool(const py::handle& h) { return PyBool_Check(h.ptr()); }

/// An integer (Python int or numpy integer; not bool, not float) in [lo, hi].
inline long long int_arg(const py::handle& h, const char* name, long long lo, long long hi) {
  if (is_bool(h) || !PyIndex_Check(h.ptr()) || PyFloat_Check(h.ptr())) {
    std::ostringstream os;
    os << name << ": expected an integer, got " << Py_TYPE(h.ptr())->tp_name << " " << repr_of(h);
    throw py::type_error(os.str());
  }
  py::int_ v = py::reinterpret_steal<py::int_>(PyNumber_Index(h.ptr()));
  if (!v) throw py::error_already_set();
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
  if (overflow != 0 || x < lo || x > hi) {
    std::ostringstream os;
    os << name << ": " << repr_of(v) << " is out of range; expected an integer in [" << lo
       << ", " << hi << "]";
    throw py::value_error(os.str());
  }
  return x;
}

/// A non-negative integer seed in [0, 2^64 - 1].
inline std::uint64_t seed_arg(const py::handle& h, const char* name) {
  if (is_bool(h) || !PyIndex_Check(h.ptr()) || PyFloat_Check(h.ptr())) {
    std::ostringstream os;
    os << name << ": expected a non-negative integer, got " << Py_TYPE(h.ptr())->tp_name << " "
       << repr_of(h);
    throw py::type_error(os.str());
  }
  py::int_ v = py::reinterpret_steal<py::int_>(PyNumber_Index(h.ptr()));
  if (!v) throw py::error_already_set();
  const unsigned long long x = PyLong_AsUnsignedLongLong(v.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    std::ostringstream os;
    os << name << ": " << repr_of(v) << " is out of range; expected an integer in [0, 2^64 - 1]";
    throw py::value_error(os.str());
  }
  return static_cast<std::uint64_t>(x);
}

/// A real number (int/float/numpy scalar; not bool, not str). Range checks are the caller's.
inline double float_arg(const py::handle& h, const char* name) {
  if (is_bool(h) || PyUnicode_Check(h.ptr()) || PyBytes_Check(h.ptr()) ||
      !(PyFloat_Check(h.ptr()) || PyIndex_Check(h.ptr()) || PyNumber_Check(h.ptr()))) {
    std::ostringstream os;
    os << name << ": expected a number, got " << Py_TYPE(h.ptr())->tp_name << " " << repr_of(h);
    throw py::type_error(os.str());
  }
  const double x = PyFloat_AsDouble(h.ptr());
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();  // e.g. an int too large for a double
    std::ostringstream os;
    os << name << ": " << repr_of(h) << " cannot be converted to a float64 number";
    throw py::value_error(os.str());
  }
  return x;
}

inline bool bool_arg(const py::handle& h, const char* name) {
  if (!is_bool(h) && !py::isinstance(h, py::module_::import("numpy").attr("bool_"))) {
    std::ostringstream os;
    os << name << ": expected True or False, got " << Py_TYPE(h.ptr())->tp_name << " " << repr_of(h);
    throw py::type_error(os.str());
  }
  return h.cast<bool>();
}

/// Properties of a parameter struct whose setters check the Python value and name the
/// field ("SceneFilterParams.cluster_eps: expected a number, got str 'abc'"); semantic
/// ranges stay in the struct's validate().
template <typename C, typename S>
void float_field(C& cls, const char* name, double S::*member) {
  const std::string full = std::string(py::str(cls.attr("__name__"))) + "." + name;
  cls.def_property(name, [member](const S& s) { return s.*member; },
                   [member, full](S& s, const py::object& v) { s.*member = float_arg(v, full.c_str()); });
}

template <typename C, typename S>
void int_field(C& cls, const char* name, int S::*member) {
  const std::string full = std::string(py::str(cls.attr("__name__"))) + "." + name;
  cls.def_property(name, [member](const S& s) { return s.*member; },
                   [member, full](S& s, const py::object& v) {
                     s.*member = static_cast<int>(int_arg(v, full.c_str(), INT_MIN, INT_MAX));
                   });
}

template <typename C, typename S>
void bool_field(C& cls, const char* name, bool S::*member) {
  const std::string full = std::string(py::str(cls.attr("__name__"))) + "." + name;
  cls.def_property(name, [member](const S& s) { return s.*member; },
                   [member, full](S& s, const py::object& v) { s.*member = bool_arg(v, full.c_str()); });
}

template <typename C, typename S>
void seed_field(C& cls, const char* name, std::uint64_t S::*member) {
  const std::string full = std::string(py::str(cls.attr("__name__"))) + "." + name;
  cls.def_property(name, [member](const S& s) { return s.*member; },
                   [member, full](S& s, const py::object& v) { s.*member = seed_arg(v, full.c_str()); });
}

}  // namespace grasp_bind
