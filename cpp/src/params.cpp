#include "grasp_core/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace grasp_core {
namespace {

template <typename T>
void require(bool ok, const char* name, T value, const char* expected) {
  if (ok) return;
  std::ostringstream os;
  os << "parameter '" << name << "' = " << value << " is invalid: expected " << expected;
  throw std::invalid_argument(os.str());
}

bool finite(double x) { return std::isfinite(x); }

}  // namespace

void SceneFilterParams::validate() const {
  require(finite(plane_dist_thresh) && plane_dist_thresh > 0 && plane_dist_thresh <= 1.0,
          "plane_dist_thresh", plane_dist_thresh, "a distance in (0, 1] m");
  require(finite(plane_max_tilt_deg) && plane_max_tilt_deg > 0 && plane_max_tilt_deg < 90,
          "plane_max_tilt_deg", plane_max_tilt_deg, "an angle in (0, 90) deg");
  require(plane_ransac_iters >= 1 && plane_ransac_iters <= 1000000, "plane_ransac_iters",
          plane_ransac_iters, "an integer in [1, 1e6]");
  require(plane_fit_max_points >= 3 && plane_fit_max_points <= 10000000, "plane_fit_max_points",
          plane_fit_max_points, "an integer in [3, 1e7]");
  require(finite(plane_min_inlier_ratio) && plane_min_inlier_ratio >= 0 &&
              plane_min_inlier_ratio <= 1,
          "plane_min_inlier_ratio", plane_min_inlier_ratio, "a ratio in [0, 1]");
  require(plane_max_count >= 1 && plane_max_count <= 100, "plane_max_count", plane_max_count,
          "an integer in [1, 100]");
  require(finite(plane_dominance) && plane_dominance > 0 && plane_dominance <= 1,
          "plane_dominance", plane_dominance, "a ratio in (0, 1]");
  require(plane_lock_after >= 1 && plane_lock_after <= 100000, "plane_lock_after",
          plane_lock_after, "an integer >= 1");
  require(finite(plane_update_tol_deg) && plane_update_tol_deg >= 0 && plane_update_tol_deg <= 90,
          "plane_update_tol_deg", plane_update_tol_deg, "an angle in [0, 90] deg");
  require(finite(plane_update_tol_m) && plane_update_tol_m >= 0 && plane_update_tol_m <= 10,
          "plane_update_tol_m", plane_update_tol_m, "a distance in [0, 10] m");
  require(plane_init_frames >= 1 && plane_init_frames <= 1000000, "plane_init_frames",
          plane_init_frames, "an integer >= 1");
  require(finite(cluster_eps) && cluster_eps > 0 && cluster_eps <= 1.0, "cluster_eps",
          cluster_eps, "a radius in (0, 1] m");
  require(cluster_min_points >= 1 && cluster_min_points <= 10000000, "cluster_min_points",
          cluster_min_points, "an integer >= 1");
  require(finite(cluster_min_extent) && cluster_min_extent >= 0 && cluster_min_extent <= 10,
          "cluster_min_extent", cluster_min_extent, "a length in [0, 10] m");
  require(finite(cluster_max_extent) && cluster_max_extent <= 100, "cluster_max_extent",
          cluster_max_extent, "a length <= 100 m (<= 0 disables the bound)");
  require(cluster_max_extent <= 0 || cluster_max_extent >= cluster_min_extent,
          "cluster_max_extent", cluster_max_extent, ">= cluster_min_extent (or <= 0 to disable)");
  require(finite(band) && band >= 0 && band <= 1.0, "band", band, "a height in [0, 1] m");
  require(finite(cluster_voxel_m) && cluster_voxel_m >= 0 && cluster_voxel_m < cluster_eps,
          "cluster_voxel_m", cluster_voxel_m, "a leaf size in [0, cluster_eps) m (0 = exact)");
  require(finite(max_abs_coordinate_m) && max_abs_coordinate_m > 0 &&
              max_abs_coordinate_m <= kMaxAbsCoordinateLimit_m,
          "max_abs_coordinate_m", max_abs_coordinate_m, "a bound in (0, 1e9] m");
  require(segment_smooth_radius_px >= 0 && segment_smooth_radius_px <= 10,
          "segment_smooth_radius_px", segment_smooth_radius_px, "an integer in [0, 10] px");
  require(finite(segment_max_step_m) && segment_max_step_m > 0 && segment_max_step_m <= 1.0,
          "segment_max_step_m", segment_max_step_m, "a step in (0, 1] m");
  require(finite(segment_max_hue_diff_deg) && segment_max_hue_diff_deg <= 180.0,
          "segment_max_hue_diff_deg", segment_max_hue_diff_deg, "an angle <= 180 deg (<= 0: colour unused)");
  require(finite(segment_min_saturation) && segment_min_saturation >= 0 && segment_min_saturation <= 1,
          "segment_min_saturation", segment_min_saturation, "a saturation in [0, 1]");
  require(finite(segment_min_brightness) && segment_min_brightness >= 0 && segment_min_brightness <= 255,
          "segment_min_brightness", segment_min_brightness, "a level in [0, 255]");
  require(segment_absorb_max_points >= 0 && segment_absorb_max_points <= 10000000,
          "segment_absorb_max_points", segment_absorb_max_points, "an integer in [0, 10000000] (0: never)");
  require(finite(segment_nest_fraction) && segment_nest_fraction <= 1.0,
          "segment_nest_fraction", segment_nest_fraction, "a fraction <= 1 (<= 0: never joined)");
  require(finite(segment_nest_min_slope_deg) && segment_nest_min_slope_deg >= 0 && segment_nest_min_slope_deg < 90,
          "segment_nest_min_slope_deg", segment_nest_min_slope_deg, "an angle in [0, 90) deg");
  require(finite(segment_nest_max_slope_deg) && segment_nest_max_slope_deg > segment_nest_min_slope_deg &&
              segment_nest_max_slope_deg < 90,
          "segment_nest_max_slope_deg", segment_nest_max_slope_deg, "an angle in (segment_nest_min_slope_deg, 90) deg");
  require(segment_nest_rings_px >= 2 && segment_nest_rings_px <= 50,
          "segment_nest_rings_px", segment_nest_rings_px, "an integer in [2, 50] px");
  require(finite(depth_noise_sigma_m) && depth_noise_sigma_m > 0 && depth_noise_sigma_m <= 0.1,
          "depth_noise_sigma_m", depth_noise_sigma_m, "a sigma in (0, 0.1] m");
  require(finite(depth_noise_ref_range_m) && depth_noise_ref_range_m > 0 && depth_noise_ref_range_m <= 100,
          "depth_noise_ref_range_m", depth_noise_ref_range_m, "a range in (0, 100] m");
  require(finite(depth_noise_exponent) && depth_noise_exponent >= 0 && depth_noise_exponent <= 4,
          "depth_noise_exponent", depth_noise_exponent, "an exponent in [0, 4]");
  require(finite(object_min_height_sigmas) && object_min_height_sigmas >= 0 && object_min_height_sigmas <= 100,
          "object_min_height_sigmas", object_min_height_sigmas, "a count in [0, 100] (0 disables)");
}

double SceneFilterParams::depth_noise_at(double range_m) const {
  return depth_noise_sigma_m * noise_growth(std::max(range_m, 0.0) / depth_noise_ref_range_m, depth_noise_exponent);
}

void ObbParams::validate() const {
  require(finite(depth_noise_sigma) && depth_noise_sigma > 0 && depth_noise_sigma <= 0.1,
          "depth_noise_sigma", depth_noise_sigma, "a sigma in (0, 0.1] m");
  require(finite(top_slice_sigmas) && top_slice_sigmas > 0 && top_slice_sigmas <= 100,
          "top_slice_sigmas", top_slice_sigmas, "a count in (0, 100]");
  require(top_slice_iters >= 1 && top_slice_iters <= 1000, "top_slice_iters", top_slice_iters,
          "an integer in [1, 1000]");
  require(n_theta >= 2 && n_theta <= 100000, "n_theta", n_theta, "an integer in [2, 100000]");
  require(finite(width_tol_m) && width_tol_m >= 0 && width_tol_m <= 1, "width_tol_m",
          width_tol_m, "a tolerance in [0, 1] m");
  require(finite(isotropy_ratio_max) && isotropy_ratio_max >= 1 && isotropy_ratio_max <= 100,
          "isotropy_ratio_max", isotropy_ratio_max, "a ratio in [1, 100]");
  require(finite(gripper_open) && gripper_open > 0 && gripper_open <= 1, "gripper_open",
          gripper_open, "an opening in (0, 1] m");
  require(finite(min_graspable_width) && min_graspable_width >= 0 &&
              min_graspable_width <= gripper_open,
          "min_graspable_width", min_graspable_width, "a width in [0, gripper_open] m");
  require(finite(min_height) && min_height >= 0 && min_height <= 10, "min_height", min_height,
          "a height in [0, 10] m");
  require(finite(resting_margin) && resting_margin >= 0 && resting_margin <= 1, "resting_margin",
          resting_margin, "a margin in [0, 1] m");
  require(finite(side_seen_sigmas) && side_seen_sigmas >= 0 && side_seen_sigmas <= 1000,
          "side_seen_sigmas", side_seen_sigmas, "a count in [0, 1000]");
  require(window >= 1 && window <= 10000, "window", window, "an integer in [1, 10000]");
  require(finite(assoc_gate_frac) && assoc_gate_frac > 0 && assoc_gate_frac <= 10,
          "assoc_gate_frac", assoc_gate_frac, "a fraction in (0, 10]");
  require(finite(max_age_s) && max_age_s > 0, "max_age_s", max_age_s, "a duration > 0 s");
  require(finite(nadir_hold_s) && nadir_hold_s > 0, "nadir_hold_s", nadir_hold_s,
          "a duration > 0 s");
  require(finite(nadir_angle_max_deg) && nadir_angle_max_deg >= 0 && nadir_angle_max_deg < 90,
          "nadir_angle_max_deg", nadir_angle_max_deg, "an angle in [0, 90) deg");
  require(finite(nadir_min_distance_m) && nadir_min_distance_m >= 0 && nadir_min_distance_m <= 10,
          "nadir_min_distance_m", nadir_min_distance_m, "a distance in [0, 10] m");
}

}  // namespace grasp_core
