// (ours) The scene volume: a voxel grid over a fixed world box that accumulates the depth
// frames the arm takes into occupancy with free space carved by every ray, so that a consumer
// can ask, for any place in the box, whether it was seen FREE, seen OCCUPIED, or never seen
// (UNKNOWN).
//
// Model: log-odds occupancy with clamping (as OctoMap's, Hornung et al. 2013), updated
// projectively. For one frame, every voxel whose centre projects into the image is compared
// with the depth d measured at its pixel (nearest pixel, depth along the optical axis):
//   z < d - truncation            -> evidence of free    (log-odds += logodds_miss, < 0)
//   |z - d| <= truncation         -> evidence of occupied (log-odds += logodds_hit, > 0)
//   z > d + truncation, d invalid -> no information
// and the log-odds is clamped to [logodds_min, logodds_max], so a few frames that see through
// a place overturn an old OCCUPIED there (an object that moved) and vice versa. A voxel never
// updated is UNKNOWN; else OCCUPIED when its log-odds is > 0, FREE otherwise.
//
// Why occupancy and not a TSDF: the consumers need the three states (the grasp sampler keeps
// the hand out of the space no camera has seen; the view planner counts unknown voxels and
// stops rays at occupied ones), not a sub-voxel surface: the surface itself comes from the
// frames' points. A TSDF would give the same three states with two numbers per voxel instead
// of one, and its weights need the same capping to forget a moved object.
#pragma once

#include "grasp_core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// The state of a place in the volume (classify(), states_in_box()).
enum class VoxelState : std::int8_t {
  kUnknown = 0,   ///< inside the box, never observed
  kFree = 1,      ///< observed, log-odds <= 0
  kOccupied = 2,  ///< observed, log-odds > 0
  kOutside = 3,   ///< outside the box (nothing is known there)
};

/// Parameters of a SceneVolume (validate() checks them).
struct SceneVolumeParams {
  Vec3 box_min_m = Vec3(0.25, -0.40, 0.18);  ///< world box, lower corner [m]
  Vec3 box_max_m = Vec3(0.85, 0.40, 0.50);   ///< upper corner [m] (rounded up to whole voxels)
  double voxel_m = 0.005;                    ///< voxel edge [m], in [0.001, 0.1]
  double truncation_m = 0.01;                ///< occupied band around the surface [m], >= voxel_m / 2
  double logodds_hit = 0.85;                 ///< added on occupied evidence (> 0)
  double logodds_miss = -0.4;                ///< added on free evidence (< 0)
  double logodds_min = -2.0;                 ///< clamp (< 0, <= logodds_miss)
  double logodds_max = 3.5;                  ///< clamp (> 0, >= logodds_hit)
  /// Throws std::invalid_argument naming the parameter.
  void validate() const;
};

/// Most voxels a volume may have (a misconfigured box must not allocate gigabytes).
constexpr std::int64_t kMaxVolumeVoxels = 64LL * 1024 * 1024;

/// What one integrate() call did.
struct VolumeIntegration {
  std::int64_t voxels_in_view = 0;  ///< voxels whose centre projected into the image (up to the far bound)
  std::int64_t voxels_free = 0;     ///< of those: free evidence
  std::int64_t voxels_occupied = 0; ///< of those: occupied evidence
  int valid_pixels = 0;             ///< depth pixels that were finite, > 0 and <= max_range_m
  double ms = 0.0;                  ///< wall time of the call [ms]
};

/// Counts of voxel states over the lattice cells whose centre lies in a query box.
struct VolumeCounts {
  std::int64_t unknown = 0, free = 0, occupied = 0;
  std::int64_t outside = 0;  ///< cells of the query box outside the volume's box
};

/// A pinhole camera: image size and intrinsics (no skew).
struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

/// The voxel grid. Not thread-safe (the Python binding serialises calls).
class SceneVolume {
 public:
  /// Validates `params` (std::invalid_argument naming the parameter) and allocates the grid,
  /// every voxel UNKNOWN.
  explicit SceneVolume(const SceneVolumeParams& params);

  /// Integrate one depth image: `depth` row-major, pixel (u, v) at depth[v * row_stride + u],
  /// metres along the optical axis, NaN/<= 0/> max_range_m = no measurement; `T_world_camera`
  /// the optical frame (z forward, x right, y down) at capture. Only voxels inside the
  /// camera's frustum up to the farthest valid depth + truncation are visited.
  /// Throws std::invalid_argument on a null image, a non-positive size/focal length or range.
  VolumeIntegration integrate(const float* depth, const PinholeCamera& camera, std::size_t row_stride,
                              const Pose& T_world_camera, double max_range_m);

  /// The state at each of n points (xyz at p + i * stride, float64); NaN rows are kOutside.
  void classify(const double* xyz, std::size_t n, std::size_t stride, std::int8_t* out) const;

  /// Centres of the OCCUPIED voxels whose centre lies in [lo, hi].
  std::vector<Vec3> occupied_centres(const Vec3& lo, const Vec3& hi) const;
  /// Centres and states of every voxel whose centre lies in [lo, hi] (x fastest, then y, z).
  void states_in_box(const Vec3& lo, const Vec3& hi, std::vector<Vec3>* centres,
                     std::vector<std::int8_t>* states) const;
  /// State counts over the lattice cells whose centre lies in [lo, hi].
  VolumeCounts count_states(const Vec3& lo, const Vec3& hi) const;

  /// For each of n points: true when a camera at `T_world_camera` would see it — its depth
  /// within [min_range_m, max_range_m], it projects into the image, and the straight line
  /// from the camera centre to it crosses no OCCUPIED voxel before the point's own voxel
  /// (UNKNOWN voxels on the way do not block: the optimistic view of next-best-view planning).
  std::vector<std::uint8_t> visible(const double* xyz, std::size_t n, std::size_t stride,
                                    const PinholeCamera& camera, const Pose& T_world_camera,
                                    double min_range_m, double max_range_m) const;

  /// Forget everything (every voxel UNKNOWN).
  void reset();
  /// Forget the voxels whose centre lies in [lo, hi] (UNKNOWN again).
  void reset_box(const Vec3& lo, const Vec3& hi);

  const SceneVolumeParams& params() const { return params_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }
  Vec3 box_min() const { return origin_; }
  /// The upper corner actually covered: box_min + n * voxel_m.
  Vec3 box_max() const;
  std::size_t memory_bytes() const { return logodds_.size() * sizeof(float); }
  int frames_integrated() const { return frames_; }

 private:
  struct IndexRange { int lo[3]; int hi[3]; bool empty; };
  /// Lattice index range of the cells whose centre lies in [lo, hi], clipped to the grid.
  IndexRange cells_in(const Vec3& lo, const Vec3& hi) const;
  std::size_t index(int ix, int iy, int iz) const {
    return (static_cast<std::size_t>(iz) * ny_ + iy) * nx_ + ix;
  }
  Vec3 centre(int ix, int iy, int iz) const;
  bool cell_of(const Vec3& p, int* ix, int* iy, int* iz) const;
  bool occupied_at(std::size_t i) const;
  bool ray_blocked(const Vec3& from, const Vec3& to) const;

  SceneVolumeParams params_;
  Vec3 origin_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<float> logodds_;  ///< NaN: never observed
  int frames_ = 0;
};

}  // namespace grasp_core
