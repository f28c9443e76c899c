// Per-pixel work on a simulated depth image, fused into single passes: the invalid pixels
// (NaN) and the grazing-angle mask (docs/method.md §0: a surface seen at more than
// grazing_max_deg from its normal gives no return), and the back-projection of the final
// depth to world points. Every value is the float32 result of the same operations, in the
// same order, as the numpy formulation in grasp_pipeline.sim.camera (no fused multiply-add:
// this file's object is compiled with -ffp-contract=off), so frames are identical bit for
// bit whichever computes them.
#pragma once

#include <cstddef>
#include <cstdint>

namespace grasp_core {

/// Pinhole geometry of an H x W depth image: x[u] = (u - cx) / fx, y[v] = (v - cy) / fy,
/// ray_norm2[v * W + u] = |(x, y, 1)|^2, and fx, fy [px], all float32.
struct DepthImageGeometry {
  int height = 0, width = 0;
  const float* x = nullptr;          ///< W values
  const float* y = nullptr;          ///< H values
  const float* ray_norm2 = nullptr;  ///< H * W values
  float fx = 1.0f, fy = 1.0f;
};

/// z[p] = NaN where invalid[p]; then invalid[p] |= the surface at p is seen at more than the
/// grazing angle (cos2_max = cos^2 of it): with the one-sided depth differences of smaller
/// magnitude g_u = fx dz/du, g_v = fy dz/dv (the following one on a tie, the preceding one
/// when either is NaN; 0 on the image border), the normal n = (-g_u, -g_v, g_u x + g_v y + z)
/// and the test z^2 < cos2_max |n|^2 |r|^2. z and invalid are H x W, row-major.
void mask_invalid_and_grazing(const DepthImageGeometry& g, float cos2_max, float* z,
                              std::uint8_t* invalid);

/// z[p] = NaN where invalid[p]; points[3 p + i] = ((R[i][0] x + R[i][1] y) + R[i][2]) z + t[i]
/// (R row-major 3x3 and t: the camera's world pose, float32).
void depth_to_world_points(const DepthImageGeometry& g, const float* R, const float* t,
                           float* z, const std::uint8_t* invalid, float* points);

/// The depth buffer of a perspective render (reversed-Z values, rows bottom to top, H x W)
/// as metres along the optical axis, rows top to bottom:
/// out[v][u] = float(double(d_coef) / (double(raw[H-1-v][u]) + double(c_coef))) —
/// mujoco.Renderer's linearisation (float32 coefficients, float64 division).
void metric_depth(int height, int width, const float* raw, float c_coef, float d_coef, float* out);

/// The sensor's depth noise added to z in one pass, the normal draws given:
/// sigma = ((z / ref_range) ^ 2) * sigma_at_ref, noise[p] = noise[p] * sigma + z[p]
/// (float32, in this order; the quadratic law of grasp_pipeline.robot.depth_noise with
/// exponent 2). `noise` holds the standard normal draws on entry and the noisy depth on exit.
void add_quadratic_depth_noise(std::size_t n, const float* z, float ref_range, float sigma_at_ref,
                               float* noise);

}  // namespace grasp_core
