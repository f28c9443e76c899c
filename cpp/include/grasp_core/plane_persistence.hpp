// method.md §1.5 — table-plane persistence (lock / hits / harden / anchor / init fallback).
//
// Eye-in-hand: the table leaves the view when the hand comes close, so the plane found
// early is kept as a session constant. Log lines are returned as FrameEvent values (the
// Python side logs them); nothing is printed.
#pragma once

#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

#include <optional>
#include <string>
#include <vector>

namespace grasp_core {

/// A message for the caller's log (Python maps the level onto logging levels).
struct FrameEvent {
  enum class Level : int { kDebug = 10, kInfo = 20, kWarning = 30, kError = 40 };
  Level level = Level::kInfo;
  std::string message;
};

/// What the state machine did with this frame's fit.
enum class PlaneDecision : int {
  kNoPlane = 0,      ///< no fit and no lock yet (nothing emitted)
  kFallback,         ///< no lock after plane_init_frames: whole cloud is environment
  kLocked,           ///< first fit became lock and anchor
  kFollowed,         ///< close fit accepted: lock = fit
  kRestarted,        ///< not hardened and not close to the previous lock: start over
  kHardened,         ///< this frame hardened the lock (anchor = this fit)
  kRefused,          ///< hardened and the fit is not close to the anchor: lock kept
  kKeptNoFit,        ///< no fit this frame: lock kept
  kUnlockedFit,      ///< plane_lock = false: this frame's own fit is used
};

/// The state of method.md §1.5 (a snapshot is copied into every frame result).
struct PersistenceState {
  std::optional<Plane> lock;    ///< the current table plane (latched)
  std::optional<Plane> anchor;  ///< reference for closeness once hardened
  int hits = 0;                 ///< consecutive close fits since the last (re)start
  bool hardened = false;
  int frames_without_lock = 0;  ///< frames processed without any table plane (see update())
  bool fallback_active = false; ///< init-frames fallback in force this frame
  bool fallback_reported = false;  ///< the fallback error was already reported (once per session)
};

/// Result of feeding one frame's fit to the state machine.
struct PersistenceUpdate {
  std::optional<Plane> table;     ///< plane to use for this frame (nullopt: none)
  bool environment_emitted = false;  ///< false before the first lock unless the fallback fired
  bool fallback = false;          ///< init-frames fallback: emit every valid point as environment
  PlaneDecision decision = PlaneDecision::kNoPlane;
  std::vector<FrameEvent> events;
};

/// method.md §1.5 closeness: normal angle <= tol_deg AND |height(a) - height(b)| <= tol_m.
bool planes_close(const Plane& a, const Plane& b, double tol_deg, double tol_m);

/// method.md §1.5 state machine.
///
/// - plane_lock_after counts the first fit: with plane_lock_after = 1 the first fit locks
///   and hardens in the same frame.
/// - frames_without_lock counts frames with no table plane to use; once it reaches
///   plane_init_frames the fallback is in force (for that and every later frame without a
///   plane) and an ERROR event is emitted once per session (until reset()).
///   With plane_lock = true a lock is never lost, so this only happens before the first fit.
/// - plane_lock = false: each frame uses its own fit (no lock/anchor/hits kept, `lock`
///   mirrors the last fit); a frame without fit counts towards the fallback like above.
class PlanePersistence {
 public:
  /// Validates `params` (std::invalid_argument naming the parameter).
  explicit PlanePersistence(const SceneFilterParams& params);

  /// Feed this frame's table fit (nullopt: no plane found this frame).
  PersistenceUpdate update(const std::optional<Plane>& fit);

  const PersistenceState& state() const { return state_; }
  bool locked() const { return state_.lock.has_value(); }
  bool hardened() const { return state_.hardened; }
  /// Forget everything (new session).
  void reset();

 private:
  SceneFilterParams params_;
  PersistenceState state_;
};

}  // namespace grasp_core
