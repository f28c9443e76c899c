// Parameter sets of the perception core, with the names and defaults of docs/method.md §1.6 and §2.7.
//
// SceneFilterParams = method.md §1.6, ObbParams = the perception part of method.md §2.7
// (estimate, guards and tracker). The Python side loads them from
// config/scene_filter.yaml and config/obb.yaml; validate() is the single place
// that rejects negative or absurd values, naming the parameter.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "grasp_core/types.hpp"

namespace grasp_core {

/// ``x`` to the power ``exponent`` for the depth noise law: the quadratic law (exponent 2,
/// the usual one) as one multiplication instead of a call of ``std::pow`` (read per pixel).
inline double noise_growth(double x, double exponent) {
  return exponent == 2.0 ? x * x : std::pow(x, exponent);
}

struct SceneFilterParams {
  double plane_dist_thresh = 0.008;      ///< inlier distance [m]
  double plane_max_tilt_deg = 10.0;      ///< max normal angle from +z [deg]
  int plane_ransac_iters = 200;          ///< RANSAC iterations per plane
  int plane_fit_max_points = 4000;       ///< subsample size for the search
  double plane_min_inlier_ratio = 0.15;  ///< acceptance within the subsample
  int plane_max_count = 3;               ///< planes extracted per frame
  double plane_dominance = 0.70;         ///< rho of method.md §1.3
  bool plane_lock = true;                ///< persistence state machine on/off
  int plane_lock_after = 5;              ///< consistent frames before hardening
  double plane_update_tol_deg = 5.0;     ///< "close" normal angle [deg]
  double plane_update_tol_m = 0.03;      ///< "close" height difference [m]
  int plane_init_frames = 30;            ///< frames without lock before falling back
  double cluster_eps = 0.015;            ///< Euclidean clustering radius [m]
  int cluster_min_points = 20;           ///< smaller components are noise
  double cluster_min_extent = 0.01;      ///< min AABB diagonal [m]
  double cluster_max_extent = 0.30;      ///< max AABB diagonal [m]; <= 0 disables
  double band = 0.01;                    ///< band above the plane [m]
  double cluster_voxel_m = 0.003;        ///< (ours) > 0: the fast grid clustering (same partition as PCL, grid cell min(this, eps/sqrt 3)); 0: per-point PCL clustering [m]
  std::uint64_t seed = 0;                ///< (ours) RNG seed: runs are reproducible
  /// (ours) sane coordinate bound [m]: rows with any |coordinate| above it are dropped and
  /// counted (SceneFilterResult::num_out_of_range), like NaN rows. In (0, 1e9].
  double max_abs_coordinate_m = kDefaultMaxAbsCoordinate_m;

  // (ours) Organized segmentation of the candidates (organized_segmentation.hpp):
  // used when the frame is organized (an image width is given), else Euclidean clustering.
  bool segment_organized = true;         ///< organized frames: image-neighbour segmentation
  int segment_smooth_radius_px = 2;      ///< half-width of the range smoothing window [px]
  double segment_max_step_m = 0.006;     ///< max smoothed range step between neighbour pixels at depth_noise_ref_range_m [m]
  double segment_max_hue_diff_deg = 20.0; ///< max hue difference of linked neighbours [deg]; <= 0: colour unused
  double segment_min_saturation = 0.25;   ///< hue compared only where both pixels' saturation (max-min)/max >= this
  double segment_min_brightness = 30.0;   ///< ... and their max channel >= this (0..255)
  int segment_absorb_max_points = 400;    ///< smaller segments join the large one they touch most (within cluster_eps); 0: never
  double segment_nest_fraction = 0.9;     ///< a segment this much enclosed by another ... (nested_segments.hpp); <= 0: never joined
  double segment_nest_min_slope_deg = 25.0; ///< ... joins it where that one's surface around it slopes at least this much [deg]
  double segment_nest_max_slope_deg = 80.0; ///< ... and at most this much (steeper: a wall seen edge-on, a box's side) [deg]
  int segment_nest_rings_px = 6;          ///< one-pixel rings of the outer segment the slope is measured over [px]
  // (ours) Depth noise model of the sensor: sigma(r) = depth_noise_sigma_m * (r / ref)^exp.
  double depth_noise_sigma_m = 0.002;    ///< depth noise sigma at depth_noise_ref_range_m [m]
  double depth_noise_ref_range_m = 0.4;  ///< [m]
  double depth_noise_exponent = 2.0;     ///< growth of the noise with range (2: structured light / ToF)
  /// (ours) A cluster is an object only if its robust height above the table (90th
  /// percentile of its points' heights) is >= this many sigma(range) at its centroid's range
  /// from the camera. 0 disables the rule (also when the camera position is unknown).
  double object_min_height_sigmas = 1.0;

  /// The depth noise model: depth_noise_sigma_m * (range_m / depth_noise_ref_range_m)^depth_noise_exponent [m].
  double depth_noise_at(double range_m) const;

  /// Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

struct ObbParams {
  double depth_noise_sigma = 0.002;     ///< sigma [m]
  double top_slice_sigmas = 4.0;        ///< slice depth in sigmas
  int top_slice_iters = 3;              ///< slice-median iterations
  int n_theta = 361;                    ///< width-scan angles over [0, pi)
  double width_tol_m = 0.002;           ///< candidate tolerance [m]
  double isotropy_ratio_max = 1.10;     ///< yaw_defined threshold
  double gripper_open = 0.08;           ///< max opening [m]
  double min_graspable_width = 0.005;   ///< [m]
  double min_height = 0.005;            ///< [m]
  double resting_margin = 0.008;        ///< [m]
  double side_seen_sigmas = 3.0;        ///< (ours) sides visible if d-span > this * sigma
  int window = 7;                       ///< tracker median window [frames]
  double assoc_gate_frac = 0.5;         ///< gate = frac * min pairwise distance
  double max_age_s = 2.0;               ///< retirement of non-NADIR tracks [s]
  double nadir_hold_s = 10.0;           ///< retirement of NADIR tracks [s]
  double nadir_angle_max_deg = 5.0;     ///< NADIR threshold [deg]
  double nadir_min_distance_m = 0.25;   ///< (ours) closer views are never NADIR: the object may not fit the view [m]

  /// Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

}  // namespace grasp_core
