// method.md §1.5 — table-plane persistence. See plane_persistence.hpp for the choices made
// where the method is silent.
#include "grasp_core/plane_persistence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace grasp_core {
namespace {

/// "z=0.2000 (tilt 0.12 deg)"
std::string describe(const Plane& p) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "z=%.4f (tilt %.2f deg)", p.height_m(), p.tilt_deg());
  return buf;
}

std::string fmt_z(const char* what, const Plane& p) { return std::string(what) + ": " + describe(p); }

FrameEvent event(FrameEvent::Level level, std::string msg) {
  return FrameEvent{level, std::move(msg)};
}

}  // namespace

bool planes_close(const Plane& a, const Plane& b, double tol_deg, double tol_m) {
  const double cos_angle = std::clamp(a.n.normalized().dot(b.n.normalized()), -1.0, 1.0);
  const double angle_deg = std::acos(cos_angle) * 180.0 / M_PI;
  const double dh = std::abs(a.height_m() - b.height_m());
  // Written so that NaN in either plane means "not close".
  return angle_deg <= tol_deg && dh <= tol_m;
}

PlanePersistence::PlanePersistence(const SceneFilterParams& params) : params_(params) {
  params_.validate();
}

void PlanePersistence::reset() { state_ = PersistenceState{}; }

PersistenceUpdate PlanePersistence::update(const std::optional<Plane>& fit) {
  using L = FrameEvent::Level;
  PersistenceUpdate out;
  state_.fallback_active = false;

  if (!params_.plane_lock) {
    // Each frame uses its own fit; `lock` mirrors the last fit for latched readers.
    if (fit) {
      state_.lock = fit;
      state_.frames_without_lock = 0;
      out.table = fit;
      out.environment_emitted = true;
      out.decision = PlaneDecision::kUnlockedFit;
      return out;
    }
    state_.lock.reset();
  } else if (state_.lock) {
    const Plane& lock = *state_.lock;
    if (!fit) {
      out.decision = PlaneDecision::kKeptNoFit;
    } else if (!state_.hardened) {
      // Not hardened: compare with the previous frame's lock (may still change its mind).
      if (planes_close(*fit, lock, params_.plane_update_tol_deg, params_.plane_update_tol_m)) {
        state_.lock = fit;
        state_.hits += 1;
        out.decision = PlaneDecision::kFollowed;
      } else {
        out.events.push_back(event(
            L::kInfo, "table plane changed before hardening: " + describe(*fit) +
                          " (was " + describe(lock) + "), restarting"));
        state_.lock = fit;
        state_.anchor = fit;
        state_.hits = 1;
        out.decision = PlaneDecision::kRestarted;
      }
      if (state_.hits >= params_.plane_lock_after) {
        state_.hardened = true;
        state_.anchor = fit;  // the plane at the moment of hardening
        out.decision = PlaneDecision::kHardened;
        out.events.push_back(event(L::kInfo, fmt_z("table plane hardened", *fit)));
      }
    } else {
      // Hardened: compare with the anchor only, so slow drift cannot accumulate.
      if (planes_close(*fit, *state_.anchor, params_.plane_update_tol_deg,
                       params_.plane_update_tol_m)) {
        state_.lock = fit;
        out.decision = PlaneDecision::kFollowed;
      } else {
        out.events.push_back(event(
            L::kDebug, fmt_z("plane fit refused (not close to the hardened anchor)", *fit)));
        out.decision = PlaneDecision::kRefused;
      }
    }
    out.table = state_.lock;
    out.environment_emitted = true;
    return out;
  } else if (fit) {
    // First lock.
    state_.lock = fit;
    state_.anchor = fit;
    state_.hits = 1;
    state_.frames_without_lock = 0;
    out.decision = PlaneDecision::kLocked;
    out.events.push_back(event(L::kInfo, fmt_z("table plane locked", *fit)));
    if (state_.hits >= params_.plane_lock_after) {
      state_.hardened = true;
      out.decision = PlaneDecision::kHardened;
      out.events.push_back(event(L::kInfo, fmt_z("table plane hardened", *fit)));
    }
    out.table = state_.lock;
    out.environment_emitted = true;
    return out;
  }

  // No plane to use this frame.
  state_.frames_without_lock += 1;
  if (state_.frames_without_lock >= params_.plane_init_frames) {
    state_.fallback_active = true;
    out.fallback = true;
    out.environment_emitted = true;
    out.decision = PlaneDecision::kFallback;
    if (!state_.fallback_reported) {
      state_.fallback_reported = true;
      char buf[200];
      std::snprintf(buf, sizeof(buf),
                    "no table plane after %d frames: emitting the whole cloud as environment",
                    state_.frames_without_lock);
      out.events.push_back(event(L::kError, buf));
    }
  } else {
    out.decision = PlaneDecision::kNoPlane;
  }
  return out;
}

}  // namespace grasp_core
