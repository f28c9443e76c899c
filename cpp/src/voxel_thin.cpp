#include "grasp_core/voxel_thin.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace grasp_core {

namespace {

/// Wrapping int64 arithmetic (numpy's): computed on uint64, reinterpreted.
std::int64_t wrap_mul(std::int64_t a, std::int64_t b) {
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b));
}
std::int64_t wrap_add(std::int64_t a, std::int64_t b) {
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b));
}

/// floor(q) as an integer: truncation corrected below zero (no libm call) where q fits.
inline std::int64_t floor_to_int(double q) {
  if (!(std::fabs(q) < 4.0e18)) return static_cast<std::int64_t>(std::floor(q));
  const auto t = static_cast<std::int64_t>(q);
  return t - (q < static_cast<double>(t) ? 1 : 0);
}

/// The (voxel, owner) key of every point and the exact number of keys (saturated at 2^100).
std::vector<std::int64_t> voxel_keys(std::size_t n, const double* points, const std::int64_t* owner,
                                     double voxel_m, long double* n_keys) {
  const std::unique_ptr<std::int64_t[]> cell(new std::int64_t[3 * n]);  // every entry written below
  std::array<std::int64_t, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<std::int64_t>::max());
  hi.fill(std::numeric_limits<std::int64_t>::min());
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) {
      const std::int64_t c = floor_to_int(points[3 * i + j] / voxel_m);
      cell[3 * i + j] = c;
      lo[j] = std::min(lo[j], c);
      hi[j] = std::max(hi[j], c);
    }
  std::int64_t own_lo = *std::min_element(owner, owner + n);
  std::int64_t own_hi = *std::max_element(owner, owner + n);
  std::array<std::int64_t, 3> dims{};
  for (int j = 0; j < 3; ++j) dims[j] = hi[j] - lo[j] + 1;
  const std::int64_t n_own = own_hi - own_lo + 1;
  *n_keys = static_cast<long double>(dims[0]) * dims[1] * dims[2] * n_own;
  std::vector<std::int64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t* c = &cell[3 * i];
    std::int64_t k = wrap_add(wrap_mul(c[0] - lo[0], dims[1]), c[1] - lo[1]);
    k = wrap_add(wrap_mul(k, dims[2]), c[2] - lo[2]);
    key[i] = wrap_add(wrap_mul(k, n_own), owner[i] - own_lo);
  }
  return key;
}

/// Stable LSD radix sort of `v` by its bits [lo_bit, hi_bit) (the bits below stay in their
/// input order among equal keys), at most 13 bits a pass.
void radix_sort(std::vector<std::uint64_t>& v, int lo_bit, int hi_bit) {
  const int bits = hi_bit - lo_bit;
  if (bits <= 0) return;
  const int passes = (bits + 12) / 13;
  const int digit = (bits + passes - 1) / passes;
  const std::uint64_t mask = (std::uint64_t{1} << digit) - 1;
  std::vector<std::size_t> count(std::size_t{1} << digit);
  std::vector<std::uint64_t> tmp(v.size());
  for (int shift = lo_bit; shift < hi_bit; shift += digit) {
    std::fill(count.begin(), count.end(), 0);
    for (std::uint64_t x : v) ++count[(x >> shift) & mask];
    std::size_t sum = 0;
    for (std::size_t& c : count) sum += std::exchange(c, sum);
    for (std::uint64_t x : v) tmp[count[(x >> shift) & mask]++] = x;
    v.swap(tmp);
  }
}

int bit_length(std::uint64_t x) {
  int b = 0;
  while (x) ++b, x >>= 1;
  return b;
}

/// The number of set bits of `x` (portable: the baseline x86-64 has no popcount instruction).
inline std::uint64_t bits_set(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ULL);
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return (x * 0x0101010101010101ULL) >> 56;
}

/// The position of the first point of each distinct key, in increasing key order, without a
/// sort: a bit per possible key (n_keys bits, at most 64 per point) marks those already met,
/// and once all are marked, a key's rank among them (the bits set below its own) is its place
/// in the output.
std::vector<std::int64_t> first_of_each_key(const std::vector<std::int64_t>& key, std::size_t n_keys) {
  std::vector<std::uint64_t> seen((n_keys + 63) / 64, 0);
  std::vector<std::size_t> first_at;  // positions of the first points, in the points' order
  for (std::size_t i = 0; i < key.size(); ++i) {
    const auto k = static_cast<std::uint64_t>(key[i]);
    std::uint64_t& word = seen[k >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (k & 63);
    if (word & bit) continue;
    word |= bit;
    first_at.push_back(i);
  }
  std::vector<std::uint64_t> below(seen.size());  // keys met in the words before
  std::uint64_t total = 0;
  for (std::size_t w = 0; w < seen.size(); ++w) below[w] = total, total += bits_set(seen[w]);
  std::vector<std::int64_t> first(first_at.size());
  for (std::size_t i : first_at) {
    const auto k = static_cast<std::uint64_t>(key[i]);
    const std::uint64_t lower = seen[k >> 6] & ((std::uint64_t{1} << (k & 63)) - 1);
    first[below[k >> 6] + bits_set(lower)] = static_cast<std::int64_t>(i);
  }
  return first;
}

}  // namespace

std::vector<std::int64_t> first_per_voxel(std::size_t n, const double* points,
                                          const std::int64_t* owner, double voxel_m) {
  std::vector<std::int64_t> first;
  if (n == 0) return first;
  long double n_keys = 0;
  const std::vector<std::int64_t> key = voxel_keys(n, points, owner, voxel_m, &n_keys);
  const int bits = std::max(1, bit_length(n - 1));
  if (n_keys >= std::ldexp(1.0L, 62 - bits)) {  // key and position do not pack into 62 bits
    std::vector<std::pair<std::int64_t, std::int64_t>> kp(n);
    for (std::size_t i = 0; i < n; ++i) kp[i] = {key[i], static_cast<std::int64_t>(i)};
    std::sort(kp.begin(), kp.end());
    for (std::size_t i = 0; i < n; ++i)
      if (i == 0 || kp[i].first != kp[i - 1].first) first.push_back(kp[i].second);
    return first;
  }
  if (n_keys <= 64.0L * static_cast<long double>(n))  // few possible keys: no sort
    return first_of_each_key(key, static_cast<std::size_t>(n_keys));
  std::vector<std::uint64_t> packed(n);
  for (std::size_t i = 0; i < n; ++i) packed[i] = (static_cast<std::uint64_t>(key[i]) << bits) | i;
  std::uint64_t top = 0;
  for (std::uint64_t x : packed) top = std::max(top, x);
  // the positions are already in order and the sort is stable: only the key's bits are sorted
  radix_sort(packed, bits, bit_length(top));
  const std::uint64_t mask = (std::uint64_t{1} << bits) - 1;
  for (std::size_t i = 0; i < packed.size(); ++i)
    if (i == 0 || (packed[i] >> bits) != (packed[i - 1] >> bits))
      first.push_back(static_cast<std::int64_t>(packed[i] & mask));
  return first;
}

namespace {

template <typename F>
ThinnedRows thin_rows(std::size_t n, const F* xyz, std::size_t row_stride, const std::int32_t* labels,
                      const RowOwners& owners, double voxel_m) {
  // the kept rows, written in place (room for all rows, left uninitialised: no per-row growth)
  const std::unique_ptr<double[]> points(new double[3 * n]);
  const std::unique_ptr<std::int64_t[]> owner(new std::int64_t[n]);
  std::size_t kept = 0;
  const std::size_t n_groups = owners.of_label.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t label = labels[i];
    std::int64_t who;
    if (label >= 0)
      who = static_cast<std::size_t>(label) < n_groups ? owners.of_label[label] : owners.untracked;
    else if (label == owners.environment_label && owners.environment_emitted)
      who = owners.environment;
    else
      continue;
    const F* p = xyz + i * row_stride;
    const double x = p[0], y = p[1], z = p[2];
    if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) continue;
    double* q = &points[3 * kept];
    q[0] = x, q[1] = y, q[2] = z;
    owner[kept++] = who;
  }
  const std::vector<std::int64_t> first = first_per_voxel(kept, points.get(), owner.get(), voxel_m);
  ThinnedRows out;
  out.points.resize(3 * first.size());
  out.owner.resize(first.size());
  for (std::size_t k = 0; k < first.size(); ++k) {
    const auto i = static_cast<std::size_t>(first[k]);
    std::copy(&points[3 * i], &points[3 * i] + 3, &out.points[3 * k]);
    out.owner[k] = owner[i];
  }
  return out;
}

}  // namespace

ThinnedRows thin_owned_rows(std::size_t n, const float* xyz, std::size_t row_stride,
                            const std::int32_t* labels, const RowOwners& owners, double voxel_m) {
  return thin_rows(n, xyz, row_stride, labels, owners, voxel_m);
}

ThinnedRows thin_owned_rows(std::size_t n, const double* xyz, std::size_t row_stride,
                            const std::int32_t* labels, const RowOwners& owners, double voxel_m) {
  return thin_rows(n, xyz, row_stride, labels, owners, voxel_m);
}

}  // namespace grasp_core
