// method.md §1.1 — one horizontal-constrained RANSAC plane, refined by least squares.
//
// The search is PCL's sample consensus: pcl::SampleConsensusModelPerpendicularPlane
// (axis +z, eps angle = plane_max_tilt_deg) driven by pcl::RandomSampleConsensus
// (threshold = plane_dist_thresh). How PCL is configured so that it honours method.md §1.1
// (fixed iteration count, seeded sampling, orientation) is documented at
// fit_plane_ransac() below.
#pragma once

#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>

namespace grasp_core {

/// Result of one plane search.
struct PlaneFit {
  Plane plane;           ///< the plane to use: the LS refinement, or ransac_plane if the
                         ///< refinement failed the post-refinement tilt re-check
  Plane ransac_plane;    ///< best RANSAC model, |n| = 1, n_z > 0
  int inliers = 0;       ///< inliers (|d| < plane_dist_thresh) of the best RANSAC model
                         ///< within the searched point set
  bool refined = false;  ///< true if `plane` is the least-squares refinement
  int iterations = 0;    ///< RANSAC models evaluated
};

/// method.md §1.1 on every valid row of `points`: rows with a NaN/Inf or a |coordinate| beyond
/// params.max_abs_coordinate_m are ignored.
///
/// - Minimal sample: 3 distinct points (PCL draws them without replacement by a partial
///   shuffle of the index list). Collinear samples (|(p2-p1)x(p3-p1)| below PCL's float
///   precision, 1e-5 m^2) are discarded by PCL and redrawn; they do not count as iterations.
/// - Tilt: PCL's perpendicular-plane model rejects a model whose normal is more than
///   plane_max_tilt_deg from +/-z, which is the rule of method.md §1.1 (n turned to n_z >= 0,
///   discarded if n_z < cos(tilt)). Such a model counts as an iteration with score 0.
/// - Iterations: exactly plane_ransac_iters scored models. PCL's adaptive early
///   termination is switched off (probability 1 => k = +inf) and PCL's off-by-one
///   (`iterations > max_iterations` test) is compensated. If samples keep failing PCL
///   stops after 10 x plane_ransac_iters rejected samples ("no model").
/// - Ties: PCL replaces the best model only on a strictly larger score, so the first best
///   model is kept.
/// - Seeding: the sampling RNG of the PCL model is re-seeded from `seed`: same input and
///   seed => same result.
/// - Refinement: least-squares plane through the inliers of the best model within
///   `points` (centroid + eigenvector of the smallest eigenvalue of the inlier scatter
///   matrix, computed in double), re-oriented to n_z > 0. If the refined normal is more
///   than plane_max_tilt_deg from +z (degenerate inlier set), the unrefined RANSAC model
///   is kept (refined = false).
/// Returns std::nullopt for fewer than 3 valid points or when no valid model was found.
/// Throws std::invalid_argument (naming the parameter) if `params` is invalid.
std::optional<PlaneFit> fit_plane_ransac(const PointsD& points, const SceneFilterParams& params,
                                         std::uint64_t seed);
/// Same, float input.
std::optional<PlaneFit> fit_plane_ransac(const PointsF& points, const SceneFilterParams& params,
                                         std::uint64_t seed);

}  // namespace grasp_core
