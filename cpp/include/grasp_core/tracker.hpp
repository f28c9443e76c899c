// Object tracker across frames (method.md §4): associate -> disambiguate yaw, then smooth ->
// quality only goes up.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "grasp_core/object_estimate.hpp"
#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

namespace grasp_core {

class Tracker;

/// One tracked object. `smoothed` is the published estimate.
struct Track {
  int tid = -1;                               ///< increasing id, never reused by a tracker
  ViewQuality quality = ViewQuality::OBLIQUE;  ///< best quality seen; only goes up
  double last_seen_s = 0.0;                   ///< time of the last associated observation [s]
  ObjectEstimate smoothed;                    ///< medians over the window (see Tracker)

  /// Number of samples currently in the windows (<= window).
  int window_size() const { return static_cast<int>(theta_rad_.size()); }

 private:
  friend class Tracker;
  std::deque<Vec3> center_;
  std::deque<double> width_m_, perp_width_m_, height_m_, theta_rad_, anisotropy_;
};

/// Tracker of method.md §4. Not thread-safe by itself (one instance per perception session); the
/// Python binding serialises every call on one instance with a mutex.
class Tracker {
 public:
  explicit Tracker(const ObbParams& p);

  /// assoc_gate_frac x min pairwise distance of the centres; no value with fewer than 2.
  static std::optional<double> gate_for(const std::vector<Vec3>& centres, double frac);

  /// Smoothed theta of the track nearest to centre, if that track is within the gate
  /// (when a gate is given) (ours: a new object must not borrow a neighbour's theta).
  std::optional<double> prior_theta(const Vec3& centre, std::optional<double> gate) const;

  /// One frame: computes the gate from these estimates (kept as last_gate), associates each
  /// observation in order to the nearest not-yet-used track within the gate (or any, with no
  /// gate), else starts a new track; then observe(). Returns the tid of each estimate.
  /// q must have ests.size() entries (missing entries count as OBLIQUE).
  std::vector<int> update(const std::vector<ObjectEstimate>& ests,
                          const std::vector<ViewQuality>& q, double now_s);

  /// Drop tracks whose age now_s - last_seen_s exceeds nadir_hold_s (NADIR tracks) or
  /// max_age_s (others).
  void retire(double now_s);

  /// Tracks sorted by tid.
  const std::vector<Track>& tracks() const { return tracks_; }
  /// The gate of the last update() (for select, method.md §5).
  std::optional<double> last_gate() const { return last_gate_; }
  /// Forget all tracks and the gate. Tids keep increasing (never reused).
  void reset();

 private:
  void observe(Track& t, const ObjectEstimate& est, ViewQuality q, double now_s) const;
  void smooth(Track& t, const ObjectEstimate& est) const;

  ObbParams p_;
  std::vector<Track> tracks_;
  std::optional<double> last_gate_;
  int next_tid_ = 0;
};

/// Two-pass estimation of one frame's clusters (method.md §4): estimate each without prior;
/// gate from those first-pass centres; prior = tracker.prior_theta(centre, gate);
/// estimate again with theta_prev; if the second pass fails keep the first.
/// Returns one result per cluster (same order); failed clusters keep their failure text.
std::vector<EstimateResult> estimate_with_priors(const std::vector<PointsD>& clusters,
                                                 const Plane& plane, const ObbParams& p,
                                                 const Tracker& tracker,
                                                 std::optional<double> band = std::nullopt,
                                                 double max_abs_coordinate_m = kDefaultMaxAbsCoordinate_m);

}  // namespace grasp_core
