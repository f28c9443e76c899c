// Validation of numpy inputs at the edge: every user array passes through here.
//
// Points are (N, 3) float32 or float64. The per-frame path reads them in place (no copy)
// when each row's three values are adjacent (column stride == item size), whatever the row
// stride (so slices like cloud[::2] are free); otherwise one contiguous copy is made.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "grasp_core/types.hpp"

namespace grasp_bind {

namespace py = pybind11;

/// A validated, strided view on an (N,3) float32/float64 array. `keep` owns the memory.
struct PointsView {
  py::array keep;
  const void* data = nullptr;
  std::size_t rows = 0;
  std::size_t row_stride = 0;  ///< in elements
  bool is_float = false;       ///< float32 (else float64)
  bool copied = false;
};

inline std::string describe(const py::handle& obj) {
  return py::str(py::type::of(obj).attr("__name__")).cast<std::string>();
}

/// True when `arr`'s dtype is T's by numpy's equivalence: an array that crossed a pickle (a
/// process pool, Ray) carries an equal dtype that is not numpy's shared dtype object.
template <typename T>
inline bool has_dtype(const py::array& arr) {
  return py::isinstance<py::array_t<T>>(arr);
}

/// `obj` as a C-ordered array of dtype T and the given shape (-1: any size), else an error
/// that names the argument and the fix.
template <typename T>
inline py::array checked(const py::object& obj, const char* name, std::initializer_list<py::ssize_t> shape,
                         bool writable) {
  const std::string want = py::str(py::dtype::of<T>()).cast<std::string>();
  if (!py::isinstance<py::array>(obj))
    throw py::type_error(std::string(name) + ": expected a numpy array of dtype " + want + ", got " +
                         describe(obj));
  py::array arr = py::reinterpret_borrow<py::array>(obj);
  if (!has_dtype<T>(arr))
    throw py::type_error(std::string(name) + ": expected dtype " + want + ", got " +
                         py::str(arr.dtype()).cast<std::string>() + " (convert with .astype)");
  bool ok = arr.ndim() == static_cast<py::ssize_t>(shape.size());
  py::ssize_t i = 0;
  for (py::ssize_t s : shape) ok = ok && (s < 0 ? arr.shape(i) > 0 : arr.shape(i) == s), ++i;
  if (!ok) {
    std::ostringstream os;
    os << name << ": expected shape (";
    i = 0;
    for (py::ssize_t s : shape) os << (i++ ? ", " : "") << (s < 0 ? std::string("n") : std::to_string(s));
    os << "), got (";
    for (py::ssize_t k = 0; k < arr.ndim(); ++k) os << (k ? ", " : "") << arr.shape(k);
    os << ")";
    throw py::value_error(os.str());
  }
  if (!(arr.flags() & py::array::c_style))
    throw py::value_error(std::string(name) + ": expected a C-ordered array (numpy.ascontiguousarray)");
  if (writable && !arr.writeable())
    throw py::value_error(std::string(name) + ": the array is read-only; pass a writable copy");
  return arr;
}

/// Reject anything that is not an (N,3) float32/float64 array (name = argument name).
inline py::array checked_array(const py::object& obj, const char* name, bool allow_empty) {
  if (!py::isinstance<py::array>(obj)) {
    std::ostringstream os;
    os << name << ": expected a numpy array of shape (N, 3) with dtype float32 or float64, got "
       << describe(obj) << " (convert with numpy.asarray(..., dtype=numpy.float32))";
    throw py::type_error(os.str());
  }
  py::array arr = py::reinterpret_borrow<py::array>(obj);
  const bool f32 = has_dtype<float>(arr);
  const bool f64 = has_dtype<double>(arr);
  if (!f32 && !f64) {
    std::ostringstream os;
    os << name << ": expected dtype float32 or float64, got "
       << py::str(arr.dtype()).cast<std::string>()
       << " (convert with .astype(numpy.float32))";
    throw py::type_error(os.str());
  }
  if (arr.ndim() != 2 || arr.shape(1) != 3) {
    std::ostringstream os;
    os << name << ": expected shape (N, 3), got (";
    for (py::ssize_t i = 0; i < arr.ndim(); ++i) os << (i ? ", " : "") << arr.shape(i);
    os << (arr.ndim() == 1 ? ",)" : ")")
       << " (an organized H x W x 3 cloud can be passed as cloud.reshape(-1, 3))";
    throw py::value_error(os.str());
  }
  if (!allow_empty && arr.shape(0) == 0) {
    std::ostringstream os;
    os << name << ": empty cloud (0 points); expected at least one point";
    throw py::value_error(os.str());
  }
  return arr;
}

/// Strided view without copying where possible.
inline PointsView points_view(const py::object& obj, const char* name, bool allow_empty = false) {
  py::array arr = checked_array(obj, name, allow_empty);
  PointsView v;
  v.is_float = has_dtype<float>(arr);
  const py::ssize_t item = arr.itemsize();
  const bool rows_ok = arr.shape(0) <= 1 || (arr.strides(0) > 0 && arr.strides(0) % item == 0);
  if (arr.strides(1) != item || !rows_ok) {
    arr = py::array::ensure(arr, py::array::c_style | py::array::forcecast);
    if (v.is_float) arr = py::array_t<float, py::array::c_style>(arr);
    else arr = py::array_t<double, py::array::c_style>(arr);
    v.copied = true;
  }
  v.keep = arr;
  v.data = arr.data();
  v.rows = static_cast<std::size_t>(arr.shape(0));
  v.row_stride = arr.shape(0) <= 1 ? 3 : static_cast<std::size_t>(arr.strides(0) / item);
  return v;
}

/// The max_abs_coordinate_m argument of a fine-grained function.
inline double checked_bound(double bound, const char* name = "max_abs_coordinate_m") {
  if (!(bound > 0 && bound <= grasp_core::kMaxAbsCoordinateLimit_m)) {
    std::ostringstream os;
    os << name << ": expected a coordinate bound in (0, 1e9] m, got " << bound;
    throw py::value_error(os.str());
  }
  return bound;
}

/// Copy to PointsD, dropping rows with a NaN/Inf or a |coordinate| > bound (their count
/// goes to *dropped).
inline grasp_core::PointsD points_double(const py::object& obj, const char* name,
                                         std::size_t* dropped = nullptr,
                                         bool allow_empty = false,
                                         double bound = grasp_core::kDefaultMaxAbsCoordinate_m) {
  PointsView v = points_view(obj, name, allow_empty);
  std::vector<double> buf;
  buf.reserve(v.rows * 3);
  std::size_t bad = 0;
  for (std::size_t r = 0; r < v.rows; ++r) {
    double x, y, z;
    if (v.is_float) {
      const float* p = static_cast<const float*>(v.data) + r * v.row_stride;
      x = p[0]; y = p[1]; z = p[2];
    } else {
      const double* p = static_cast<const double*>(v.data) + r * v.row_stride;
      x = p[0]; y = p[1]; z = p[2];
    }
    if (!grasp_core::within_bound(x, y, z, bound)) { ++bad; continue; }
    buf.push_back(x); buf.push_back(y); buf.push_back(z);
  }
  if (dropped) *dropped = bad;
  grasp_core::PointsD out(static_cast<Eigen::Index>(buf.size() / 3), 3);
  for (Eigen::Index i = 0; i < out.rows(); ++i) {
    out(i, 0) = buf[3 * i]; out(i, 1) = buf[3 * i + 1]; out(i, 2) = buf[3 * i + 2];
  }
  return out;
}

/// A finite 3-vector argument.
inline grasp_core::Vec3 vec3(const py::object& obj, const char* name) {
  py::array_t<double, py::array::forcecast> arr;
  try {
    arr = py::array_t<double, py::array::forcecast>::ensure(obj);
  } catch (...) {
    arr = py::array_t<double, py::array::forcecast>();
  }
  if (!arr || arr.ndim() != 1 || arr.shape(0) != 3) {
    throw py::value_error(std::string(name) + ": expected 3 numbers (x, y, z)");
  }
  grasp_core::Vec3 v(arr.at(0), arr.at(1), arr.at(2));
  if (!v.allFinite()) throw py::value_error(std::string(name) + ": must be finite, got NaN/Inf");
  return v;
}

/// A finite 3x3 matrix argument.
inline grasp_core::Mat3 mat3(const py::object& obj, const char* name) {
  py::array_t<double, py::array::forcecast> arr;
  try {
    arr = py::array_t<double, py::array::forcecast>::ensure(obj);
  } catch (...) {
    arr = py::array_t<double, py::array::forcecast>();
  }
  if (!arr || arr.ndim() != 2 || arr.shape(0) != 3 || arr.shape(1) != 3) {
    throw py::value_error(std::string(name) + ": expected a 3x3 matrix");
  }
  grasp_core::Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = arr.at(i, j);
  if (!m.allFinite()) throw py::value_error(std::string(name) + ": must be finite, got NaN/Inf");
  return m;
}

/// std::vector<int> -> numpy int32 without an extra copy.
inline py::array_t<int> to_numpy(std::vector<int>&& v) {
  auto* heap = new std::vector<int>(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<int>*>(p); });
  return py::array_t<int>(static_cast<py::ssize_t>(heap->size()), heap->data(), owner);
}

inline py::array_t<double> to_numpy(const std::vector<double>& v) {
  py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

/// An optional colour image for `rows` points: None -> an empty handle; else a
/// C-contiguous uint8 array with rows x 3 values ((H, W, 3) or (N, 3)), read in place when it
/// already is one (a copy otherwise). TypeError / ValueError name the argument.
/// The colour rows of `obj` (C-contiguous uint8), or an empty array for None (callers test
/// `obj.is_none()`: an empty py::array is a valid object whose data() is not null).
inline py::array rgb_view(const py::object& obj, std::size_t rows) {
  if (obj.is_none()) return py::array();
  if (!py::isinstance<py::array>(obj))
    throw py::type_error("rgb: expected None or a numpy uint8 array of shape (H, W, 3), got " +
                         describe(obj));
  py::array arr = py::reinterpret_borrow<py::array>(obj);
  if (!has_dtype<std::uint8_t>(arr))
    throw py::type_error("rgb: expected dtype uint8, got " + py::str(arr.dtype()).cast<std::string>() +
                         " (convert with .astype(numpy.uint8))");
  const bool shape_ok = (arr.ndim() == 3 && arr.shape(2) == 3) || (arr.ndim() == 2 && arr.shape(1) == 3);
  if (!shape_ok || static_cast<std::size_t>(arr.size()) != 3 * rows) {
    std::ostringstream os;
    os << "rgb: expected shape (H, W, 3) with H*W = " << rows << " points (one colour per row), got (";
    for (py::ssize_t i = 0; i < arr.ndim(); ++i) os << (i ? ", " : "") << arr.shape(i);
    os << ")";
    throw py::value_error(os.str());
  }
  return py::array_t<std::uint8_t, py::array::c_style>::ensure(arr);
}

}  // namespace grasp_bind
