// method.md §1.1 — see plane_fit.hpp for how PCL's RANSAC is configured to honour the method.
#include "grasp_core/plane_fit.hpp"
#include "simd_clones.hpp"

#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_perpendicular_plane.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

namespace grasp_core {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// Smallest float f with (float x < f) <=> (double(x) < t) for every float x: PCL compares
/// float distances with a double threshold; we keep that exact semantics in float.
float float_threshold(double t) {
  float f = static_cast<float>(t);
  if (static_cast<double>(f) < t) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// Number of points i < n with |a x_i + b y_i + c z_i + d| < t (float, PCL's test).
GRASP_SIMD_CLONES unsigned int count_within(const float* __restrict x, const float* __restrict y,
                                           const float* __restrict z, std::size_t n, float a,
                                           float b, float c, float d, float t) {
  unsigned int cnt = 0;
  for (std::size_t i = 0; i < n; ++i) cnt += std::abs(a * x[i] + b * y[i] + c * z[i] + d) < t;
  return cnt;
}

/// PCL's perpendicular-plane model with two changes that do not alter its semantics:
///  - the sampling RNG is seeded by us (PCL seeds it with a fixed 12345 or the wall clock;
///    rng_alg_ is the protected generator drawIndexSample uses);
///  - countWithinDistance (the RANSAC scoring loop, ~all of the run time) is a tight loop
///    compiled with our flags. The Debian build of PCL's scalar loop costs ~11 ns/point on
///    this machine class (a store-forwarding stall), ~10x the budget of method.md §1.6's
///    200 iterations x 4000 points x 3 planes per frame. Same test as PCL:
///    model valid (tilt) and |a x + b y + c z + d| < threshold, float distances.
class SeededPerpendicularPlane : public pcl::SampleConsensusModelPerpendicularPlane<pcl::PointXYZ> {
 public:
  SeededPerpendicularPlane(const Cloud::ConstPtr& cloud, std::uint32_t seed)
      : pcl::SampleConsensusModelPerpendicularPlane<pcl::PointXYZ>(cloud, /*random=*/false) {
    rng_alg_.seed(seed);
    // Structure-of-arrays copy of the searched points for the scoring loop.
    xs_.reserve(cloud->size());
    ys_.reserve(cloud->size());
    zs_.reserve(cloud->size());
    for (const auto& p : *cloud) {
      xs_.push_back(p.x);
      ys_.push_back(p.y);
      zs_.push_back(p.z);
    }
  }

  std::size_t countWithinDistance(const Eigen::VectorXf& model_coefficients,
                                  const double threshold) const override {
    if (model_coefficients.size() != 4 || !isModelValid(model_coefficients)) return 0;
    const float a = model_coefficients[0], b = model_coefficients[1],
                c = model_coefficients[2], d = model_coefficients[3];
    const float t = float_threshold(threshold);
    std::size_t count = 0;
    if (indices_->size() == xs_.size()) {  // the constructor's identity indices: SoA loop
      return count_within(xs_.data(), ys_.data(), zs_.data(), xs_.size(), a, b, c, d, t);
    }
    const Cloud& cloud = *input_;
    for (const auto i : *indices_) {
      const pcl::PointXYZ& p = cloud[static_cast<std::size_t>(i)];
      count += std::abs(a * p.x + b * p.y + c * p.z + d) < t ? 1 : 0;
    }
    return count;
  }

 private:
  std::vector<float> xs_, ys_, zs_;
};

/// PCL's RANSAC, exposing the number of scored models.
class CountingRansac : public pcl::RandomSampleConsensus<pcl::PointXYZ> {
 public:
  using pcl::RandomSampleConsensus<pcl::PointXYZ>::RandomSampleConsensus;
  int scored_models() const { return iterations_; }
};

/// PCL reports routine outcomes ("RANSAC found no model", collinear samples) with
/// PCL_ERROR on stderr; for us they are normal results. PCL's verbosity is one process-wide
/// variable, so the quiet scope is reference-counted under a mutex: the first scope to open
/// saves the level, the last one to close restores it (safe with concurrent filters).
class QuietPcl {
 public:
  QuietPcl() {
    const std::lock_guard<std::mutex> lock(mutex());
    if (depth()++ == 0) {
      saved() = pcl::console::getVerbosityLevel();
      pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    }
  }
  ~QuietPcl() {
    const std::lock_guard<std::mutex> lock(mutex());
    if (--depth() == 0) pcl::console::setVerbosityLevel(saved());
  }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static int& depth() {
    static int d = 0;
    return d;
  }
  static pcl::console::VERBOSITY_LEVEL& saved() {
    static pcl::console::VERBOSITY_LEVEL v = pcl::console::L_INFO;
    return v;
  }
};

/// SplitMix64 finaliser: spreads a 64-bit seed onto the 32 bits boost::mt19937 accepts.
std::uint32_t mix_seed(std::uint64_t seed) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<std::uint32_t>(z ^ (z >> 32));
}

/// The valid rows (finite, every |coordinate| <= bound, checked on the input values) as float.
template <typename Points>
Cloud::Ptr finite_cloud(const Points& points, double bound) {
  auto cloud = std::make_shared<Cloud>();
  cloud->reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double x = points(i, 0), y = points(i, 1), z = points(i, 2);
    if (!within_bound(x, y, z, bound)) continue;  // NaN/Inf or out of range
    cloud->push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)));
  }
  return cloud;
}

/// Least-squares plane through cloud[idx] (double precision), n_z >= 0; nullopt if degenerate.
std::optional<Plane> least_squares_plane(const Cloud& cloud, const pcl::Indices& idx) {
  if (idx.size() < 3) return std::nullopt;
  Vec3 centroid = Vec3::Zero();
  for (const auto i : idx) centroid += cloud[i].getVector3fMap().cast<double>();
  centroid /= static_cast<double>(idx.size());
  Mat3 scatter = Mat3::Zero();
  for (const auto i : idx) {
    const Vec3 d = cloud[i].getVector3fMap().cast<double>() - centroid;
    scatter.noalias() += d * d.transpose();
  }
  // Eigenvector of the smallest eigenvalue of the scatter matrix = right singular vector of
  // the smallest singular value of the centred inliers.
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  if (eig.info() != Eigen::Success) return std::nullopt;
  Vec3 n = eig.eigenvectors().col(0);
  const double norm = n.norm();
  if (!std::isfinite(norm) || norm <= 0.0) return std::nullopt;
  n /= norm;
  if (n.z() < 0.0) n = -n;
  Plane plane;
  plane.n = n;
  plane.c = -n.dot(centroid);
  if (!std::isfinite(plane.c)) return std::nullopt;
  return plane;
}

std::optional<PlaneFit> fit_cloud(const Cloud::ConstPtr& cloud, const SceneFilterParams& params,
                                  std::uint64_t seed) {
  // Also guards PCL: an eps angle of 0 would silently switch its tilt check off.
  params.validate();
  if (cloud->size() < 3 || params.plane_ransac_iters < 1) return std::nullopt;
  const double max_tilt_rad = params.plane_max_tilt_deg * M_PI / 180.0;

  QuietPcl quiet;
  auto model = std::make_shared<SeededPerpendicularPlane>(cloud, mix_seed(seed));
  model->setAxis(Eigen::Vector3f::UnitZ());
  model->setEpsAngle(max_tilt_rad);

  CountingRansac ransac(model, /*random=*/false);
  ransac.setDistanceThreshold(params.plane_dist_thresh);
  // PCL stops once `iterations > max_iterations`, i.e. after max_iterations + 1 models.
  ransac.setMaxIterations(params.plane_ransac_iters - 1);
  // probability 1 => log(1 - p) = -inf => adaptive bound k = +inf: no early termination.
  ransac.setProbability(1.0);
  ransac.setNumberOfThreads(-1);  // sequential: deterministic
  if (!ransac.computeModel()) return std::nullopt;

  Eigen::VectorXf coeff;
  ransac.getModelCoefficients(coeff);
  pcl::Indices inliers;
  ransac.getInliers(inliers);
  if (coeff.size() != 4 || inliers.empty()) return std::nullopt;

  PlaneFit fit;
  Vec3 n = coeff.head<3>().cast<double>();
  double c = static_cast<double>(coeff[3]);
  const double norm = n.norm();
  if (!std::isfinite(norm) || norm <= 0.0 || !std::isfinite(c)) return std::nullopt;
  n /= norm;
  c /= norm;
  if (n.z() < 0.0) {  // method.md §0/1.1: orient n_z >= 0
    n = -n;
    c = -c;
  }
  fit.ransac_plane.n = n;
  fit.ransac_plane.c = c;
  fit.inliers = static_cast<int>(inliers.size());
  fit.iterations = ransac.scored_models();
  fit.plane = fit.ransac_plane;

  const std::optional<Plane> refined = least_squares_plane(*cloud, inliers);
  // Post-refinement tilt re-check: a degenerate inlier set can tip the LS normal over.
  if (refined && refined->n.z() >= std::cos(max_tilt_rad)) {
    fit.plane = *refined;
    fit.refined = true;
  }
  return fit;
}

}  // namespace

std::optional<PlaneFit> fit_plane_ransac(const PointsD& points, const SceneFilterParams& params,
                                         std::uint64_t seed) {
  params.validate();
  return fit_cloud(finite_cloud(points, params.max_abs_coordinate_m), params, seed);
}

std::optional<PlaneFit> fit_plane_ransac(const PointsF& points, const SceneFilterParams& params,
                                         std::uint64_t seed) {
  params.validate();
  return fit_cloud(finite_cloud(points, params.max_abs_coordinate_m), params, seed);
}

}  // namespace grasp_core
