// The sensor noise's normal draws: a seeded stream (same seed, same draws; a shorter fill is a
// prefix of a longer one) with the standard normal's moments and tails.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grasp_core/normal_draws.hpp"

using grasp_core::fill_standard_normal;

TEST(NormalDraws, SameSeedSameDrawsAndShorterFillsArePrefixes) {
  std::vector<float> a(1001), b(1001), c(1000);
  fill_standard_normal(42, a.size(), a.data());
  fill_standard_normal(42, b.size(), b.data());
  fill_standard_normal(42, c.size(), c.data());
  EXPECT_EQ(a, b);
  for (std::size_t i = 0; i < c.size(); ++i) ASSERT_EQ(a[i], c[i]) << i;
  fill_standard_normal(43, b.size(), b.data());
  int same = 0;
  for (std::size_t i = 0; i < a.size(); ++i) same += a[i] == b[i];
  EXPECT_LT(same, 3);
}

TEST(NormalDraws, MomentsAndTailsOfTheStandardNormal) {
  const std::size_t n = 2000000;
  std::vector<float> x(n);
  fill_standard_normal(7, n, x.data());
  double s = 0.0, s2 = 0.0, s4 = 0.0;
  std::size_t beyond[4] = {0, 0, 0, 0};
  const double edges[4] = {1.0, 2.0, 3.0, 3.5};
  for (float v : x) {
    ASSERT_TRUE(std::isfinite(v));
    const double d = v;
    s += d;
    s2 += d * d;
    s4 += d * d * d * d;
    for (int k = 0; k < 4; ++k) beyond[k] += std::abs(d) > edges[k];
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_LT(std::abs(mean), 5.0 / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(var, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(s4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));
  const double tail[4] = {0.3173105, 0.0455003, 0.0026998, 0.000465};
  for (int k = 0; k < 4; ++k) {
    const double share = static_cast<double>(beyond[k]) / n;
    EXPECT_NEAR(share, tail[k], 5.0 * std::sqrt(tail[k] * (1.0 - tail[k]) / n)) << edges[k];
  }
}

TEST(NormalDraws, EmptyAndSingleFills) {
  float one = 0.0f;
  fill_standard_normal(1, 0, nullptr);
  fill_standard_normal(1, 1, &one);
  EXPECT_TRUE(std::isfinite(one));
}
