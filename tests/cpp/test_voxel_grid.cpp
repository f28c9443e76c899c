// The occupancy grid's voxelisation (voxel_grid.cpp) against a direct formulation on random
// clouds with rows outside the box, on its faces, NaN and infinite coordinates.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "grasp_core/voxel_grid.hpp"

using grasp_core::mark_occupied;
using grasp_core::voxelize_rows;

namespace {

std::vector<double> random_cloud(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<double> p(3 * n);
  for (auto& v : p) v = u(rng);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  p[0] = nan, p[4] = inf, p[8] = -inf;  // rows 0, 1, 2 are not finite
  p[9] = -0.5, p[10] = 0.5, p[11] = 0.0;  // row 3 on two faces of the box
  return p;
}

}  // namespace

TEST(VoxelGrid, KeepsTheFiniteRowsInsideTheBoxAndTheirFloorIndices) {
  std::mt19937 rng(3);
  const std::array<double, 3> lo{-0.5, -0.4, -0.45}, hi{0.45, 0.5, 0.5};
  for (int trial = 0; trial < 10; ++trial) {
    const std::vector<double> p = random_cloud(rng, 500);
    const double voxel = 0.01 + 0.005 * trial;
    const auto rows = voxelize_rows(p.data(), 500, lo, hi, voxel, 3);
    std::vector<double> kept;
    std::array<std::int64_t, 3> mn{1 << 30, 1 << 30, 1 << 30}, mx{-(1 << 30), -(1 << 30), -(1 << 30)};
    std::set<std::tuple<std::int64_t, std::int64_t, std::int64_t>> voxels;
    for (std::size_t i = 0; i < 500; ++i) {
      bool in = true;
      for (int j = 0; j < 3; ++j) in = in && std::isfinite(p[3 * i + j]) && p[3 * i + j] >= lo[j] && p[3 * i + j] <= hi[j];
      if (!in) continue;
      std::array<std::int64_t, 3> c{};
      for (int j = 0; j < 3; ++j) {
        kept.push_back(p[3 * i + j]);
        c[j] = static_cast<std::int64_t>(std::floor((p[3 * i + j] - lo[j]) / voxel));
        mn[j] = std::min(mn[j], c[j]), mx[j] = std::max(mx[j], c[j]);
      }
      voxels.insert({c[0], c[1], c[2]});
    }
    ASSERT_EQ(rows.kept, kept);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(rows.first_index[j], mn[j] - 3);
      EXPECT_EQ(rows.shape[j], mx[j] - mn[j] + 7);
    }
    std::vector<std::uint8_t> grid(static_cast<std::size_t>(rows.shape[0] * rows.shape[1] * rows.shape[2]), 0);
    mark_occupied(rows, grid.data());
    std::size_t marked = 0;
    for (std::int64_t x = 0; x < rows.shape[0]; ++x)
      for (std::int64_t y = 0; y < rows.shape[1]; ++y)
        for (std::int64_t z = 0; z < rows.shape[2]; ++z) {
          const bool on = grid[(x * rows.shape[1] + y) * rows.shape[2] + z] != 0;
          marked += on;
          const auto key = std::make_tuple(x + rows.first_index[0], y + rows.first_index[1], z + rows.first_index[2]);
          ASSERT_EQ(on, voxels.count(key) == 1);
        }
    EXPECT_EQ(marked, voxels.size());
  }
}

TEST(VoxelGrid, NoRowInsideGivesAnEmptyResult) {
  const std::vector<double> p{2.0, 2.0, 2.0, std::nan(""), 0.0, 0.0};
  const auto rows = voxelize_rows(p.data(), 2, {-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, 0.01, 2);
  EXPECT_TRUE(rows.kept.empty());
  EXPECT_EQ(rows.shape, (std::array<std::int64_t, 3>{0, 0, 0}));
}
