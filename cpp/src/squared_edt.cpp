#include "grasp_core/squared_edt.hpp"

#include <algorithm>
#include <cstddef>

namespace grasp_core {

namespace {

/// Larger than any squared distance of a grid (coordinates below 2^20 per axis).
constexpr std::int64_t kFar = std::int64_t{1} << 62;

/// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// In place on the `n` values f[0], f[stride], ...: f'(x) = min_i (x - i)^2 + f(i) over the
/// finite f(i) (< kFar); kFar where none is. `s`, `t`: scratch of n values each.
void envelope_1d(std::int64_t* f, std::ptrdiff_t stride, int n, std::vector<std::int64_t>& g,
                 std::vector<int>& s, std::vector<std::int64_t>& t) {
  for (int i = 0; i < n; ++i) g[i] = f[i * stride];
  int q = -1;  // top of the stack of parabolas (their apexes s, starting points t)
  for (int u = 0; u < n; ++u) {
    if (g[u] >= kFar) continue;
    while (q >= 0) {  // drop the parabolas that u's hides from their start on
      const std::int64_t x = t[q];
      if ((x - s[q]) * (x - s[q]) + g[s[q]] <= (x - u) * (x - u) + g[u]) break;
      --q;
    }
    if (q < 0) {
      s[0] = u, t[0] = 0, q = 0;
      continue;
    }
    // first x at which u's parabola lies below s[q]'s: floor(sep) + 1
    const std::int64_t w = 1 + floor_div(std::int64_t{u} * u - std::int64_t{s[q]} * s[q] + g[u] - g[s[q]],
                                         2 * (std::int64_t{u} - s[q]));
    if (w < n) s[++q] = u, t[q] = w;
  }
  if (q < 0) {
    for (int x = 0; x < n; ++x) f[x * stride] = kFar;
    return;
  }
  for (int x = n - 1; x >= 0; --x) {
    const std::int64_t d = x - s[q];
    f[x * stride] = d * d + g[s[q]];
    if (x == t[q]) --q;
  }
}

}  // namespace

std::vector<std::int64_t> squared_distance_transform(const std::uint8_t* occupied, int nx, int ny,
                                                     int nz) {
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<std::int64_t> f(total);
  bool any = false;
  for (std::size_t i = 0; i < total; ++i) {
    f[i] = occupied[i] ? 0 : kFar;
    any = any || occupied[i];
  }
  if (!any) return std::vector<std::int64_t>(total, -1);
  const int longest = std::max(nx, std::max(ny, nz));
  std::vector<std::int64_t> g(longest), t(longest);
  std::vector<int> s(longest);
  const std::ptrdiff_t sx = static_cast<std::ptrdiff_t>(ny) * nz, sy = nz;
  for (int y = 0; y < ny; ++y)  // along x
    for (int z = 0; z < nz; ++z) envelope_1d(&f[y * sy + z], sx, nx, g, s, t);
  for (int x = 0; x < nx; ++x)  // along y
    for (int z = 0; z < nz; ++z) envelope_1d(&f[x * sx + z], sy, ny, g, s, t);
  for (int x = 0; x < nx; ++x)  // along z
    for (int y = 0; y < ny; ++y) envelope_1d(&f[x * sx + y * sy], 1, nz, g, s, t);
  return f;
}

}  // namespace grasp_core
