#include "grasp_core/perception.hpp"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace grasp_core {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Perception::Perception(const SceneFilterParams& filter_params, const ObbParams& obb_params)
    : filter_(filter_params), obb_(obb_params), tracker_(obb_params), last_time_s_(0.0) {
  obb_.validate();
}

void Perception::reset() {
  filter_.reset();
  tracker_.reset();
  has_time_ = false;
}

PerceptionFrame Perception::process(const float* xyz, std::size_t n_rows, std::size_t row_stride,
                                    const Vec3& camera_position, double time_s, int image_width,
                                    const std::uint8_t* rgb) {
  return process_impl(xyz, n_rows, row_stride, camera_position, time_s, image_width, rgb);
}

PerceptionFrame Perception::process(const double* xyz, std::size_t n_rows, std::size_t row_stride,
                                    const Vec3& camera_position, double time_s, int image_width,
                                    const std::uint8_t* rgb) {
  return process_impl(xyz, n_rows, row_stride, camera_position, time_s, image_width, rgb);
}

template <typename T>
PerceptionFrame Perception::process_impl(const T* xyz, std::size_t n_rows, std::size_t row_stride,
                                         const Vec3& camera_position, double time_s,
                                         int image_width, const std::uint8_t* rgb) {
  if (!std::isfinite(time_s)) throw std::invalid_argument("time_s must be finite");
  if (!camera_position.allFinite()) {
    throw std::invalid_argument("camera_position must be 3 finite numbers");
  }
  if (has_time_ && time_s < last_time_s_) {
    std::ostringstream os;
    os << "time_s went backwards (" << time_s << " s after " << last_time_s_
       << " s); frames must arrive in capture order, or call reset() for a new session";
    throw std::invalid_argument(os.str());
  }
  const auto t0 = std::chrono::steady_clock::now();
  PerceptionFrame out;
  out.time_s = time_s;
  out.camera_position = camera_position;
  FrameContext ctx;
  ctx.image_width = image_width;
  ctx.rgb = rgb;
  ctx.camera_position = camera_position;
  out.filter = filter_.process(xyz, n_rows, row_stride, ctx);
  last_time_s_ = time_s;
  has_time_ = true;

  const auto t1 = std::chrono::steady_clock::now();
  if (out.filter.table && !out.filter.cluster_ids.empty()) {
    const Plane& plane = *out.filter.table;
    // Bucket every object row into its cluster (labels are compact 0..K-1). The filter
    // lists the object rows in ascending order, so each cluster keeps the input row order
    // without a pass over the whole frame.
    const int k = static_cast<int>(out.filter.cluster_ids.size());
    std::vector<int> slot(static_cast<std::size_t>(out.filter.cluster_ids.back()) + 1, -1);
    for (int i = 0; i < k; ++i) slot[static_cast<std::size_t>(out.filter.cluster_ids[i])] = i;
    const auto slot_of_row = [&](int row) {
      const int lab = out.filter.labels[static_cast<std::size_t>(row)];
      return (lab >= 0 && static_cast<std::size_t>(lab) < slot.size()) ? slot[lab] : -1;
    };
    std::vector<std::size_t> counts(static_cast<std::size_t>(k), 0);
    for (const int row : out.filter.object_rows) {
      const int s = slot_of_row(row);
      if (s >= 0) ++counts[static_cast<std::size_t>(s)];
    }
    std::vector<PointsD> clusters(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) clusters[i].resize(static_cast<Eigen::Index>(counts[i]), 3);
    std::vector<Eigen::Index> fill(static_cast<std::size_t>(k), 0);
    for (const int row : out.filter.object_rows) {
      const int s = slot_of_row(row);
      if (s < 0) continue;
      const T* p = xyz + static_cast<std::size_t>(row) * row_stride;
      clusters[s].row(fill[s]++) << static_cast<double>(p[0]), static_cast<double>(p[1]),
          static_cast<double>(p[2]);
    }
    const std::vector<EstimateResult> results =
        estimate_with_priors(clusters, plane, obb_, tracker_, out.filter.band,
                             filter_.params().max_abs_coordinate_m);
    std::vector<ViewQuality> qualities;
    for (int i = 0; i < k; ++i) {
      const EstimateResult& r = results[static_cast<std::size_t>(i)];
      if (!r.estimate) {
        out.failed_labels.push_back(out.filter.cluster_ids[i]);
        out.failures.push_back(r.failure);
        continue;
      }
      out.estimate_labels.push_back(out.filter.cluster_ids[i]);
      out.estimates.push_back(*r.estimate);
      ViewAssessment view =
          assess_view(r.estimate->center, camera_position, plane.n, obb_.nadir_angle_max_deg);
      // (ours) A view from closer than nadir_min_distance_m is never NADIR: the camera passing
      // low over an object (e.g. while carrying another) sees only part of it.
      if ((r.estimate->center - camera_position).norm() < obb_.nadir_min_distance_m)
        view.quality = ViewQuality::OBLIQUE;
      out.views.push_back(view);
      qualities.push_back(out.views.back().quality);
    }
    out.ms_estimate = ms_since(t1);
    const auto t2 = std::chrono::steady_clock::now();
    out.tids = tracker_.update(out.estimates, qualities, time_s);
    tracker_.retire(time_s);
    out.ms_track = ms_since(t2);
  } else {
    // No objects this frame: the tracker still sees an empty frame (its gate becomes
    // undefined) and retires old tracks.
    const auto t2 = std::chrono::steady_clock::now();
    tracker_.update({}, {}, time_s);
    tracker_.retire(time_s);
    out.ms_track = ms_since(t2);
  }
  out.ms_total = ms_since(t0);
  return out;
}

template PerceptionFrame Perception::process_impl<float>(const float*, std::size_t, std::size_t,
                                                         const Vec3&, double, int,
                                                         const std::uint8_t*);
template PerceptionFrame Perception::process_impl<double>(const double*, std::size_t, std::size_t,
                                                          const Vec3&, double, int,
                                                          const std::uint8_t*);

}  // namespace grasp_core
