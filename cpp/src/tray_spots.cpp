#include "grasp_core/tray_spots.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <utility>

namespace grasp_core {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// numpy's maximum: NaN when either is NaN.
inline double nmax(double a, double b) { return (a >= b || std::isnan(a)) ? a : b; }

using Offsets = std::vector<std::array<std::int64_t, 2>>;

/// A grid array padded by `pad` cells on every side (row-major).
struct Padded {
  std::int64_t rows = 0, cols = 0;
  std::vector<double> v;
};

/// `a` (nu x nv) padded with `fill`; where `mask` is given, the cells where it is 0 hold `fill` too.
Padded padded(const double* a, const std::uint8_t* mask, std::int64_t nu, std::int64_t nv,
              std::int64_t pad, double fill) {
  Padded p;
  p.rows = nu + 2 * pad;
  p.cols = nv + 2 * pad;
  p.v.assign(static_cast<std::size_t>(p.rows * p.cols), fill);
  for (std::int64_t i = 0; i < nu; ++i)
    for (std::int64_t j = 0; j < nv; ++j) {
      const std::int64_t k = i * nv + j;
      if (mask == nullptr || mask[k]) p.v[static_cast<std::size_t>((i + pad) * p.cols + j + pad)] = a[k];
    }
  return p;
}

/// Maxima over runs of consecutive columns: level l holds, at column c, the largest of columns
/// c .. c + 2^l - 1 (row-major, `cols - 2^l + 1` columns).
class RunMaxima {
 public:
  explicit RunMaxima(const Padded& a) : rows_(a.rows), cols_(a.cols) { levels_.push_back(a.v); }

  /// The level of the longest power-of-two run within `length` (its row width in `*width`).
  const std::vector<double>& level(std::int64_t length, std::int64_t* width, std::int64_t* run) {
    int lv = 0;
    while ((std::int64_t{2} << lv) <= length) ++lv;
    while (static_cast<int>(levels_.size()) <= lv) {
      const std::vector<double>& prev = levels_.back();
      const std::int64_t half = std::int64_t{1} << (levels_.size() - 1);
      const std::int64_t w_prev = cols_ - half + 1, w = w_prev - half;
      std::vector<double> next(static_cast<std::size_t>(rows_ * w));
      for (std::int64_t r = 0; r < rows_; ++r)
        for (std::int64_t c = 0; c < w; ++c)
          next[static_cast<std::size_t>(r * w + c)] =
              nmax(prev[static_cast<std::size_t>(r * w_prev + c)], prev[static_cast<std::size_t>(r * w_prev + c + half)]);
      levels_.push_back(std::move(next));
    }
    *run = std::int64_t{1} << lv;
    *width = cols_ - *run + 1;
    return levels_[static_cast<std::size_t>(lv)];
  }

 private:
  std::int64_t rows_, cols_;
  std::vector<std::vector<double>> levels_;
};

/// `offsets` as runs (du, first dv, last dv) of consecutive dv, sorted.
std::vector<std::array<std::int64_t, 3>> row_runs(Offsets offsets) {
  std::sort(offsets.begin(), offsets.end());
  offsets.erase(std::unique(offsets.begin(), offsets.end()), offsets.end());
  std::vector<std::array<std::int64_t, 3>> runs;
  for (const auto& o : offsets) {
    if (!runs.empty() && runs.back()[0] == o[0] && runs.back()[2] + 1 == o[1])
      runs.back()[2] = o[1];
    else
      runs.push_back({o[0], o[1], o[1]});
  }
  return runs;
}

/// Per cell (nu x nv), the largest of `a` (padded by `pad`) over the cells at `offsets` from it
/// (-inf without offsets).
std::vector<double> highest(RunMaxima& table, const Offsets& offsets, std::int64_t pad,
                            std::int64_t nu, std::int64_t nv) {
  std::vector<double> out(static_cast<std::size_t>(nu * nv), -kInf);
  for (const auto& run : row_runs(offsets)) {
    const std::int64_t du = run[0], first = run[1], last = run[2], length = last - first + 1;
    std::int64_t width = 0, w = 0;
    const std::vector<double>& lv = table.level(length, &width, &w);
    for (std::int64_t i = 0; i < nu; ++i) {
      const double* row = lv.data() + (pad + du + i) * width;
      double* o = out.data() + i * nv;
      for (std::int64_t j = 0; j < nv; ++j) o[j] = nmax(o[j], row[pad + first + j]);
      if (w < length)
        for (std::int64_t j = 0; j < nv; ++j) o[j] = nmax(o[j], row[pad + last - w + 1 + j]);
    }
  }
  return out;
}

Offsets as_offsets(const std::vector<std::int64_t>& flat) {
  Offsets out(flat.size() / 2);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = {flat[2 * k], flat[2 * k + 1]};
  return out;
}

/// The hand's cells grouped by the lowest limit of the spheres that reach each (the limits in
/// increasing order).
std::map<double, Offsets> hand_cells_by_limit(const SpotStamp& stamp, double cell_m) {
  std::map<std::array<std::int64_t, 2>, double> lowest;
  for (std::size_t k = 0; k < stamp.hand.n; ++k) {
    const Discs one{stamp.hand.xy + 2 * k, stamp.hand.r + k, 1};
    const Offsets cells = as_offsets(cells_near(one, stamp.spacing_m, cell_m));
    for (const auto& c : cells) {
      auto it = lowest.find(c);
      if (it == lowest.end())
        lowest.emplace(c, stamp.hand_limit[k]);
      else
        it->second = std::min(it->second, stamp.hand_limit[k]);
    }
  }
  std::map<double, Offsets> groups;
  for (const auto& [cell, limit] : lowest) groups[limit].push_back(cell);
  return groups;
}

std::int64_t reach_of(const Offsets& offsets) {
  std::int64_t r = 0;
  for (const auto& o : offsets) r = std::max({r, std::abs(o[0]), std::abs(o[1])});
  return r;
}

}  // namespace

std::vector<std::int64_t> cells_near(const Discs& discs, double pad_m, double cell_m) {
  std::vector<std::int64_t> out;
  if (discs.n == 0) return out;
  const double reach = pad_m + 0.5 * std::sqrt(2.0) * cell_m;
  double lo_m[2] = {kInf, kInf}, hi_m[2] = {-kInf, -kInf};
  for (std::size_t k = 0; k < discs.n; ++k)
    for (int a = 0; a < 2; ++a) {
      lo_m[a] = std::min(lo_m[a], discs.xy[2 * k + a] - discs.r[k]);
      hi_m[a] = std::max(hi_m[a], discs.xy[2 * k + a] + discs.r[k]);
    }
  std::int64_t lo[2], hi[2];
  for (int a = 0; a < 2; ++a) {
    lo[a] = static_cast<std::int64_t>(std::floor(lo_m[a] / cell_m - 1 - reach / cell_m));
    hi[a] = static_cast<std::int64_t>(std::ceil(hi_m[a] / cell_m + 1 + reach / cell_m));
  }
  for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
      const double x = static_cast<double>(i) * cell_m, y = static_cast<double>(j) * cell_m;
      for (std::size_t k = 0; k < discs.n; ++k) {
        const double dx = x - discs.xy[2 * k], dy = y - discs.xy[2 * k + 1];
        if (std::sqrt(dx * dx + dy * dy) - discs.r[k] <= reach) {
          out.push_back(i);
          out.push_back(j);
          break;
        }
      }
    }
  return out;
}

void spot_cells(const SpotGrid& grid, const SpotStamp& stamp, double tolerance_m, std::uint8_t* ok,
                double* support) {
  const std::int64_t nu = grid.nu, nv = grid.nv;
  const Offsets obj = as_offsets(cells_near(stamp.object, stamp.spacing_m, grid.cell_m));
  Offsets under(stamp.n_under);
  for (std::size_t k = 0; k < stamp.n_under; ++k) under[k] = {stamp.under[2 * k], stamp.under[2 * k + 1]};
  const std::map<double, Offsets> hand = hand_cells_by_limit(stamp, grid.cell_m);
  std::int64_t pad = std::max(reach_of(obj), reach_of(under));
  for (const auto& group : hand) pad = std::max(pad, reach_of(group.second));
  // a cell outside the walls under the object counts as infinitely high: never finite
  RunMaxima inside_contents(padded(grid.contents, grid.inside, nu, nv, pad, kInf));
  RunMaxima contents(padded(grid.contents, nullptr, nu, nv, pad, kInf));
  RunMaxima heights(padded(grid.heights, nullptr, nu, nv, pad, grid.rim_m));
  const std::vector<double> around = highest(inside_contents, obj, pad, nu, nv);
  const std::vector<double> below = highest(contents, under, pad, nu, nv);
  const std::size_t n = static_cast<std::size_t>(nu * nv);
  for (std::size_t k = 0; k < n; ++k) {
    const double a = nmax(around[k], 0.0);
    support[k] = nmax(below[k], 0.0);
    ok[k] = std::isfinite(a) && a <= support[k] + tolerance_m;
  }
  for (const auto& [limit, cells] : hand) {
    const std::vector<double> top = highest(heights, cells, pad, nu, nv);
    for (std::size_t k = 0; k < n; ++k) ok[k] = ok[k] && top[k] <= limit + support[k];
  }
}

}  // namespace grasp_core
