// Fused per-pixel passes over a depth image (see depth_image.hpp). The arithmetic is written
// as float32 operations in the order of the numpy formulation; nothing here may be reordered
// or contracted (CMakeLists.txt compiles this file with -ffp-contract=off).
#include "grasp_core/depth_image.hpp"
#include "simd_clones.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace grasp_core {

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Of the preceding difference `prv` and the following one `nxt`, the smaller in magnitude
/// (`nxt` on a tie; `prv` when either is NaN, as a comparison with NaN is false).
inline float smaller_step(float prv, float nxt) {
  return std::fabs(nxt) <= std::fabs(prv) ? nxt : prv;
}

}  // namespace

void mask_invalid_and_grazing(const DepthImageGeometry& g, float cos2_max, float* z,
                              std::uint8_t* invalid) {
  const int h = g.height, w = g.width;
  const std::size_t n = static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
  for (std::size_t p = 0; p < n; ++p) z[p] = invalid[p] ? kNaN : z[p];
  std::vector<float> gu(static_cast<std::size_t>(w)), gv(static_cast<std::size_t>(w));
  for (int v = 0; v < h; ++v) {
    const float* row = z + static_cast<std::size_t>(v) * w;
    if (v > 0 && v + 1 < h) {
      const float* up = row - w;
      const float* down = row + w;
      for (int u = 0; u < w; ++u) gv[u] = smaller_step(row[u] - up[u], down[u] - row[u]) * g.fy;
    } else {
      for (int u = 0; u < w; ++u) gv[u] = 0.0f * g.fy;  // the image border
    }
    gu[0] = 0.0f * g.fx;
    gu[w - 1] = 0.0f * g.fx;
    for (int u = 1; u + 1 < w; ++u) gu[u] = smaller_step(row[u] - row[u - 1], row[u + 1] - row[u]) * g.fx;
    // (restrict: the byte stores into `inv` could otherwise alias every float read)
    std::uint8_t* __restrict inv = invalid + static_cast<std::size_t>(v) * w;
    const float* __restrict zr = row;
    const float* __restrict rn2 = g.ray_norm2 + static_cast<std::size_t>(v) * w;
    const float* __restrict x = g.x;
    const float* __restrict gur = gu.data();
    const float* __restrict gvr = gv.data();
    const float y = g.y[v];
    for (int u = 0; u < w; ++u) {
      float nz = gur[u] * x[u];
      nz = nz + gvr[u] * y;
      nz = nz + zr[u];
      float n2 = gur[u] * gur[u];
      n2 = n2 + gvr[u] * gvr[u];
      n2 = n2 + nz * nz;
      const float rhs = (cos2_max * n2) * rn2[u];
      inv[u] = static_cast<std::uint8_t>(inv[u] | (zr[u] * zr[u] < rhs));
    }
  }
}

namespace {

/// One row's world coordinates, planar: ``X[u] = ((r_x x[u] + r_y y) + r_z) z[u] + t`` per
/// axis (float32, in this order), for the AVX2 clone and the baseline alike.
GRASP_SIMD_CLONES void row_coordinates(int w, const float* __restrict x, const float* __restrict z,
                                       float rx, float ry, float rz, float t, float* __restrict out) {
  for (int u = 0; u < w; ++u) out[u] = ((rx * x[u] + ry) + rz) * z[u] + t;
}

}  // namespace

void depth_to_world_points(const DepthImageGeometry& g, const float* R, const float* t,
                           float* z, const std::uint8_t* invalid, float* points) {
  const int h = g.height, w = g.width;
  float r[9], tr[3];  // local copies: the stores into `points` cannot alias them
  for (int i = 0; i < 9; ++i) r[i] = R[i];
  for (int i = 0; i < 3; ++i) tr[i] = t[i];
  // a row's coordinates are computed planar (vectorised), then interleaved into the points
  std::vector<float> planes(3 * static_cast<std::size_t>(w));
  float* __restrict px = planes.data();
  float* __restrict py = px + w;
  float* __restrict pz = py + w;
  for (int v = 0; v < h; ++v) {
    const std::size_t base = static_cast<std::size_t>(v) * w;
    float* __restrict zrow = z + base;
    const std::uint8_t* __restrict inv = invalid + base;
    float* __restrict out = points + 3 * base;
    for (int u = 0; u < w; ++u) zrow[u] = inv[u] ? kNaN : zrow[u];
    // R[i][1] y is the same product for every pixel of the row
    row_coordinates(w, g.x, zrow, r[0], r[1] * g.y[v], r[2], tr[0], px);
    row_coordinates(w, g.x, zrow, r[3], r[4] * g.y[v], r[5], tr[1], py);
    row_coordinates(w, g.x, zrow, r[6], r[7] * g.y[v], r[8], tr[2], pz);
    for (int u = 0; u < w; ++u) {
      out[3 * u] = px[u];
      out[3 * u + 1] = py[u];
      out[3 * u + 2] = pz[u];
    }
  }
}

void metric_depth(int height, int width, const float* raw, float c_coef, float d_coef, float* out) {
  const double c = static_cast<double>(c_coef), d = static_cast<double>(d_coef);
  for (int v = 0; v < height; ++v) {
    const float* __restrict in = raw + static_cast<std::size_t>(height - 1 - v) * width;
    float* __restrict o = out + static_cast<std::size_t>(v) * width;
    for (int u = 0; u < width; ++u) o[u] = static_cast<float>(d / (static_cast<double>(in[u]) + c));
  }
}

void add_quadratic_depth_noise(std::size_t n, const float* z, float ref_range, float sigma_at_ref,
                               float* noise) {
  const float* __restrict zr = z;
  float* __restrict out = noise;
  for (std::size_t p = 0; p < n; ++p) {
    float sigma = zr[p] / ref_range;
    sigma = sigma * sigma;
    sigma = sigma * sigma_at_ref;
    const float scaled = out[p] * sigma;
    out[p] = scaled + zr[p];
  }
}

}  // namespace grasp_core
