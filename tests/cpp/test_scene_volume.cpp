// (ours) The scene volume (grasp_core::SceneVolume): projective log-odds occupancy.
#include <gtest/gtest.h>

#include "grasp_core/scene_volume.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace grasp_core;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// An axis-aligned box in world.
struct Box {
  Vec3 lo, hi;
};

PinholeCamera camera_640x480() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 430.0;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

/// Optical frame at `eye` looking at `target` (x right, y down, z forward), `up` ~ world up.
Pose look_at(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitZ()) {
  const Vec3 z = (target - eye).normalized();
  Vec3 x = z.cross(up);
  if (x.norm() < 1e-9) x = z.cross(Vec3::UnitY());
  x.normalize();
  const Vec3 y = z.cross(x);
  Pose p;
  p.R.col(0) = x;
  p.R.col(1) = y;
  p.R.col(2) = z;
  p.t = eye;
  return p;
}

/// Entry parameter of the ray o + t d into `b` (inf: misses).
double hit_box(const Vec3& o, const Vec3& d, const Box& b) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (o[a] < b.lo[a] || o[a] > b.hi[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

/// Depth image (metres along the optical axis, NaN: no surface) of `boxes` and, when
/// `table_z` is finite, the plane z = table_z, ray-cast from `T`.
std::vector<float> render(const PinholeCamera& c, const Pose& T, const std::vector<Box>& boxes,
                          double table_z = std::nan("")) {
  std::vector<float> depth(static_cast<std::size_t>(c.width) * c.height, kNaN);
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const Vec3 dc((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0);  // z = 1: t is the depth
      const Vec3 dw = T.R * dc;
      double t = std::numeric_limits<double>::infinity();
      for (const Box& b : boxes) t = std::min(t, hit_box(T.t, dw, b));
      if (std::isfinite(table_z) && dw.z() < -1e-12) {
        const double tt = (table_z - T.t.z()) / dw.z();
        if (tt > 0) t = std::min(t, tt);
      }
      if (std::isfinite(t)) depth[static_cast<std::size_t>(v) * c.width + u] = static_cast<float>(t);
    }
  return depth;
}

SceneVolumeParams small_params() {
  SceneVolumeParams p;
  p.box_min_m = Vec3(0.30, -0.20, 0.15);
  p.box_max_m = Vec3(0.70, 0.20, 0.40);
  return p;
}

VoxelState state_at(const SceneVolume& v, const Vec3& p) {
  std::int8_t s;
  v.classify(p.data(), 1, 3, &s);
  return static_cast<VoxelState>(s);
}

const Box kBox{Vec3(0.45, -0.05, 0.20), Vec3(0.55, 0.05, 0.30)};

}  // namespace

TEST(SceneVolume, GridCoversTheBoxInWholeVoxelsAndStartsUnknown) {
  SceneVolume v(small_params());
  EXPECT_EQ(v.nx(), 80);
  EXPECT_EQ(v.ny(), 80);
  EXPECT_EQ(v.nz(), 50);
  EXPECT_EQ(v.memory_bytes(), 80u * 80u * 50u * sizeof(float));
  EXPECT_EQ(state_at(v, Vec3(0.5, 0.0, 0.25)), VoxelState::kUnknown);
  EXPECT_EQ(state_at(v, Vec3(0.1, 0.0, 0.25)), VoxelState::kOutside);
  const Vec3 nan(std::nan(""), 0.0, 0.0);
  EXPECT_EQ(state_at(v, nan), VoxelState::kOutside);
  const VolumeCounts c = v.count_states(Vec3(0.3, -0.2, 0.15), Vec3(0.7, 0.2, 0.4));
  EXPECT_EQ(c.unknown, 80 * 80 * 50);
  EXPECT_EQ(c.free + c.occupied + c.outside, 0);
}

TEST(SceneVolume, OneSideViewFrontFreeSurfaceOccupiedBehindUnknown) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose T = look_at(Vec3(0.15, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  const std::vector<float> depth = render(cam, T, {kBox});
  const VolumeIntegration r = v.integrate(depth.data(), cam, cam.width, T, 3.0);
  EXPECT_GT(r.valid_pixels, 0);
  EXPECT_GT(r.voxels_free, 0);
  EXPECT_GT(r.voxels_occupied, 0);
  EXPECT_EQ(v.frames_integrated(), 1);
  EXPECT_EQ(state_at(v, Vec3(0.40, 0.0, 0.25)), VoxelState::kFree);       // in front
  EXPECT_EQ(state_at(v, Vec3(0.4525, 0.0, 0.25)), VoxelState::kOccupied); // the face
  EXPECT_EQ(state_at(v, Vec3(0.50, 0.0, 0.25)), VoxelState::kUnknown);    // inside, behind
  EXPECT_EQ(state_at(v, Vec3(0.65, 0.0, 0.25)), VoxelState::kUnknown);    // the far side
  // Beside the box the rays return nothing (no table): no information there either.
  EXPECT_EQ(state_at(v, Vec3(0.40, 0.15, 0.25)), VoxelState::kUnknown);
}

TEST(SceneVolume, TwoOppositeViewsCarveTheBack) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose front = look_at(Vec3(0.15, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  const Pose back = look_at(Vec3(0.85, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  for (const Pose& T : {front, back}) {
    const std::vector<float> depth = render(cam, T, {kBox});
    v.integrate(depth.data(), cam, cam.width, T, 3.0);
  }
  EXPECT_EQ(state_at(v, Vec3(0.40, 0.0, 0.25)), VoxelState::kFree);
  EXPECT_EQ(state_at(v, Vec3(0.65, 0.0, 0.25)), VoxelState::kFree);
  EXPECT_EQ(state_at(v, Vec3(0.4525, 0.0, 0.25)), VoxelState::kOccupied);
  EXPECT_EQ(state_at(v, Vec3(0.5475, 0.0, 0.25)), VoxelState::kOccupied);
  EXPECT_EQ(state_at(v, Vec3(0.50, 0.0, 0.25)), VoxelState::kUnknown);  // the core nobody sees
}

TEST(SceneVolume, TopViewCarvesBesideTheBoxAndLeavesUnderTheTableUnknown) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose T = look_at(Vec3(0.5, 0.0, 0.65), Vec3(0.5, 0.0, 0.2), Vec3::UnitX());
  const std::vector<float> depth = render(cam, T, {kBox}, 0.20);
  v.integrate(depth.data(), cam, cam.width, T, 3.0);
  EXPECT_EQ(state_at(v, Vec3(0.5, 0.0, 0.3025)), VoxelState::kOccupied);  // top face
  EXPECT_EQ(state_at(v, Vec3(0.5, 0.0, 0.35)), VoxelState::kFree);        // above it
  EXPECT_EQ(state_at(v, Vec3(0.62, 0.0, 0.25)), VoxelState::kFree);       // beside it
  EXPECT_EQ(state_at(v, Vec3(0.62, 0.0, 0.2025)), VoxelState::kOccupied); // the table
  EXPECT_EQ(state_at(v, Vec3(0.62, 0.0, 0.17)), VoxelState::kUnknown);    // under the table
  // Right beside the face, near the table: in the box's shadow from this camera.
  EXPECT_EQ(state_at(v, Vec3(0.5575, 0.0, 0.2175)), VoxelState::kUnknown);
  const std::vector<Vec3> occ = v.occupied_centres(kBox.lo - Vec3::Constant(0.002), kBox.hi + Vec3(0.002, 0.002, 0.02));
  ASSERT_FALSE(occ.empty());
  for (const Vec3& c : occ) EXPECT_GE(c.z(), 0.29);  // only the top is seen
}

TEST(SceneVolume, AnObjectThatLeftIsCarvedAwayByLaterFrames) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose T = look_at(Vec3(0.30, 0.0, 0.60), Vec3(0.5, 0.0, 0.2));
  const std::vector<float> with_box = render(cam, T, {kBox}, 0.20);
  const std::vector<float> without = render(cam, T, {}, 0.20);
  for (int i = 0; i < 10; ++i) v.integrate(with_box.data(), cam, cam.width, T, 3.0);
  const Vec3 top(0.5, 0.0, 0.3025);
  ASSERT_EQ(state_at(v, top), VoxelState::kOccupied);
  int frames = 0;
  while (state_at(v, top) == VoxelState::kOccupied && frames < 50) {
    v.integrate(without.data(), cam, cam.width, T, 3.0);
    ++frames;
  }
  EXPECT_EQ(state_at(v, top), VoxelState::kFree);
  // The clamp bounds how long the old evidence holds: logodds_max / |logodds_miss| frames.
  EXPECT_LE(frames, static_cast<int>(std::ceil(3.5 / 0.4)) + 1);
}

TEST(SceneVolume, DepthBeyondTheRangeOrInvalidGivesNoInformation) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose T = look_at(Vec3(0.15, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  const std::vector<float> depth = render(cam, T, {kBox});
  const VolumeIntegration r = v.integrate(depth.data(), cam, cam.width, T, 0.2);  // the box is 0.3 m away
  EXPECT_EQ(r.valid_pixels, 0);
  EXPECT_EQ(state_at(v, Vec3(0.40, 0.0, 0.25)), VoxelState::kUnknown);
}

TEST(SceneVolume, VisibilityStopsAtOccupiedVoxels) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose front = look_at(Vec3(0.15, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  const std::vector<float> depth = render(cam, front, {kBox});
  v.integrate(depth.data(), cam, cam.width, front, 3.0);
  const Pose back = look_at(Vec3(0.85, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  const double pts[] = {0.60, 0.0, 0.25,   // behind the box seen from the front
                        0.40, 0.0, 0.25};  // in front
  const std::vector<std::uint8_t> f = v.visible(pts, 2, 3, cam, front, 0.05, 3.0);
  EXPECT_EQ(f[0], 0);
  EXPECT_EQ(f[1], 1);
  const std::vector<std::uint8_t> b = v.visible(pts, 2, 3, cam, back, 0.05, 3.0);
  EXPECT_EQ(b[0], 1);  // nothing occupied between the back camera and it
  EXPECT_EQ(b[1], 0);  // the box's front face is in the way
  const std::vector<std::uint8_t> near = v.visible(pts, 1, 3, cam, back, 0.3, 3.0);
  EXPECT_EQ(near[0], 0);  // nearer than the minimum range
}

TEST(SceneVolume, ResetBoxForgetsOnlyThatBox) {
  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  const Pose T = look_at(Vec3(0.5, 0.0, 0.65), Vec3(0.5, 0.0, 0.2), Vec3::UnitX());
  const std::vector<float> depth = render(cam, T, {kBox}, 0.20);
  v.integrate(depth.data(), cam, cam.width, T, 3.0);
  v.reset_box(Vec3(0.4, -0.1, 0.15), Vec3(0.6, 0.1, 0.40));
  EXPECT_EQ(state_at(v, Vec3(0.5, 0.0, 0.35)), VoxelState::kUnknown);
  EXPECT_EQ(state_at(v, Vec3(0.65, 0.0, 0.25)), VoxelState::kFree);
  const VolumeCounts c = v.count_states(Vec3(0.4, -0.1, 0.15), Vec3(0.6, 0.1, 0.40));
  EXPECT_EQ(c.free + c.occupied, 0);
  EXPECT_GT(c.unknown, 0);
  const VolumeCounts wide = v.count_states(Vec3(0.0, -0.1, 0.2), Vec3(0.401, 0.1, 0.2049));
  EXPECT_EQ(wide.outside, 60 * 40);  // x 0.0-0.3 (60 cells) outside, one z layer
  v.reset();
  EXPECT_EQ(v.frames_integrated(), 0);
  EXPECT_EQ(state_at(v, Vec3(0.65, 0.0, 0.25)), VoxelState::kUnknown);
}

TEST(SceneVolume, BadParametersAndInputsThrow) {
  SceneVolumeParams p = small_params();
  p.voxel_m = 0.0;
  EXPECT_THROW(SceneVolume{p}, std::invalid_argument);
  p = small_params();
  p.box_max_m = p.box_min_m;
  EXPECT_THROW(SceneVolume{p}, std::invalid_argument);
  p = small_params();
  p.box_min_m = Vec3(-100, -100, -100);
  p.box_max_m = Vec3(100, 100, 100);
  EXPECT_THROW(SceneVolume{p}, std::invalid_argument);  // too many voxels
  p = small_params();
  p.logodds_miss = 0.1;
  EXPECT_THROW(SceneVolume{p}, std::invalid_argument);
  p = small_params();
  p.truncation_m = 0.001;
  EXPECT_THROW(SceneVolume{p}, std::invalid_argument);

  SceneVolume v(small_params());
  const PinholeCamera cam = camera_640x480();
  std::vector<float> depth(static_cast<std::size_t>(cam.width) * cam.height, 0.5f);
  Pose T = look_at(Vec3(0.15, 0.0, 0.25), Vec3(0.5, 0.0, 0.25));
  Pose bad = T;
  bad.t.x() = std::nan("");
  EXPECT_THROW(v.integrate(depth.data(), cam, cam.width, bad, 3.0), std::invalid_argument);
  bad = T;
  bad.R *= 2.0;
  EXPECT_THROW(v.integrate(depth.data(), cam, cam.width, bad, 3.0), std::invalid_argument);
  EXPECT_THROW(v.integrate(nullptr, cam, cam.width, T, 3.0), std::invalid_argument);
  EXPECT_THROW(v.integrate(depth.data(), cam, cam.width, T, -1.0), std::invalid_argument);
  PinholeCamera flat = cam;
  flat.fx = 0.0;
  EXPECT_THROW(v.integrate(depth.data(), flat, cam.width, T, 3.0), std::invalid_argument);
  EXPECT_EQ(v.frames_integrated(), 0);
}
