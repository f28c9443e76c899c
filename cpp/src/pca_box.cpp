// PCA oriented bounding box (method.md §2.5).
#include "grasp_core/pca_box.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace grasp_core {
namespace {

std::optional<PcaBox> fail(std::string* why_not, const char* reason) {
  if (why_not) *why_not = reason;
  return std::nullopt;
}

}  // namespace

std::optional<PcaBox> pca_box(const PointsD& pts, std::string* why_not) {
  const Eigen::Index n = pts.rows();
  if (n < 3) return fail(why_not, "PCA failed: fewer than 3 points");

  const Vec3 centroid = pts.colwise().mean().transpose();
  const PointsD centred = pts.rowwise() - centroid.transpose();
  const Mat3 cov = (centred.transpose() * centred) / static_cast<double>(n - 1);
  if (!cov.allFinite()) return fail(why_not, "PCA failed: non-finite covariance");

  Eigen::SelfAdjointEigenSolver<Mat3> solver(cov);
  if (solver.info() != Eigen::Success) return fail(why_not, "PCA failed: eigen-decomposition");

  // Eigen returns ascending eigenvalues: reverse to descending.
  PcaBox box;
  for (int k = 0; k < 3; ++k) {
    box.eigenvalues(k) = solver.eigenvalues()(2 - k);
    box.R.col(k) = solver.eigenvectors().col(2 - k);
  }
  const double l1 = box.eigenvalues(0);
  const double l2 = box.eigenvalues(1);
  if (!(l1 > 0.0)) return fail(why_not, "PCA failed: all points coincide");
  if (l2 <= kPcaCollinearRatio * l1) return fail(why_not, "PCA failed: points are collinear");
  if (box.R.determinant() < 0.0) box.R.col(2) = -box.R.col(2);

  // Box from the projections on the axes; centre = centroid + R (lo + hi) / 2.
  const Eigen::Matrix<double, Eigen::Dynamic, 3> proj = centred * box.R;
  const Vec3 lo = proj.colwise().minCoeff().transpose();
  const Vec3 hi = proj.colwise().maxCoeff().transpose();
  box.extents = hi - lo;
  box.center = centroid + box.R * (0.5 * (lo + hi));
  if (why_not) why_not->clear();
  return box;
}

double pca_tilt_deg(const PcaBox& box, const Vec3& n) {
  const double nn = n.norm();
  if (!(nn > 0.0) || !std::isfinite(nn)) return std::numeric_limits<double>::quiet_NaN();
  const double c = std::clamp(std::abs(box.R.col(2).dot(n) / nn), 0.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

}  // namespace grasp_core
