// (ours) Organized segmentation of the candidates. See organized_segmentation.hpp.
#include "grasp_core/organized_segmentation.hpp"

#include "grasp_core/nested_segments.hpp"
#include "grasp_core/union_find.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace grasp_core {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Hue of a pixel [deg, 0..360), or -1 where it is not reliable (too dark or too grey).
/// Hue is unchanged by shading (scaling) and by adding white (ambient light, highlights), so
/// a shaded or lit part of one object keeps its hue; chromaticity would not.
float pixel_hue(const std::uint8_t* c, float min_value, float min_saturation) {
  const float r = c[0], g = c[1], b = c[2];
  const float mx = std::max({r, g, b}), mn = std::min({r, g, b});
  if (mx < min_value || mx <= 0.0f || (mx - mn) < min_saturation * mx) return -1.0f;
  const float d = mx - mn;
  float h;
  if (mx == r) h = (g - b) / d;
  else if (mx == g) h = 2.0f + (b - r) / d;
  else h = 4.0f + (r - g) / d;
  h *= 60.0f;
  return h < 0.0f ? h + 360.0f : h;
}

/// Edge-preserving box smoothing of the candidates' ranges (see the header). The window is read
/// from an image of the candidates' ranges (NaN elsewhere, which no test admits) without a
/// branch per pixel: a pixel left out adds 0 to the sum, which leaves a sum of non-negative
/// ranges unchanged, so every sum is the one of the pixels admitted, added in the same order.
void smooth_ranges(const int* cand_rows, std::size_t n_cand, int width, int height, int radius,
                   const SceneFilterParams& p, OrganizedWorkspace& ws) {
  const std::size_t n_pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (ws.range_image.size() != n_pixels) ws.range_image.assign(n_pixels, kNaN);
  float* image = ws.range_image.data();
  const float* r = ws.range.data();
  float* out = ws.smooth.data();
  for (std::size_t k = 0; k < n_cand; ++k) image[cand_rows[k]] = r[k];
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int u0 = cand_rows[k] % width, v0 = cand_rows[k] / width;
    const float rk = r[k];
    const float tol = static_cast<float>(3.0 * p.depth_noise_at(rk));
    const int u_lo = std::max(0, u0 - radius), u_hi = std::min(width - 1, u0 + radius);
    float sum = 0.0f;
    int cnt = 0;
    for (int v = std::max(0, v0 - radius); v <= std::min(height - 1, v0 + radius); ++v) {
      const float* row = image + static_cast<std::size_t>(v) * width;
      for (int u = u_lo; u <= u_hi; ++u) {
        const float x = row[u];
        const bool admitted = std::abs(x - rk) <= tol;  // NaN (no candidate) compares false
        sum += admitted ? x : 0.0f;
        cnt += admitted;
      }
    }
    out[k] = sum / static_cast<float>(cnt);  // cnt >= 1: the pixel itself
  }
  for (std::size_t k = 0; k < n_cand; ++k) image[cand_rows[k]] = kNaN;  // leave the image all NaN
}

/// Segments of fewer than segment_absorb_max_points points (slivers of a steep side face,
/// cut off by its large range steps) join the large segment they touch most in the image,
/// counting only neighbour pairs within cluster_eps in 3-D (the Euclidean rule of method.md §1.4,
/// so nothing is joined that Euclidean clustering would have kept apart).
void absorb_small_segments(const float* xyz, const int* cand_rows, std::size_t n_cand, int width,
                           int height, const SceneFilterParams& p, OrganizedWorkspace& ws) {
  const int small = p.segment_absorb_max_points;
  if (small <= 0) return;
  std::vector<int> size(n_cand, 0);
  for (std::size_t k = 0; k < n_cand; ++k) ++size[static_cast<std::size_t>(find_root(ws.parent, static_cast<int>(k)))];
  const float eps_sq = static_cast<float>(p.cluster_eps * p.cluster_eps);
  const int* pix = ws.pixel_to_candidate.data();
  std::vector<std::pair<int, int>> votes;  // (small root, large root) per touching pair
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int rk = find_root(ws.parent, static_cast<int>(k));
    if (size[static_cast<std::size_t>(rk)] >= small) continue;
    const int u0 = cand_rows[k] % width, v0 = cand_rows[k] / width;
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du) {
        const int u = u0 + du, v = v0 + dv;
        if ((du == 0 && dv == 0) || u < 0 || u >= width || v < 0 || v >= height) continue;
        const int j = pix[static_cast<std::size_t>(v) * width + u];
        if (j < 0) continue;
        const int rj = find_root(ws.parent, j);
        if (rj == rk || size[static_cast<std::size_t>(rj)] < small) continue;
        const float* a = xyz + 3 * k;
        const float* b = xyz + 3 * static_cast<std::size_t>(j);
        const float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        if (dx * dx + dy * dy + dz * dz <= eps_sq) votes.emplace_back(rk, rj);
      }
  }
  std::sort(votes.begin(), votes.end());
  for (std::size_t i = 0; i < votes.size();) {  // per small root: the most-voted large root
    std::size_t best = i, best_n = 0;
    std::size_t j = i;
    while (j < votes.size() && votes[j].first == votes[i].first) {
      std::size_t e = j;
      while (e < votes.size() && votes[e] == votes[j]) ++e;
      if (e - j > best_n) { best_n = e - j; best = j; }
      j = e;
    }
    ws.parent[static_cast<std::size_t>(votes[best].first)] = votes[best].second;
    i = j;
  }
}

}  // namespace

std::vector<int> organized_components(const float* cand_xyz, const int* cand_rows,
                                      std::size_t n_cand, std::size_t n_pixels, int width,
                                      const std::uint8_t* rgb, const Vec3& camera,
                                      const SceneFilterParams& params, OrganizedWorkspace& ws,
                                      const Plane* table) {
  if (width < 1 || n_pixels % static_cast<std::size_t>(width) != 0)
    throw std::invalid_argument("organized_components: the frame's rows must be width x height pixels");
  const int height = static_cast<int>(n_pixels / static_cast<std::size_t>(width));
  if (ws.pixel_to_candidate.size() != n_pixels) ws.pixel_to_candidate.assign(n_pixels, -1);
  ws.range.resize(n_cand);
  ws.smooth.resize(n_cand);
  ws.parent.resize(n_cand);
  int* pix = ws.pixel_to_candidate.data();
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int row = cand_rows[k];
    if (row < 0 || static_cast<std::size_t>(row) >= n_pixels) {
      for (std::size_t j = 0; j < k; ++j) pix[cand_rows[j]] = -1;
      throw std::invalid_argument("organized_components: a candidate row is outside the image");
    }
    pix[row] = static_cast<int>(k);
    const float* p = cand_xyz + 3 * k;
    ws.range[k] = static_cast<float>((Vec3(p[0], p[1], p[2]) - camera).norm());
    ws.parent[k] = static_cast<int>(k);
  }
  smooth_ranges(cand_rows, n_cand, width, height, params.segment_smooth_radius_px, params, ws);

  const bool use_colour = rgb != nullptr && params.segment_max_hue_diff_deg > 0.0;
  ws.hue.resize(use_colour ? n_cand : 0);
  for (std::size_t k = 0; use_colour && k < n_cand; ++k)
    ws.hue[k] = pixel_hue(rgb + 3 * static_cast<std::size_t>(cand_rows[k]),
                          static_cast<float>(params.segment_min_brightness),
                          static_cast<float>(params.segment_min_saturation));
  const float max_hue = static_cast<float>(params.segment_max_hue_diff_deg);
  const float* s = ws.smooth.data();
  const double ref = params.depth_noise_ref_range_m;
  // Forward half of the 8-neighbourhood: right, down-left, down, down-right.
  const int du[4] = {1, -1, 0, 1};
  const int dv[4] = {0, 1, 1, 1};
  for (std::size_t k = 0; k < n_cand; ++k) {
    const int row = cand_rows[k];
    const int u0 = row % width, v0 = row / width;
    const double scale = noise_growth(std::max(1.0, static_cast<double>(s[k]) / ref), params.depth_noise_exponent);
    const float step = static_cast<float>(params.segment_max_step_m * scale);
    for (int e = 0; e < 4; ++e) {
      const int u = u0 + du[e], v = v0 + dv[e];
      if (u < 0 || u >= width || v >= height) continue;
      const int nb = v * width + u;
      const int j = pix[nb];
      if (j < 0) continue;
      if (std::abs(s[j] - s[k]) > step) continue;
      if (use_colour) {
        const float ha = ws.hue[k], hb = ws.hue[static_cast<std::size_t>(j)];
        if (ha >= 0.0f && hb >= 0.0f) {
          const float dh = std::abs(ha - hb);
          if (std::min(dh, 360.0f - dh) > max_hue) continue;  // a colour boundary
        }
      }
      unite(ws.parent, static_cast<int>(k), j);
    }
  }
  absorb_small_segments(cand_xyz, cand_rows, n_cand, width, height, params, ws);
  if (table != nullptr)
    join_nested_segments(cand_xyz, cand_rows, n_cand, width, height, *table, params, pix, ws.parent, ws.nested);
  std::vector<int> comp(n_cand);
  for (std::size_t k = 0; k < n_cand; ++k) comp[k] = find_root(ws.parent, static_cast<int>(k));
  for (std::size_t k = 0; k < n_cand; ++k) pix[cand_rows[k]] = -1;  // leave the map all -1
  return comp;
}

}  // namespace grasp_core
