// Voxel thinning (voxel_thin.cpp): the first point of each (voxel, owner) pair, pairs in key
// order, from the paths of few possible keys (a bit per key), of many (every point sorted) and
// of keys too large to pack with the position (a comparison sort), checked against a plain
// std::map reference on random clouds.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "grasp_core/voxel_thin.hpp"

using grasp_core::first_per_voxel;

namespace {

/// The reference: key of every point as the header defines it, the smallest index per key.
std::vector<std::int64_t> reference(const std::vector<double>& p, const std::vector<std::int64_t>& own,
                                    double voxel) {
  const std::size_t n = own.size();
  std::vector<long long> lo(3, 1LL << 62), hi(3, -(1LL << 62));
  for (std::size_t i = 0; i < 3 * n; ++i) {
    const auto c = static_cast<long long>(std::floor(p[i] / voxel));
    lo[i % 3] = std::min(lo[i % 3], c), hi[i % 3] = std::max(hi[i % 3], c);
  }
  long long olo = own[0], ohi = own[0];
  for (auto o : own) olo = std::min<long long>(olo, o), ohi = std::max<long long>(ohi, o);
  std::map<long long, std::int64_t> first;
  for (std::size_t i = 0; i < n; ++i) {
    long long k = 0;
    for (int j = 0; j < 3; ++j)
      k = k * (j ? hi[j] - lo[j] + 1 : 1) + static_cast<long long>(std::floor(p[3 * i + j] / voxel)) - lo[j];
    k = k * (ohi - olo + 1) + own[i] - olo;
    first.emplace(k, static_cast<std::int64_t>(i));  // keeps the first index of each key
  }
  std::vector<std::int64_t> out;
  for (const auto& kv : first) out.push_back(kv.second);
  return out;
}

void random_cloud(unsigned seed, std::size_t n, std::vector<double>* p, std::vector<std::int64_t>* own) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::uniform_int_distribution<int> o(-2, 4);
  p->resize(3 * n);
  own->resize(n);
  for (auto& v : *p) v = u(rng);
  for (auto& v : *own) v = o(rng);
}

}  // namespace

TEST(VoxelThin, FirstPointOfEachVoxelAndOwnerInKeyOrder) {
  const std::vector<double> p = {0.0, 0, 0, 0.001, 0, 0, 0.001, 0, 0, 0.01, 0, 0, -0.002, 0, 0};
  const std::vector<std::int64_t> own = {1, 1, 2, 1, 1};
  // voxels along x at 3 mm: -1 (point 4), 0 (points 0, 1, 2), 3 (point 3)
  EXPECT_EQ(first_per_voxel(own.size(), p.data(), own.data(), 0.003),
            (std::vector<std::int64_t>{4, 0, 2, 3}));
  EXPECT_TRUE(first_per_voxel(0, nullptr, nullptr, 0.003).empty());
}

TEST(VoxelThin, MatchesTheReferenceOnRandomClouds) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    std::vector<double> p;
    std::vector<std::int64_t> own;
    random_cloud(seed, 20000, &p, &own);
    // 0.02, 0.2: a bit per possible key; 0.003, 2e-5: every point sorted; 2e-6: keys too large
    // to pack with the index
    for (double voxel : {0.003, 0.02, 0.2, 2e-5, 2e-6}) {
      const auto got = first_per_voxel(own.size(), p.data(), own.data(), voxel);
      EXPECT_EQ(got, reference(p, own, voxel)) << "seed " << seed << " voxel " << voxel;
      if (voxel >= 0.02) {
        EXPECT_LT(got.size(), own.size());
      }
    }
  }
}
