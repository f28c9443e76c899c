// The tray's free-cell search (tray_spots.cpp): the cells near discs, and per cell the verdicts
// against brute force (every offset of every cell) on random trays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "grasp_core/tray_spots.hpp"

using grasp_core::Discs;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The largest value over `offsets` around cell (i, j): `outside` beyond the grid, `value`
/// inside it.
template <typename F>
double highest_at(const std::vector<std::int64_t>& offsets, std::int64_t i, std::int64_t j,
                  std::int64_t nu, std::int64_t nv, double outside, F value) {
  double m = -kInf;
  for (std::size_t k = 0; k + 1 < offsets.size(); k += 2) {
    const std::int64_t a = i + offsets[k], b = j + offsets[k + 1];
    m = std::max(m, (a < 0 || b < 0 || a >= nu || b >= nv) ? outside : value(a * nv + b));
  }
  return m;
}

}  // namespace

TEST(TraySpots, CellsNearADiscAreTheRingOfItsReach) {
  const double xy[2] = {0.0, 0.0}, r[1] = {0.008};
  // 1 cm cells, no padding: reach is half a cell's diagonal, so the 3 x 3 cells around (0, 0)
  const std::vector<std::int64_t> cells = grasp_core::cells_near(Discs{xy, r, 1}, 0.0, 0.01);
  ASSERT_EQ(cells.size(), 18u);
  for (std::size_t k = 0; k < cells.size(); k += 2) {
    EXPECT_LE(std::abs(cells[k]), 1);
    EXPECT_LE(std::abs(cells[k + 1]), 1);
  }
  EXPECT_TRUE(grasp_core::cells_near(Discs{xy, r, 0}, 0.0, 0.01).empty());
}

TEST(TraySpots, VerdictsEqualBruteForceOnRandomTrays) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const std::int64_t nu = 6 + rng() % 20, nv = 6 + rng() % 20;
    const std::size_t n = static_cast<std::size_t>(nu * nv);
    std::vector<double> contents(n, 0.0), heights(n);
    std::vector<std::uint8_t> inside(n);
    for (std::size_t k = 0; k < n; ++k) {
      if (u01(rng) < 0.04) contents[k] = 0.08 * u01(rng);
      heights[k] = std::max(contents[k], u01(rng) < 0.04 ? 0.05 : 0.0);
      inside[k] = u01(rng) > 0.04;
    }
    std::vector<double> oxy, orad, hxy, hrad, hlim;
    for (int k = 0; k < 1 + static_cast<int>(rng() % 5); ++k)
      oxy.insert(oxy.end(), {0.02 * (u01(rng) - 0.5), 0.02 * (u01(rng) - 0.5)}), orad.push_back(0.003 + 0.015 * u01(rng));
    for (int k = 0; k < static_cast<int>(rng() % 8); ++k)
      hxy.insert(hxy.end(), {0.04 * (u01(rng) - 0.5), 0.04 * (u01(rng) - 0.5)}), hrad.push_back(0.005 + 0.015 * u01(rng)),
          hlim.push_back(std::round(20 * u01(rng)) / 100);
    std::vector<std::int64_t> under;
    for (int k = 0; k < static_cast<int>(rng() % 10); ++k)
      under.insert(under.end(), {static_cast<std::int64_t>(rng() % 5) - 2, static_cast<std::int64_t>(rng() % 5) - 2});
    const double cell = trial % 2 ? 0.01 : 0.005, spacing = 0.004, tol = 0.008, rim = 0.06;
    grasp_core::SpotGrid g;
    g.nu = nu, g.nv = nv, g.contents = contents.data(), g.heights = heights.data(), g.inside = inside.data();
    g.rim_m = rim, g.cell_m = cell;
    grasp_core::SpotStamp s;
    s.object = Discs{oxy.data(), orad.data(), orad.size()};
    s.under = under.data(), s.n_under = under.size() / 2;
    s.hand = Discs{hxy.data(), hrad.data(), hrad.size()}, s.hand_limit = hlim.data(), s.spacing_m = spacing;
    std::vector<std::uint8_t> ok(n);
    std::vector<double> support(n);
    grasp_core::spot_cells(g, s, tol, ok.data(), support.data());

    const auto obj = grasp_core::cells_near(s.object, spacing, cell);
    std::vector<std::vector<std::int64_t>> hand_cells;
    for (std::size_t k = 0; k < hrad.size(); ++k)
      hand_cells.push_back(grasp_core::cells_near(Discs{hxy.data() + 2 * k, hrad.data() + k, 1}, spacing, cell));
    for (std::int64_t i = 0; i < nu; ++i)
      for (std::int64_t j = 0; j < nv; ++j) {
        const double around = std::max(0.0, highest_at(obj, i, j, nu, nv, kInf, [&](std::int64_t k) {
          return inside[k] ? contents[k] : kInf;
        }));
        const double below = std::max(0.0, highest_at(under, i, j, nu, nv, kInf, [&](std::int64_t k) {
          return contents[k];
        }));
        bool want = std::isfinite(around) && around <= below + tol;
        for (std::size_t k = 0; k < hand_cells.size(); ++k)
          want = want && highest_at(hand_cells[k], i, j, nu, nv, rim, [&](std::int64_t c) {
                   return heights[c];
                 }) <= hlim[k] + below;
        EXPECT_EQ(support[i * nv + j], below) << trial;
        EXPECT_EQ(static_cast<bool>(ok[i * nv + j]), want) << trial << " at " << i << ", " << j;
      }
  }
}
