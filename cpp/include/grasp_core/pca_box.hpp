// PCA oriented bounding box (method.md §2.5): a diagnostic only, it never drives the grasp.
#pragma once

#include <optional>
#include <string>

#include "grasp_core/types.hpp"

namespace grasp_core {

/// An oriented box from principal component analysis.
struct PcaBox {
  Vec3 center = Vec3::Zero();       ///< centroid + R (lo + hi) / 2 (not the centroid) [m]
  Mat3 R = Mat3::Identity();        ///< columns = axes, eigenvalue descending, det +1
  Vec3 extents = Vec3::Zero();      ///< hi - lo along each column of R [m]
  Vec3 eigenvalues = Vec3::Zero();  ///< covariance eigenvalues, descending [m^2]
};

/// Collinearity threshold of method.md §2.5: lambda2 <= kPcaCollinearRatio * lambda1 fails.
constexpr double kPcaCollinearRatio = 1e-6;

/// PCA box of N x 3 points (covariance with N - 1).
///
/// Returns no value (and a reason in *why_not when given) for: fewer than 3 points,
/// a non-finite covariance (any NaN/Inf input row makes it so), coincident points
/// (lambda1 <= 0) and collinear points (lambda2 <= 1e-6 lambda1). Coplanar points are valid.
std::optional<PcaBox> pca_box(const PointsD& pts, std::string* why_not = nullptr);

/// Angle between the PCA minor axis (column 2) and the plane normal n, using |dot| [deg].
/// 0 for a flat top face seen from directly above. NaN if n is zero / non-finite.
double pca_tilt_deg(const PcaBox& box, const Vec3& n);

}  // namespace grasp_core
