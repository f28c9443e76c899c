// The exact squared distance transform (squared_edt.cpp) against brute force on random grids,
// including lines without an occupied voxel and single-voxel sides.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "grasp_core/squared_edt.hpp"

using grasp_core::squared_distance_transform;

namespace {

std::vector<std::int64_t> brute_force(const std::vector<std::uint8_t>& occ, int nx, int ny, int nz) {
  std::vector<std::int64_t> out(occ.size(), std::numeric_limits<std::int64_t>::max());
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z)
        for (int a = 0; a < nx; ++a)
          for (int b = 0; b < ny; ++b)
            for (int c = 0; c < nz; ++c)
              if (occ[(a * ny + b) * nz + c]) {
                const std::int64_t d = std::int64_t{x - a} * (x - a) + std::int64_t{y - b} * (y - b) +
                                       std::int64_t{z - c} * (z - c);
                auto& o = out[(x * ny + y) * nz + z];
                o = std::min(o, d);
              }
  return out;
}

}  // namespace

TEST(SquaredEdt, EqualsBruteForceOnRandomGrids) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const int nx = 1 + rng() % 9, ny = 1 + rng() % 9, nz = 1 + rng() % 9;
    const double fill = std::vector<double>{0.02, 0.1, 0.5, 0.9}[trial % 4];
    std::vector<std::uint8_t> occ(static_cast<std::size_t>(nx) * ny * nz);
    for (auto& v : occ) v = std::uniform_real_distribution<double>(0, 1)(rng) < fill;
    occ[rng() % occ.size()] = 1;
    EXPECT_EQ(squared_distance_transform(occ.data(), nx, ny, nz), brute_force(occ, nx, ny, nz))
        << nx << " x " << ny << " x " << nz;
  }
}

TEST(SquaredEdt, AnEmptyGridIsMinusOneEverywhere) {
  std::vector<std::uint8_t> occ(24, 0);
  EXPECT_EQ(squared_distance_transform(occ.data(), 2, 3, 4), std::vector<std::int64_t>(24, -1));
}
