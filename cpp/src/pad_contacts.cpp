#include "grasp_core/pad_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grasp_core {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// The points' columns read by frame k.
struct Column {
  const float* x;
  const float* y;
  const float* z;
};

Column column_of(const FrameColumns& f, std::size_t k) {
  const std::size_t off = static_cast<std::size_t>(f.column[k]) * f.n_points;
  return {f.x + off, f.y + off, f.z + off};
}

/// |X − x0| <= half_width in float64 (numpy: a float32 array minus a float64 one).
inline bool within(float x, double x0, double half_width) {
  return std::fabs(static_cast<double>(x) - x0) <= half_width;
}

}  // namespace

DepthBounds pad_depth_bounds(const FrameColumns& f, double strip_half_width_m, double palm_half_width_m) {
  DepthBounds out;
  out.z_first.assign(f.n_frames, kInf);
  out.z_last.assign(f.n_frames, -kInf);
  out.z_palm.assign(f.n_frames, kInf);
  for (std::size_t k = 0; k < f.n_frames; ++k) {
    const Column c = column_of(f, k);
    const double x0 = f.x0[k];
    float lo = kInf, hi = -kInf, palm = kInf;
    for (std::size_t i = 0; i < f.n_points; ++i) {
      // branch-free: whether a point is in a strip does not follow a pattern
      const double dx = std::fabs(static_cast<double>(c.x[i]) - x0);
      const float z = c.z[i];
      const bool strip = dx <= strip_half_width_m;
      lo = std::min(lo, strip ? z : kInf);
      hi = std::max(hi, strip ? z : -kInf);
      palm = std::min(palm, dx <= palm_half_width_m ? z : kInf);
    }
    out.z_first[k] = lo, out.z_last[k] = hi, out.z_palm[k] = palm;
  }
  return out;
}

template <typename T>
Material pad_material(const FrameColumns& f, double strip_half_width_m, const T* z_tcp, double half_length_m) {
  Material out;
  out.y_lo.assign(f.n_frames, kInf);
  out.y_hi.assign(f.n_frames, -kInf);
  out.count.assign(f.n_frames, 0);
  const T half = static_cast<T>(half_length_m);
  for (std::size_t k = 0; k < f.n_frames; ++k) {
    const Column c = column_of(f, k);
    const double x0 = f.x0[k];
    const T zt = z_tcp[k];
    float lo = kInf, hi = -kInf;
    std::int64_t n = 0;
    for (std::size_t i = 0; i < f.n_points; ++i) {
      const bool mat = within(c.x[i], x0, strip_half_width_m) & (std::fabs(static_cast<T>(c.z[i]) - zt) <= half);
      lo = std::min(lo, mat ? c.y[i] : kInf);
      hi = std::max(hi, mat ? c.y[i] : -kInf);
      n += mat ? 1 : 0;
    }
    out.y_lo[k] = lo, out.y_hi[k] = hi, out.count[k] = n;
  }
  return out;
}

template Material pad_material<float>(const FrameColumns&, double, const float*, double);
template Material pad_material<double>(const FrameColumns&, double, const double*, double);

namespace {

void resize_end(PadEnd& e, std::size_t k) {
  e.x_lo.resize(k);
  e.x_hi.resize(k);
  e.normal_sum.resize(k);
  e.count.resize(k);
  e.facing.resize(k);
}

/// A patch's running reductions over one frame's points (kept in registers).
struct EndSums {
  float x_lo = kInf, x_hi = -kInf, sum = 0.0f;
  std::int64_t count = 0, facing = 0;

  /// Branch-free: whether a point is in the patch follows no pattern. A point left out adds
  /// 0 to the float32 sum, as numpy's masked sum does (x + 0 == x).
  void add(bool in, float x, float along, bool faces) {
    x_lo = std::min(x_lo, in ? x : kInf);
    x_hi = std::max(x_hi, in ? x : -kInf);
    sum += in ? along : 0.0f;
    count += in;
    facing += in & faces;
  }

  void store(PadEnd& e, std::size_t k) const {
    e.x_lo[k] = x_lo, e.x_hi[k] = x_hi, e.normal_sum[k] = sum, e.count[k] = count, e.facing[k] = facing;
  }
};

}  // namespace

ContactEnds pad_contact_ends(const FrameColumns& f, const float* closing, const std::int64_t* closing_column,
                             const EndLimits& lim, const double* z_tcp, const float* y_lo, const float* y_hi,
                             const float* y_mid, const float* inner, const float* outer) {
  ContactEnds out;
  resize_end(out.upper, f.n_frames);
  resize_end(out.lower, f.n_frames);
  out.blocked_upper.assign(f.n_frames, 0);
  out.blocked_lower.assign(f.n_frames, 0);
  for (std::size_t k = 0; k < f.n_frames; ++k) {
    const Column c = column_of(f, k);
    const float* along = closing + static_cast<std::size_t>(closing_column[k]) * f.n_points;
    const double x0 = f.x0[k], zt = z_tcp[k], reach = z_tcp[k] + lim.half_length_m;
    const float hi = y_hi[k], lo = y_lo[k], mid = y_mid[k], in = inner[k], out_ = outer[k];
    EndSums up, low;
    std::int64_t block_up = 0, block_low = 0;
    for (std::size_t i = 0; i < f.n_points; ++i) {
      const double dx = std::fabs(static_cast<double>(c.x[i]) - x0);
      const float y = c.y[i];
      const double z = static_cast<double>(c.z[i]);
      const bool mat = (dx <= lim.strip_half_width_m) & (std::fabs(z - zt) <= lim.half_length_m);
      const bool faces = along[i] >= lim.cos_cone;
      up.add(mat & (y - hi >= -lim.contact_depth_m), c.x[i], along[i], faces);
      low.add(mat & (y - lo <= lim.contact_depth_m), c.x[i], along[i], faces);
      const bool way = (dx <= lim.finger_half_width_m) & (z <= reach);
      const float d = y - mid;
      block_up += way & (d >= in) & (d <= out_);
      block_low += way & (d <= -in) & (d >= -out_);
    }
    up.store(out.upper, k), low.store(out.lower, k);
    out.blocked_upper[k] = block_up, out.blocked_lower[k] = block_low;
  }
  return out;
}

}  // namespace grasp_core
