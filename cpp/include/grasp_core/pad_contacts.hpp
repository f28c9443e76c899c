// The passes over an object's points that the grasp sampler's contact checks make for every
// candidate frame: where the pads' strip meets the object along the approach, the material
// between the pads at a depth, and the contact patches at the pads' ends with the fingers' way
// in. Each is a reduction per frame over the points (minima, maxima, counts and one float32
// sum), in the points' order and in the operand types of the numpy formulation it replaces
// (orchestration/grasping/contacts.py), so the values are the same bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// The object's N points in the candidate frames' coordinates X = p·b, Y = p·c, Z = p·a
/// (float32): one contiguous column of N values per distinct (approach, closing) pair, and per
/// frame the column it reads and its closing line's offset x0 along b.
struct FrameColumns {
  std::size_t n_points = 0;
  std::size_t n_frames = 0;
  const float* x = nullptr;             ///< (columns, n_points)
  const float* y = nullptr;             ///< (columns, n_points)
  const float* z = nullptr;             ///< (columns, n_points)
  const std::int64_t* column = nullptr;  ///< (n_frames,) column of each frame
  const double* x0 = nullptr;            ///< (n_frames,) [m]
};

/// Per frame: the smallest and largest Z of the points in the pads' strip
/// (|X − x0| <= strip_half_width_m, in float64) and the smallest Z of those in the palm's
/// strip (|X − x0| <= palm_half_width_m); +inf / −inf where a strip holds none.
struct DepthBounds {
  std::vector<float> z_first, z_last, z_palm;
};
DepthBounds pad_depth_bounds(const FrameColumns& f, double strip_half_width_m, double palm_half_width_m);

/// Per frame: the smallest and largest Y, and the count, of the material — the points in the
/// pads' strip with |Z − z_tcp| <= half_length_m, computed in T (float: the float32
/// difference against the limit rounded to float32; double: in float64).
struct Material {
  std::vector<float> y_lo, y_hi;
  std::vector<std::int64_t> count;
};
template <typename T>
Material pad_material(const FrameColumns& f, double strip_half_width_m, const T* z_tcp, double half_length_m);

/// The limits of :func:`pad_contact_ends` (float32 ones are compared in float32).
struct EndLimits {
  double strip_half_width_m = 0.0;   ///< the pads' strip, |X − x0| <=
  double half_length_m = 0.0;        ///< the pads' window, |Z − z_tcp| <= (float64)
  float contact_depth_m = 0.0f;      ///< the patch: within this of the material's end along Y
  float cos_cone = 0.0f;             ///< a normal faces the pad where |n·c| >= this
  double finger_half_width_m = 0.0;  ///< the fingers' sweep, |X − x0| <=
};

/// The contact patch at one end of the material: the smallest and largest X of its points,
/// their count, the float32 sum of |n·c| over them (in the points' order, from 0) and how many
/// face the pad.
struct PadEnd {
  std::vector<float> x_lo, x_hi, normal_sum;
  std::vector<std::int64_t> count, facing;
};

/// Per frame, with the material at depth z_tcp (float64) whose Y runs y_lo..y_hi: the patches
/// at the upper end (Y − y_hi >= −contact_depth) and the lower end (Y − y_lo <= contact_depth),
/// and the object's points in each finger's way — in the fingers' sweep, Z <= z_tcp +
/// half_length_m (float64), and d = Y − y_mid within inner..outer (upper finger) or
/// −outer..−inner (lower finger). `closing` holds |n·c| or n·c of the points' normals, a
/// contiguous column of N values per distinct closing axis, `closing_column` the column of
/// each frame.
struct ContactEnds {
  PadEnd upper, lower;
  std::vector<std::int64_t> blocked_upper, blocked_lower;
};
ContactEnds pad_contact_ends(const FrameColumns& f, const float* closing, const std::int64_t* closing_column,
                             const EndLimits& lim, const double* z_tcp, const float* y_lo, const float* y_hi,
                             const float* y_mid, const float* inner, const float* outer);

}  // namespace grasp_core
