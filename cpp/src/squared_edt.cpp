#include "grasp_core/squared_edt.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace grasp_core {

namespace {

/// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// floor(a / b) for b > 0 through a double division, exact where |a| < 2^32 and b < 2^17 (the
/// 32-bit grids): an integer quotient is exact, and a non-integer one lies at least 1/b from the
/// integers while the division's rounding moves it by at most |a / b| 2^-53 < 2^-21 < 1/b.
/// (A 64-bit integer division costs several times more; one is made per parabola.)
std::int64_t floor_div_small(std::int64_t a, std::int64_t b) {
  const double q = static_cast<double>(a) / static_cast<double>(b);
  const auto t = static_cast<std::int64_t>(q);  // truncation, corrected below zero (no libm call)
  return t - (q < static_cast<double>(t) ? 1 : 0);
}

/// Scratch of one line: its input values and the stack of parabolas (apexes s, starts t).
struct LineScratch {
  explicit LineScratch(int n) : g(n), s(n), t(n) {}
  std::vector<std::int64_t> g;
  std::vector<int> s;
  std::vector<std::int64_t> t;
};

/// out[x * stride] = min_i (x - i)^2 + in[i] over the finite in[i] (< far), for the `n`
/// values in[0..n) (contiguous); `far` where none is. The lower envelope of parabolas with
/// integer separators: exact.
template <typename T>
void envelope_line(const T* in, T* out, std::ptrdiff_t stride, int n, T far, LineScratch& w) {
  std::int64_t* g = w.g.data();
  int* s = w.s.data();
  std::int64_t* t = w.t.data();
  int q = -1;
  for (int u = 0; u < n; ++u) {
    if (in[u] >= far) continue;
    g[u] = in[u];
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
    const std::int64_t num = std::int64_t{u} * u - std::int64_t{s[q]} * s[q] + g[u] - g[s[q]];
    const std::int64_t den = 2 * (std::int64_t{u} - s[q]);
    const std::int64_t sep = sizeof(T) == 4 ? floor_div_small(num, den) : floor_div(num, den);
    if (sep + 1 < n) s[++q] = u, t[q] = sep + 1;
  }
  if (q < 0) {
    for (int x = 0; x < n; ++x) out[x * stride] = far;
    return;
  }
  for (int x = n - 1; x >= 0; --x) {
    const std::int64_t d = x - s[q];
    out[x * stride] = static_cast<T>(d * d + g[s[q]]);
    if (x == t[q]) --q;
  }
}

/// Along z (contiguous lines of a binary grid): the squared distance to the nearest occupied
/// voxel of the line (two sweeps), `far` on a line without one.
template <typename T>
void binary_pass_z(const std::uint8_t* occupied, T* f, std::size_t n_lines, int nz, T far) {
  for (std::size_t line = 0; line < n_lines; ++line) {
    const std::uint8_t* o = occupied + line * nz;
    T* out = f + line * nz;
    int last = -1;  // the latest occupied voxel seen from the left
    for (int z = 0; z < nz; ++z) {
      if (o[z]) last = z;
      out[z] = last < 0 ? far : static_cast<T>(std::int64_t{z - last} * (z - last));
    }
    if (last < 0) continue;
    int next = -1;  // the nearest occupied voxel on the right
    for (int z = nz - 1; z >= 0; --z) {
      if (o[z]) next = z;
      if (next >= 0) out[z] = std::min(out[z], static_cast<T>(std::int64_t{next - z} * (next - z)));
    }
  }
}

/// The exact transform in the value type T (wide enough for the grid's squared diagonal):
/// z first (binary, contiguous), then y within each x slab, then x through a transposed
/// y slab (contiguous lines: the strided axis costs cache misses otherwise).
template <typename T>
std::vector<T> transform(const std::uint8_t* occupied, int nx, int ny, int nz, T far) {
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<T> f(total);
  binary_pass_z(occupied, f.data(), static_cast<std::size_t>(nx) * ny, nz, far);
  LineScratch w(std::max(nx, std::max(ny, nz)));
  std::vector<T> line(std::max(nx, ny));
  const std::ptrdiff_t sx = static_cast<std::ptrdiff_t>(ny) * nz, sy = nz;
  for (int x = 0; x < nx; ++x)  // along y
    for (int z = 0; z < nz; ++z) {
      T* base = &f[x * sx + z];
      for (int y = 0; y < ny; ++y) line[y] = base[y * sy];
      envelope_line(line.data(), base, sy, ny, far, w);
    }
  std::vector<T> slab(static_cast<std::size_t>(nx) * nz), done(slab.size());
  for (int y = 0; y < ny; ++y) {  // along x
    for (int x = 0; x < nx; ++x) {
      const T* row = &f[x * sx + y * sy];
      for (int z = 0; z < nz; ++z) slab[static_cast<std::size_t>(z) * nx + x] = row[z];
    }
    for (int z = 0; z < nz; ++z)
      envelope_line(&slab[static_cast<std::size_t>(z) * nx], &done[static_cast<std::size_t>(z) * nx], 1, nx,
                    far, w);
    for (int x = 0; x < nx; ++x) {
      T* row = &f[x * sx + y * sy];
      for (int z = 0; z < nz; ++z) row[z] = done[static_cast<std::size_t>(z) * nx + x];
    }
  }
  return f;
}

bool any_occupied(const std::uint8_t* occupied, std::size_t total) {
  return std::any_of(occupied, occupied + total, [](std::uint8_t v) { return v != 0; });
}

/// Whether the squared diagonal of the grid fits the 32-bit path (with room for `far`; then
/// every separator's numerator is below 2^32 and its denominator below 2^17).
bool fits_int32(int nx, int ny, int nz) {
  const std::int64_t d = std::int64_t{nx} * nx + std::int64_t{ny} * ny + std::int64_t{nz} * nz;
  return d < (std::int64_t{1} << 30);
}

}  // namespace

std::vector<std::int64_t> squared_distance_transform(const std::uint8_t* occupied, int nx, int ny,
                                                     int nz) {
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  if (!any_occupied(occupied, total)) return std::vector<std::int64_t>(total, -1);
  if (fits_int32(nx, ny, nz)) {
    const std::vector<std::int32_t> f = transform<std::int32_t>(occupied, nx, ny, nz, std::int32_t{1} << 30);
    return std::vector<std::int64_t>(f.begin(), f.end());
  }
  return transform<std::int64_t>(occupied, nx, ny, nz, std::int64_t{1} << 62);
}

void distance_field(const std::uint8_t* occupied, int nx, int ny, int nz, double voxel_m, float* out) {
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  if (!any_occupied(occupied, total)) {
    std::fill(out, out + total, std::numeric_limits<float>::infinity());
    return;
  }
  const auto value = [voxel_m](std::int64_t k) { return static_cast<float>(std::sqrt(static_cast<double>(k)) * voxel_m); };
  if (!fits_int32(nx, ny, nz)) {
    const std::vector<std::int64_t> sq = transform<std::int64_t>(occupied, nx, ny, nz, std::int64_t{1} << 62);
    for (std::size_t i = 0; i < total; ++i) out[i] = value(sq[i]);
    return;
  }
  const std::vector<std::int32_t> sq = transform<std::int32_t>(occupied, nx, ny, nz, std::int32_t{1} << 30);
  const std::int32_t top = *std::max_element(sq.begin(), sq.end());
  std::vector<float> table(static_cast<std::size_t>(top) + 1);
  for (std::int32_t k = 0; k <= top; ++k) table[k] = value(k);
  for (std::size_t i = 0; i < total; ++i) out[i] = table[sq[i]];
}

}  // namespace grasp_core
