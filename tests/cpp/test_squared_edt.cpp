// The exact squared distance transform (squared_edt.cpp) against brute force on random grids,
// including lines without an occupied voxel and single-voxel sides.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>
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

TEST(SquaredEdt, ALongLineTakesTheWidePathAndStaysExact) {
  // 1 x 2 x 33000: the squared diagonal passes 2^30, so the 64-bit values are used
  const int nz = 33000;
  std::vector<std::uint8_t> occ(2 * nz, 0);
  occ[5] = occ[nz + 20000] = occ[32999] = 1;
  const std::vector<std::int64_t> sq = squared_distance_transform(occ.data(), 1, 2, nz);
  for (int y = 0; y < 2; ++y)
    for (int z = 0; z < nz; z += 97) {
      std::int64_t best = std::numeric_limits<std::int64_t>::max();
      for (const auto& [b, c] : {std::pair{0, 5}, std::pair{1, 20000}, std::pair{0, 32999}})
        best = std::min(best, std::int64_t{y - b} * (y - b) + std::int64_t{z - c} * (z - c));
      ASSERT_EQ(sq[static_cast<std::size_t>(y) * nz + z], best) << y << " " << z;
    }
}

TEST(SquaredEdt, DistanceFieldIsTheRootOfEachSquaredDistanceTimesTheVoxel) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const int nx = 1 + rng() % 12, ny = 1 + rng() % 12, nz = 1 + rng() % 12;
    std::vector<std::uint8_t> occ(static_cast<std::size_t>(nx) * ny * nz);
    for (auto& v : occ) v = rng() % 10 == 0;
    occ[rng() % occ.size()] = 1;
    const double voxel = 0.0075 + 0.001 * trial;
    std::vector<float> field(occ.size());
    grasp_core::distance_field(occ.data(), nx, ny, nz, voxel, field.data());
    const std::vector<std::int64_t> sq = squared_distance_transform(occ.data(), nx, ny, nz);
    for (std::size_t i = 0; i < occ.size(); ++i)
      ASSERT_EQ(field[i], static_cast<float>(std::sqrt(static_cast<double>(sq[i])) * voxel)) << i;
  }
  std::vector<std::uint8_t> empty(8, 0);
  std::vector<float> field(8, 0.0f);
  grasp_core::distance_field(empty.data(), 2, 2, 2, 0.01, field.data());
  for (float v : field) EXPECT_TRUE(std::isinf(v) && v > 0);
}
