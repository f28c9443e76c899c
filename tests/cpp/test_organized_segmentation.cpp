// Organized segmentation of the candidates (grasp_core::organized_components)
// and the range-dependent minimum height of clusters_from_components.
#include <gtest/gtest.h>

#include "grasp_core/clustering.hpp"
#include "grasp_core/organized_segmentation.hpp"

#include <random>
#include <set>
#include <vector>

using namespace grasp_core;

namespace {

/// An organized W x H image seen from a camera at the origin looking along +z: pixel (u, v)
/// at x = u * 1 mm, y = v * 1 mm, depth z(u, v) (NaN: no candidate).
struct Image {
  int w, h;
  std::vector<float> z;
  std::vector<std::uint8_t> rgb;
  Image(int w_, int h_) : w(w_), h(h_), z(static_cast<std::size_t>(w_ * h_), NAN), rgb(3 * w_ * h_, 0) {}
  float& at(int u, int v) { return z[static_cast<std::size_t>(v * w + u)]; }
  void colour(int u, int v, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    std::uint8_t* p = &rgb[3 * static_cast<std::size_t>(v * w + u)];
    p[0] = r; p[1] = g; p[2] = b;
  }
  /// Segment count of the candidates.
  std::size_t segments(const SceneFilterParams& p, bool colour = false) {
    std::vector<float> xyz;
    std::vector<int> rows;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u)
        if (!std::isnan(at(u, v))) {
          xyz.insert(xyz.end(), {u * 0.001f, v * 0.001f, at(u, v)});
          rows.push_back(v * w + u);
        }
    OrganizedWorkspace ws;
    const auto comp = organized_components(xyz.data(), rows.data(), rows.size(), z.size(), w,
                                           colour ? rgb.data() : nullptr, Vec3::Zero(), p, ws);
    for (int pix : ws.pixel_to_candidate) EXPECT_EQ(pix, -1);  // the map is left clean
    for (float r : ws.range_image) EXPECT_TRUE(std::isnan(r));  // and so is the range image
    return std::set<int>(comp.begin(), comp.end()).size();
  }
};

TEST(OrganizedSegmentation, GapStepAndNoise) {
  SceneFilterParams p;
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.0f, 0.002f);  // 2 mm at 0.4 m, as the sensor
  Image img(60, 30);
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 60; ++u) img.at(u, v) = 0.4f + noise(rng);
  EXPECT_EQ(img.segments(p), 1u);           // one noisy surface stays one segment
  for (int v = 0; v < 30; ++v) img.at(30, v) = NAN;  // a 1-pixel slit where the table shows
  EXPECT_EQ(img.segments(p), 2u);
  for (int v = 0; v < 30; ++v) {
    img.at(30, v) = 0.4f + noise(rng);
    for (int u = 31; u < 60; ++u) img.at(u, v) = 0.37f + noise(rng);  // a 3 cm height step
  }
  EXPECT_EQ(img.segments(p), 2u);
}

TEST(OrganizedSegmentation, ColourBoundaryByHue) {
  SceneFilterParams p;
  Image img(40, 20);
  for (int v = 0; v < 20; ++v)
    for (int u = 0; u < 40; ++u) {
      img.at(u, v) = 0.4f;
      const std::uint8_t s = static_cast<std::uint8_t>(120 + 3 * (u % 30));  // shading
      if (u < 20) img.colour(u, v, s, s / 5, s / 5);  // red
      else img.colour(u, v, s / 5, s / 4, s);         // blue
    }
  EXPECT_EQ(img.segments(p, false), 1u);
  EXPECT_EQ(img.segments(p, true), 2u);
  p.segment_max_hue_diff_deg = 0.0;  // colour off
  EXPECT_EQ(img.segments(p, true), 1u);
}

TEST(OrganizedSegmentation, AReusedWorkspaceSmoothsAsAFreshOne) {
  // Two frames of different candidates through one workspace: the second frame's smoothed
  // ranges and segments are those of a fresh workspace (nothing of the first is left over).
  SceneFilterParams p;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.002f);
  const int w = 40, h = 20;
  std::vector<std::vector<float>> xyz(2);
  std::vector<std::vector<int>> rows(2);
  for (int f = 0; f < 2; ++f)
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        if ((u + v + f) % 7 == 0) continue;  // holes in other places in each frame
        const float z = (u < 20 ? 0.40f : 0.37f + 0.01f * f) + noise(rng);
        xyz[f].insert(xyz[f].end(), {u * 0.001f, v * 0.001f, z});
        rows[f].push_back(v * w + u);
      }
  auto run = [&](int f, OrganizedWorkspace& ws) {
    const auto comp = organized_components(xyz[f].data(), rows[f].data(), rows[f].size(),
                                           static_cast<std::size_t>(w * h), w, nullptr, Vec3::Zero(), p, ws);
    return std::make_pair(comp, ws.smooth);
  };
  OrganizedWorkspace reused, fresh;
  run(0, reused);
  const auto again = run(1, reused), once = run(1, fresh);
  EXPECT_EQ(again.first, once.first);
  ASSERT_EQ(again.second.size(), once.second.size());
  for (std::size_t k = 0; k < once.second.size(); ++k) EXPECT_EQ(again.second[k], once.second[k]);
}

TEST(OrganizedSegmentation, RejectsRowsOutsideTheImage) {
  SceneFilterParams p;
  OrganizedWorkspace ws;
  const float xyz[3] = {0, 0, 1};
  const int rows[1] = {100};
  EXPECT_THROW(organized_components(xyz, rows, 1, 50, 10, nullptr, Vec3::Zero(), p, ws),
               std::invalid_argument);
  EXPECT_THROW(organized_components(xyz, rows, 1, 55, 10, nullptr, Vec3::Zero(), p, ws),
               std::invalid_argument);
}

TEST(HeightRule, LowPatchesFarAwayAreNotObjects) {
  // Two 12 mm high patches: one 0.5 m from the camera, one 2 m away.
  std::vector<float> xyz;
  std::vector<int> comp;
  for (int i = 0; i < 100; ++i) {
    xyz.insert(xyz.end(), {0.4f + 0.001f * (i % 10), 0.001f * (i / 10), 0.012f});
    comp.push_back(0);
  }
  for (int i = 0; i < 100; ++i) {
    xyz.insert(xyz.end(), {1.9f + 0.001f * (i % 10), 0.001f * (i / 10), 0.012f});
    comp.push_back(100);
  }
  HeightRule rule;
  rule.table = Plane{Vec3::UnitZ(), 0.0};
  rule.camera = Vec3(0.0, 0.0, 0.3);
  rule.sigmas = 1.0;
  const ClusterResult r = clusters_from_components(xyz.data(), comp.size(), 3, comp, 20, 0.005, 0.3, &rule);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_EQ(r.num_accepted, 1);
  EXPECT_EQ(r.labels[0], 0);
  EXPECT_EQ(r.labels[150], kLabelEnvironment);
  const ClusterResult off = clusters_from_components(xyz.data(), comp.size(), 3, comp, 20, 0.005, 0.3);
  EXPECT_EQ(off.num_accepted, 2);
}

}  // namespace
