// method.md §1.2–1.5 — the per-frame scene filter: sequential plane extraction, table choice
// (dominance then height), band split, Euclidean clustering with extent filters, a label
// for every input row, and the plane persistence that makes the table a session constant.
#pragma once

#include "grasp_core/clustering.hpp"
#include "grasp_core/organized_segmentation.hpp"
#include "grasp_core/params.hpp"
#include "grasp_core/plane_fit.hpp"
#include "grasp_core/plane_persistence.hpp"
#include "grasp_core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace grasp_core {

/// (ours) What a frame may say besides its points. All optional.
struct FrameContext {
  /// > 0: the frame is organized, row v * image_width + u is pixel (u, v) (NaN rows where
  /// invalid), and the candidates are segmented over the image (organized_segmentation.hpp)
  /// when params.segment_organized; 0: Euclidean clustering (method.md §1.4).
  int image_width = 0;
  /// nullptr or (rows) x 3 bytes: the colour of each row's pixel (row-major RGB), used by the
  /// organized segmentation's colour test.
  const std::uint8_t* rgb = nullptr;
  /// The camera position at capture: needed by the organized segmentation (ranges) and the
  /// range-dependent minimum object height; without it neither is used.
  std::optional<Vec3> camera_position;
};

/// One plane of the sequential extraction (method.md §1.2).
struct PlaneCandidate {
  Plane plane;                ///< refined plane (or the RANSAC model, see PlaneFit::refined)
  int count_whole = 0;        ///< method.md §1.2 `count`: inliers |d| < plane_dist_thresh on the WHOLE frame cloud
  int subsample_inliers = 0;  ///< inliers of the RANSAC model within the search subsample
  int subsample_size = 0;     ///< size of that subsample
  int removed = 0;            ///< points removed from the remainder (inliers of `plane` in it)
  bool refined = false;       ///< PlaneFit::refined
};

/// method.md §1.2 on the valid rows of a strided float array (row i at xyz + i*stride, stride >= 3):
/// finite, with every |coordinate| <= params.max_abs_coordinate_m.
/// Plane k searches a subsample of at most plane_fit_max_points drawn without replacement,
/// with a std::mt19937_64 seeded from (seed, k), from the points not yet assigned to a
/// plane; accepted if the RANSAC model has >= plane_min_inlier_ratio x subsample size
/// inliers in the subsample; its inliers (w.r.t. the plane kept) are removed from the whole
/// remainder. Stops after plane_max_count planes, at the first rejected/absent model, or
/// when fewer than 3 points remain. Non-finite rows are skipped; coordinates are processed
/// as float (double input is converted). Throws std::invalid_argument on invalid params,
/// stride < 3 or a null buffer with n_rows > 0.
/// (The PointsF/PointsD overloads need a concrete matrix: an Eigen expression such as
/// PointsD::Constant(...) matches both and is ambiguous.)
std::vector<PlaneCandidate> extract_planes(const float* xyz, std::size_t n_rows,
                                           std::size_t row_stride_floats,
                                           const SceneFilterParams& params, std::uint64_t seed);
std::vector<PlaneCandidate> extract_planes(const PointsF& points, const SceneFilterParams& params,
                                           std::uint64_t seed);
std::vector<PlaneCandidate> extract_planes(const PointsD& points, const SceneFilterParams& params,
                                           std::uint64_t seed);

/// method.md §1.3: among planes with count_whole >= dominance x max count_whole take the highest
/// (largest height_m()); ties keep the earlier plane. Returns its index, or -1 if `planes`
/// is empty.
int choose_table(const std::vector<PlaneCandidate>& planes, double dominance);

/// Everything the scene filter computed for one frame.
struct SceneFilterResult {
  /// One per INPUT row: kLabelInvalid (NaN/Inf row, or a |coordinate| beyond
  /// max_abs_coordinate_m), kLabelEnvironment, or an accepted
  /// object group id >= 0 (frame-local, compact 0..K-1, see euclidean_clusters()).
  /// When environment_emitted is false (before the first lock) every valid row is
  /// kLabelEnvironment but no environment cloud should be published.
  std::vector<int> labels;
  bool environment_emitted = false;  ///< false before the first lock unless the fallback fired
  bool fallback = false;             ///< init-frames fallback: whole cloud is environment
  std::optional<Plane> table;        ///< the plane used this frame (the lock), latched
  std::optional<Plane> fit;          ///< this frame's own table fit (diagnostic)
  double band = 0.0;                 ///< method.md §1.4 band [m] (session constant)
  std::vector<PlaneCandidate> planes;   ///< all planes extracted this frame
  int table_index = -1;              ///< index of the table in planes, -1 if none
  int num_valid = 0;                 ///< rows used: finite and within the coordinate bound
  int num_invalid = 0;               ///< rows dropped (kLabelInvalid): NaN/Inf or out of range
  int num_out_of_range = 0;          ///< of num_invalid: finite rows with a |coordinate| > max_abs_coordinate_m
  double max_abs_coordinate_m = 0.0; ///< the coordinate bound applied this frame [m]
  int num_candidates = 0;            ///< valid points above the band (clustering input)
  std::vector<int> cluster_ids;      ///< accepted object group ids this frame (ascending)
  std::vector<ClusterInfo> clusters; ///< every component >= cluster_min_points (diagnostic)
  std::vector<int> object_rows;      ///< input rows with an object label (>= 0), ascending
  PlaneDecision decision = PlaneDecision::kNoPlane;
  PersistenceState persistence;      ///< lock state after this frame
  std::vector<FrameEvent> events;    ///< log lines for the caller
  double ms_pack = 0.0;              ///< validity check, packing and labels of every row [ms]
  double ms_plane = 0.0;             ///< plane extraction + table choice + persistence [ms]
  double ms_cluster = 0.0;           ///< band split + clustering [ms]
  double ms_total = 0.0;             ///< whole process() call [ms]
  bool organized = false;            ///< the candidates were segmented over the image
  int num_too_low = 0;               ///< clusters refused by the range-dependent minimum height
};

/// Reusable whole-frame buffers of the scene filter (ours: frames of a constant size
/// allocate nothing for them). Their contents never carry over from one frame to the next.
struct SceneFilterWorkspace {
  std::vector<float> x, y, z;        ///< valid points, packed (structure of arrays)
  std::vector<int> rows;             ///< input row of each packed point
  std::vector<int> remainder;        ///< packed indices not yet assigned to a plane
  std::vector<std::uint8_t> inlier;  ///< per packed point: inlier of the current plane
  std::vector<float> cand_xyz;       ///< clustering input: points above the band, xyz interleaved
  std::vector<int> cand_rows;        ///< input row of each candidate
  OrganizedWorkspace organized;      ///< buffers of the organized segmentation
};

/// The per-frame scene filter (method.md §1). Owns the plane persistence, so one instance per
/// camera session. Frame k's plane search is seeded with (params.seed, k): a session is
/// reproducible.
class SceneFilter {
 public:
  /// Validates `params` (std::invalid_argument naming the parameter).
  explicit SceneFilter(const SceneFilterParams& params);

  /// Process one N x 3 frame in `world`. Row i starts at xyz + i * row_stride (in elements,
  /// >= 3; a numpy (N,3) C-contiguous array has stride 3). No copy of the caller's array is
  /// kept. Throws std::invalid_argument on stride < 3 or xyz == nullptr with n_rows > 0.
  /// Rows with a NaN/Inf or a |coordinate| > params.max_abs_coordinate_m are dropped
  /// (kLabelInvalid, counted in num_invalid; the latter also in num_out_of_range, with a
  /// WARNING event the first time in a session and DEBUG after). The check is made on the
  /// input values, then coordinates are processed as float (float resolution is < 0.1 um
  /// at workspace scale).
  /// Every call is one frame: it advances frame_index() and the persistence state.
  /// `ctx`: organization, colour and camera position of the frame (see FrameContext).
  SceneFilterResult process(const float* xyz, std::size_t n_rows, std::size_t row_stride,
                            const FrameContext& ctx = {});
  SceneFilterResult process(const double* xyz, std::size_t n_rows, std::size_t row_stride,
                            const FrameContext& ctx = {});
  SceneFilterResult process(const PointsF& points);
  SceneFilterResult process(const PointsD& points);

  const PlanePersistence& persistence() const { return persistence_; }
  const SceneFilterParams& params() const { return params_; }
  int frame_index() const { return frame_index_; }
  /// New session: forget the lock and restart frame numbering.
  void reset();

 private:
  std::uint64_t next_frame_seed();  ///< seed of the frame being processed; advances the count

  SceneFilterParams params_;
  PlanePersistence persistence_;
  int frame_index_ = 0;
  bool out_of_range_reported_ = false;  ///< the out-of-range WARNING was emitted this session
  SceneFilterWorkspace work_;           ///< per-frame buffers, reused
};

}  // namespace grasp_core
