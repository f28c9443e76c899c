// A segment nested in another one across a sloped surface joins it
// (grasp_core::join_nested_segments through organized_components): a bottle's cap and shoulder
// seen from above become one segment; a box on a larger box stays two.
#include <gtest/gtest.h>

#include "grasp_core/organized_segmentation.hpp"

#include <cmath>
#include <set>
#include <vector>

using namespace grasp_core;

namespace {

constexpr int kSize = 60;                 // px; 1 px = 1 mm at the table
constexpr float kTableDepth_m = 0.5f;     // the camera at the origin looks along +z at the table
const Plane kTable{Vec3(0, 0, -1), 0.5};  // height = 0.5 - z

/// Segment count of a top view whose height [m] at pixel (u, v) is height(u, v) (<= 0: table).
template <typename F>
std::size_t segments(F height, const Plane* table, const SceneFilterParams& p = SceneFilterParams()) {
  std::vector<float> xyz;
  std::vector<int> rows;
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) {
      const float h = height(u, v);
      if (h <= 0.02f) continue;  // the table and the band: no candidate
      xyz.insert(xyz.end(), {u * 0.001f, v * 0.001f, kTableDepth_m - h});
      rows.push_back(v * kSize + u);
    }
  OrganizedWorkspace ws;
  const auto comp = organized_components(xyz.data(), rows.data(), rows.size(), kSize * kSize, kSize,
                                         nullptr, Vec3::Zero(), p, ws, table);
  for (int pix : ws.pixel_to_candidate) EXPECT_EQ(pix, -1);  // the map is left clean
  return std::set<int>(comp.begin(), comp.end()).size();
}

float radius(int u, int v) { return std::hypot(u - 30.0f, v - 30.0f); }

/// A cap (radius 8 mm, 70 mm high) on a shoulder falling from 50 mm at its edge to 35 mm at 22 mm
/// (slope 15 / 14: 47 deg).
float bottle(int u, int v) {
  const float r = radius(u, v);
  if (r <= 8.0f) return 0.070f;
  if (r <= 22.0f) return 0.050f - 0.015f * (r - 8.0f) / 14.0f;
  return 0.0f;
}

/// A 16 mm box 30 mm high on a 40 mm box 40 mm high: flat around the step.
float box_on_box(int u, int v) {
  const int du = std::abs(u - 30), dv = std::abs(v - 30);
  if (du <= 8 && dv <= 8) return 0.070f;
  if (du <= 20 && dv <= 20) return 0.040f;
  return 0.0f;
}

}  // namespace

TEST(NestedSegments, ACapJoinsTheShoulderItSitsOn) {
  EXPECT_EQ(segments(bottle, nullptr), 2u);  // without the table: the range step splits them
  EXPECT_EQ(segments(bottle, &kTable), 1u);
}

TEST(NestedSegments, ABoxOnALargerBoxStaysTwo) {
  EXPECT_EQ(segments(box_on_box, &kTable), 2u);
}

TEST(NestedSegments, ABowlsFloorJoinsItsRimAcrossTheInnerWall) {
  // a flat rim 45 mm high (18..24 mm out); inside it the inner wall falls at 45 deg to the floor
  const auto bowl = [](int u, int v) {
    const float r = radius(u, v);
    if (r > 24.0f) return 0.0f;
    if (r > 18.0f) return 0.045f;
    if (r > 8.0f) return 0.034f - 0.010f * (18.0f - r) / 10.0f;  // the inner wall, 45 deg
    return 0.024f;
  };
  EXPECT_EQ(segments(bowl, nullptr), 2u);
  EXPECT_EQ(segments(bowl, &kTable), 1u);
}

TEST(NestedSegments, ObjectsSideBySideAreNotNested) {
  const auto pair = [](int u, int v) {
    if (v < 20 || v > 40) return 0.0f;
    if (u >= 10 && u < 30) return 0.060f - 0.001f * (u - 10);  // a sloped top
    if (u >= 30 && u < 50) return 0.030f;
    return 0.0f;
  };
  EXPECT_EQ(segments(pair, &kTable), 2u);
}

TEST(NestedSegments, OffWhenTheFractionIsZero) {
  SceneFilterParams p;
  p.segment_nest_fraction = 0.0;
  EXPECT_EQ(segments(bottle, &kTable, p), 2u);
}

TEST(NestedSegments, NoJoinWhoseUnionWouldExceedTheClusterExtent) {
  // the shoulder's 3-D box diagonal is 64 mm, the cap's 23 mm, the bottle's 71 mm: a join would
  // make one segment the cluster extent rule rejects, so both parts stay as they are
  SceneFilterParams p;
  p.cluster_max_extent = 0.068;
  EXPECT_EQ(segments(bottle, &kTable, p), 2u);
  p.cluster_max_extent = 0.075;
  EXPECT_EQ(segments(bottle, &kTable, p), 1u);
}
