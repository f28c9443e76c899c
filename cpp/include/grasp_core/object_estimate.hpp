// Object estimate of one cluster above the table plane (method.md §2.1-2.4, 2.6).
//
// The closing direction comes from a horizontal width scan, not from PCA; the PCA box
// (pca_box.hpp) is carried along as a diagnostic only. Angles theta are in [0, pi):
// theta and theta + pi are the same line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "grasp_core/params.hpp"
#include "grasp_core/pca_box.hpp"
#include "grasp_core/types.hpp"

namespace grasp_core {

/// Result of estimating one cluster.
struct ObjectEstimate {
  Vec3 center = Vec3::Zero();   ///< box centre: footprint midpoint + height/2 along n [m]
  Mat3 R_box = Mat3::Identity();  ///< [e_theta, e_theta_perp, n], det +1
  Vec3 extents = Vec3::Zero();  ///< (width, perp_width, height) [m]
  double theta_rad = 0.0;       ///< closing direction in the (u, v) basis, [0, pi)
  double width_m = 0.0;         ///< footprint span along e_theta [m]
  double perp_width_m = 0.0;    ///< footprint span along e_theta_perp [m]
  double height_m = 0.0;        ///< slice-median top above the plane [m]
  double anisotropy = 1.0;      ///< max ext / min ext of the width scan (inf if min ~ 0)
  bool yaw_defined = false;     ///< anisotropy >= isotropy_ratio_max (diagnostic)
  PcaBox pca;                   ///< PCA box (diagnostic)
  double pca_tilt_deg = 0.0;    ///< angle(PCA minor axis, n) [deg]
  double lowest_m = 0.0;        ///< min signed distance of the points to the plane [m]
  bool resting = true;          ///< lowest point within band + resting_margin (or undetermined)
  bool height_ok = true;        ///< height >= min_height
  bool width_ok = true;         ///< min_graspable_width <= width <= gripper_open
  bool grasp_ok = true;         ///< resting && height_ok && width_ok
  std::string resting_note;     ///< the "floating/stacked" note, empty when resting
  std::vector<std::string> notes;               ///< hard notes (refusal reasons), English
  std::vector<std::string> undetermined_notes;  ///< informative only, never a refusal
  int num_points = 0;           ///< valid points used (finite, within the coordinate bound)
};

/// An estimate, or the reason there is none (e.g. PCA failed, too few points).
struct EstimateResult {
  std::optional<ObjectEstimate> estimate;
  std::string failure;  ///< empty on success
};

/// Estimate one object from its cluster (method.md §2).
///
/// @param pts        cluster points in world (rows with a NaN/Inf or a |coordinate| beyond
///                   max_abs_coordinate_m are ignored defensively)
/// @param plane      the locked table plane (n need not be exactly unit; it is normalised)
/// @param p          validated OBB parameters
/// @param theta_prev prior closing direction [rad] (tracker's smoothed theta), if any
/// @param band       the scene filter's band [m]; unknown -> resting is undetermined
/// @param max_abs_coordinate_m  sane coordinate bound [m] (SceneFilterParams' value in the
///                   per-frame path)
///
/// No estimate (a failure text instead) for: an invalid plane, fewer than 3 valid points,
/// a failed PCA (method.md §2.5), and (ours) a cluster that is not above the plane, i.e. whose
/// slice-median top is below it (height < 0): method.md §2 estimates objects standing on the
/// plane, and a box with a negative height is no box; the guards of 2.6 (e.g. "too low")
/// judge estimates that exist, with 0 <= height.
///
/// Resting (2.6) is judged only when the sides are visible, which here means the lowest
/// point lies more than (top_slice_sigmas + side_seen_sigmas) * depth_noise_sigma below the
/// slice-median top (14 mm with defaults) (ours: the literal max d - min d > 3 sigma is met
/// by the noise of a flat top face alone). Otherwise, or with band unknown, resting = true
/// and an undetermined note is added.
EstimateResult estimate_object(const PointsD& pts, const Plane& plane, const ObbParams& p,
                               std::optional<double> theta_prev = std::nullopt,
                               std::optional<double> band = std::nullopt,
                               double max_abs_coordinate_m = kDefaultMaxAbsCoordinate_m);

/// The part of method.md §2 for one cluster that does not depend on theta_prev: the valid points,
/// the PCA box (2.5), the decomposition (2.1), the slice-median height (2.4) and the width
/// scan (2.2). method.md §4's two-pass estimation computes it once per cluster and finishes it
/// twice (without, then with the tracker's prior), so the second pass repeats none of the
/// per-point work; the results are exactly those of two full estimate_object() calls.
struct PreparedEstimate {
  std::string failure;       ///< non-empty: no estimate for this cluster (the reason)
  ObjectEstimate partial;    ///< num_points, pca, pca_tilt_deg, height_m, anisotropy,
                             ///< yaw_defined and lowest_m filled in
  Vec3 n = Vec3::UnitZ();    ///< unit plane normal
  Vec3 u = Vec3::UnitX();    ///< in-plane basis, u x v = n
  Vec3 v = Vec3::UnitY();
  Vec3 p0 = Vec3::Zero();    ///< anchor -c n [m]
  std::vector<double> a, b;  ///< in-plane coordinates of every valid point [m]
  std::vector<double> ext;   ///< width scan ext(theta_t), t = 0..n_theta-1 [m]
};

/// First half of estimate_object(): everything that does not depend on theta_prev or band.
/// Same arguments and failures (in PreparedEstimate::failure) as estimate_object().
PreparedEstimate prepare_estimate(const PointsD& pts, const Plane& plane, const ObbParams& p,
                                  double max_abs_coordinate_m = kDefaultMaxAbsCoordinate_m);

/// Second half of estimate_object(): closing direction (2.3), box and centre (2.4) and
/// guards (2.6) of a prepared cluster; a failed preparation gives its failure.
EstimateResult finish_estimate(const PreparedEstimate& prep, const ObbParams& p,
                               std::optional<double> theta_prev = std::nullopt,
                               std::optional<double> band = std::nullopt);

/// Recompute height_ok, width_ok, grasp_ok and the hard notes (resting_note first, then
/// the size notes) from the estimate's current width_m / height_m / resting. Used by
/// estimate_object and by the tracker after smoothing.
void apply_size_guards(ObjectEstimate& est, const ObbParams& p);

// ---- fine-grained steps (bound for tests and users) ------------------------------------

/// Deterministic in-plane orthonormal basis with u x v = n (n is normalised first).
/// u = the projection of world x into the plane (world y if n is within ~25.8 deg of x).
/// For n = +z this gives u = x, v = y.
void in_plane_basis(const Vec3& n, Vec3* u, Vec3* v);

/// theta_t = pi t / T.
double scan_angle_rad(int t, int n_theta);

/// ext(theta_t) = max(a cos + b sin) - min(...) for t = 0..n_theta-1. Empty input -> zeros.
std::vector<double> width_scan(const std::vector<double>& a, const std::vector<double>& b,
                               int n_theta);

/// Span of (a cos theta + b sin theta): the footprint width along one direction [m].
double extent_along(const std::vector<double>& a, const std::vector<double>& b, double theta_rad);

/// max ext / min ext; +inf when min ext ~ 0 (or the scan is empty).
double anisotropy_ratio(const std::vector<double>& ext);

/// One run of consecutive candidate indices (method.md §2.3).
struct DirectionRun {
  int first = 0;             ///< first index in circular order
  int last = 0;              ///< last index; last < first for a run merged across the wrap
  std::vector<int> indices;  ///< members in circular order (first ... last)
  double theta_rad = 0.0;    ///< circular median mod pi of the members' angles, [0, pi)
  double width_m = 0.0;      ///< the run's minimum ext [m]
};

/// Runs of candidates (ext <= min ext + width_tol_m) over a scan of ext.size() angles;
/// index 0 and T-1 are neighbours (a run touching both ends is merged). If every index is
/// a candidate there is one run 0..T-1. Sorted by theta_rad ascending.
std::vector<DirectionRun> direction_runs(const std::vector<double>& ext, double width_tol_m);

/// The chosen closing direction and every run considered.
struct DirectionChoice {
  double theta_rad = 0.0;  ///< chosen run's theta, [0, pi)
  double width_m = 0.0;    ///< chosen run's minimum ext [m]
  int chosen = -1;         ///< index into runs (-1 if ext is empty)
  std::vector<DirectionRun> runs;
};

/// method.md §2.3: with theta_prev the run nearest to it (mod-pi distance; ties -> smaller theta);
/// without, among runs within width_tol_m of the smallest run width the smallest theta.
DirectionChoice choose_direction(const std::vector<double>& ext, double width_tol_m,
                                 std::optional<double> theta_prev);

/// Circular median mod pi: offsets (a - reference) wrapped into [-pi/2, pi/2), median of
/// the offsets, + reference, wrapped into [0, pi). The reference should be one of the
/// angles. Empty -> reference wrapped into [0, pi).
double circular_median_mod_pi(const std::vector<double>& angles_rad, double reference_rad);

/// Median; an even count gives the mean of the two middle values. Empty -> NaN.
double median(std::vector<double> v);

/// |((a - b + pi/2) mod pi) - pi/2|: distance of two lines' angles, in [0, pi/2].
double angle_dist_mod_pi(double a_rad, double b_rad);

/// x wrapped into [0, pi).
double wrap_mod_pi(double x_rad);

/// Slice-median top (method.md §2.4): top = max d; up to iters times keep d >= top - k sigma,
/// stop if fewer than 3 kept, top = median(kept), stop when unchanged. Empty -> NaN.
double slice_median_top(const std::vector<double>& d, double sigma_m, double slice_sigmas,
                        int iters);

}  // namespace grasp_core
