// The per-frame entry point (one call into C++ per frame, docs/method.md §0): scene filter ->
// two-pass estimates -> view quality -> tracker. Python makes one call per camera frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "grasp_core/grasp.hpp"
#include "grasp_core/object_estimate.hpp"
#include "grasp_core/params.hpp"
#include "grasp_core/scene_filter.hpp"
#include "grasp_core/tracker.hpp"
#include "grasp_core/types.hpp"

namespace grasp_core {

/// Everything perception produced for one frame.
struct PerceptionFrame {
  SceneFilterResult filter;               ///< plane, labels (one per input row), events, timings
  std::vector<int> estimate_labels;       ///< object group id of each estimate (filter label)
  std::vector<ObjectEstimate> estimates;  ///< this frame's estimates (two-pass)
  std::vector<ViewAssessment> views;      ///< view quality of each estimate
  std::vector<int> tids;                  ///< track id each estimate was associated with
  std::vector<int> failed_labels;         ///< groups whose estimate failed
  std::vector<std::string> failures;      ///< ... and why (same order)
  double time_s = 0.0;                    ///< capture time of the frame [s]
  Vec3 camera_position = Vec3::Zero();    ///< camera position at capture [m]
  double ms_estimate = 0.0;               ///< estimates + view quality [ms]
  double ms_track = 0.0;                  ///< tracker update + retirement [ms]
  double ms_total = 0.0;                  ///< whole process() call [ms]
};

/// Scene filter + estimates + tracker for one camera session. Not thread-safe by itself;
/// the Python binding serialises every call on one instance (and on its scene_filter /
/// tracker views) with one mutex.
class Perception {
 public:
  /// Validates both parameter sets (std::invalid_argument naming the parameter).
  Perception(const SceneFilterParams& filter_params, const ObbParams& obb_params);

  /// One frame in world coordinates: row i at xyz + i * row_stride (elements, >= 3).
  /// `camera_position` is the camera position at capture; `time_s` the capture time,
  /// which must not go backwards (std::invalid_argument otherwise).
  /// `image_width` > 0: the frame is organized (row v * image_width + u is pixel
  /// (u, v)); `rgb`: nullptr or n_rows x 3 bytes of colour, one per row (FrameContext).
  PerceptionFrame process(const float* xyz, std::size_t n_rows, std::size_t row_stride,
                          const Vec3& camera_position, double time_s, int image_width = 0,
                          const std::uint8_t* rgb = nullptr);
  PerceptionFrame process(const double* xyz, std::size_t n_rows, std::size_t row_stride,
                          const Vec3& camera_position, double time_s, int image_width = 0,
                          const std::uint8_t* rgb = nullptr);

  const SceneFilter& scene_filter() const { return filter_; }
  const Tracker& tracker() const { return tracker_; }
  const ObbParams& obb_params() const { return obb_; }
  /// Retire tracks at `now_s` without a new frame (a consumer's clock).
  void retire(double now_s) { tracker_.retire(now_s); }
  /// New session: forget the plane lock and all tracks.
  void reset();

 private:
  template <typename T>
  PerceptionFrame process_impl(const T* xyz, std::size_t n_rows, std::size_t row_stride,
                               const Vec3& camera_position, double time_s, int image_width,
                               const std::uint8_t* rgb);

  SceneFilter filter_;
  ObbParams obb_;
  Tracker tracker_;
  double last_time_s_;
  bool has_time_ = false;
};

}  // namespace grasp_core
