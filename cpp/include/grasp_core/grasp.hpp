// Grasp pose math and view quality (method.md §3).
#pragma once

#include <optional>

#include "grasp_core/object_estimate.hpp"
#include "grasp_core/types.hpp"

namespace grasp_core {

/// The single coupling point between "where to grasp" and "how to move".
/// Convention: position = contact point (the estimate's centre); column 0 of R = approach
/// axis pointing INTO the object (-n for a top-down grasp); column 2 = closing axis
/// (its sign is irrelevant); det R = +1.
struct BestGrasp {
  Mat3 R = Mat3::Identity();
  Vec3 position = Vec3::Zero();  ///< [m], world
  double width_m = 0.0;          ///< opening needed: the estimate's width [m]
  double score = 0.0;            ///< always 0 for this geometric method (no fake confidence)
};

/// Below this norm a cross product / projection counts as zero (method.md §3's "~0", 1e-6).
constexpr double kDegenerateNorm = 1e-6;
/// Below this distance object and camera coincide (method.md §3).
constexpr double kCoincidentDistance_m = 1e-9;

/// R = [n, normalize(closing x n), closing] with closing = R_box[:,0] (method.md §3).
/// Returns no value when |closing x n| < kDegenerateNorm. The third column is rebuilt as
/// col0 x col1 (= closing when closing is perpendicular to n) so det is exactly +1.
std::optional<Mat3> top_down_rotation(const Mat3& R_box, const Vec3& n);

/// BestGrasp from an estimate: top_down_rotation with columns 0 and 2 negated,
/// position = centre, width = estimate width, score 0. No value if the rotation fails.
/// Guards (grasp_ok) are NOT checked here: selection does that (method.md §5).
std::optional<BestGrasp> best_grasp_from_estimate(const ObjectEstimate& est, const Plane& plane);

/// Camera pose above an object (method.md §3): z_c = -n; x_c = the ready camera's x projected
/// into the plane (fallback u of in_plane_basis when shorter than kDegenerateNorm),
/// normalised; y_c = z_c x x_c; position = (object x, object y, ready camera z).
Pose camera_above_pose(const Vec3& object, const Plane& plane, const Pose& ready_camera_world);

/// Flange target that puts the camera at camera_above_pose:
/// R_f = R_wc R_lc^T, p_f = p_c - R_f t_lc, with (R_lc, t_lc) = camera_in_flange, the
/// camera pose in the flange frame (from the robot model; never hard-coded here).
Pose camera_above_flange_target(const Vec3& object, const Plane& plane,
                                const Pose& ready_camera_world, const Pose& camera_in_flange);

/// View quality of one observation and its angle.
struct ViewAssessment {
  ViewQuality quality = ViewQuality::OBLIQUE;
  double angle_deg = 0.0;  ///< angle(object - camera, -n) [deg]; NaN when coincident
};

/// Delta = angle(object - camera_position, -n); Delta <= nadir_angle_max_deg -> NADIR,
/// else OBLIQUE; OBLIQUE (angle NaN) when |object - camera| < kCoincidentDistance_m.
ViewAssessment assess_view(const Vec3& object, const Vec3& camera_position, const Vec3& n,
                           double nadir_angle_max_deg);

}  // namespace grasp_core
