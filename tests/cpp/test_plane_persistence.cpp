// method.md §1.5 — plane persistence (grasp_core::PlanePersistence).
#include <gtest/gtest.h>

#include "grasp_core/plane_persistence.hpp"

#include <cmath>
#include <optional>

using namespace grasp_core;

namespace {

/// Plane of height h [m] whose normal is tilted by tilt_deg about the x axis.
Plane plane_at(double h, double tilt_deg = 0.0) {
  const double t = tilt_deg * M_PI / 180.0;
  Plane p;
  p.n = Vec3(0.0, -std::sin(t), std::cos(t));
  p.c = -h * p.n.z();
  return p;
}

int count_level(const std::vector<FrameEvent>& ev, FrameEvent::Level level) {
  int n = 0;
  for (const auto& e : ev) n += e.level == level ? 1 : 0;
  return n;
}

bool has_message(const std::vector<FrameEvent>& ev, const std::string& text) {
  for (const auto& e : ev)
    if (e.message.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(PlanesClose, HeightAndAngleTolerances) {
  EXPECT_TRUE(planes_close(plane_at(0.20), plane_at(0.229), 5.0, 0.03));
  EXPECT_FALSE(planes_close(plane_at(0.20), plane_at(0.231), 5.0, 0.03));
  EXPECT_TRUE(planes_close(plane_at(0.20), plane_at(0.20, 4.9), 5.0, 0.03));
  EXPECT_FALSE(planes_close(plane_at(0.20), plane_at(0.20, 5.1), 5.0, 0.03));
  Plane bad = plane_at(0.2);
  bad.c = std::nan("");
  EXPECT_FALSE(planes_close(plane_at(0.20), bad, 5.0, 0.03));
}

TEST(PlanePersistence, FirstFitLocksAndIsLogged) {
  PlanePersistence pp{SceneFilterParams{}};
  EXPECT_FALSE(pp.locked());
  const auto u = pp.update(plane_at(0.2));
  EXPECT_EQ(u.decision, PlaneDecision::kLocked);
  ASSERT_TRUE(u.table.has_value());
  EXPECT_DOUBLE_EQ(u.table->height_m(), 0.2);
  EXPECT_TRUE(u.environment_emitted);
  EXPECT_TRUE(has_message(u.events, "table plane locked: z=0.2000"));
  EXPECT_EQ(pp.state().hits, 1);
  ASSERT_TRUE(pp.state().anchor.has_value());
  EXPECT_DOUBLE_EQ(pp.state().anchor->height_m(), 0.2);
}

TEST(PlanePersistence, ChangesItsMindBeforeHardening) {
  SceneFilterParams p;  // plane_lock_after = 5
  PlanePersistence pp(p);
  pp.update(plane_at(0.20));
  pp.update(plane_at(0.20));
  EXPECT_EQ(pp.state().hits, 2);
  // A different plane (e.g. an object top) for a few frames: start over on it.
  const auto u = pp.update(plane_at(0.30));
  EXPECT_EQ(u.decision, PlaneDecision::kRestarted);
  EXPECT_DOUBLE_EQ(u.table->height_m(), 0.30);
  EXPECT_EQ(pp.state().hits, 1);
  EXPECT_DOUBLE_EQ(pp.state().anchor->height_m(), 0.30);
  pp.update(plane_at(0.30));
  // Back to the table: restart again (compared with the previous frame, not the first).
  const auto back = pp.update(plane_at(0.20));
  EXPECT_EQ(back.decision, PlaneDecision::kRestarted);
  EXPECT_EQ(pp.state().hits, 1);
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(pp.update(plane_at(0.20)).decision == PlaneDecision::kHardened);
  EXPECT_FALSE(pp.hardened());
  const auto h = pp.update(plane_at(0.20));  // 5th consistent frame
  EXPECT_EQ(h.decision, PlaneDecision::kHardened);
  EXPECT_TRUE(pp.hardened());
  // An angle change beyond plane_update_tol_deg also counts as "not close".
  PlanePersistence q(p);
  q.update(plane_at(0.20));
  EXPECT_EQ(q.update(plane_at(0.20, 6.0)).decision, PlaneDecision::kRestarted);
}

TEST(PlanePersistence, HardensWithAnchorAtTheHardeningFrame) {
  SceneFilterParams p;
  PlanePersistence pp(p);
  // Each fit is within tolerance of the previous one; the 5th is 2 cm above the first.
  const double h[5] = {0.200, 0.205, 0.210, 0.215, 0.220};
  for (int i = 0; i < 4; ++i) pp.update(plane_at(h[i]));
  EXPECT_FALSE(pp.hardened());
  const auto u = pp.update(plane_at(h[4]));
  EXPECT_EQ(u.decision, PlaneDecision::kHardened);
  EXPECT_TRUE(has_message(u.events, "table plane hardened: z=0.2200"));
  ASSERT_TRUE(pp.state().anchor.has_value());
  EXPECT_DOUBLE_EQ(pp.state().anchor->height_m(), 0.220);  // not the first fit (0.200)
  // 0.245 is within 3 cm of the anchor (0.220) but not of the first fit (0.200): accepted.
  const auto v = pp.update(plane_at(0.245));
  EXPECT_EQ(v.decision, PlaneDecision::kFollowed);
  EXPECT_DOUBLE_EQ(v.table->height_m(), 0.245);
}

TEST(PlanePersistence, PlaneLockAfterOneHardensOnTheFirstFit) {
  SceneFilterParams p;
  p.plane_lock_after = 1;
  PlanePersistence pp(p);
  const auto u = pp.update(plane_at(0.2));
  EXPECT_EQ(u.decision, PlaneDecision::kHardened);
  EXPECT_TRUE(pp.hardened());
  EXPECT_TRUE(has_message(u.events, "table plane locked"));
  EXPECT_TRUE(has_message(u.events, "table plane hardened"));
}

TEST(PlanePersistence, RefusesSlowDriftAfterHardening) {
  SceneFilterParams p;
  PlanePersistence pp(p);
  for (int i = 0; i < p.plane_lock_after; ++i) pp.update(plane_at(0.200));
  ASSERT_TRUE(pp.hardened());
  // Drift 1 cm per frame: each step is close to the previous frame, but it is compared with
  // the anchor, so it stops following once beyond plane_update_tol_m (3 cm).
  double last_followed = 0.0;
  int refused = 0;
  for (int k = 1; k <= 6; ++k) {
    const double h = 0.199 + 0.01 * k;  // 0.209, 0.219, ... (1 mm off the tolerance edge)
    const auto u = pp.update(plane_at(h));
    if (u.decision == PlaneDecision::kFollowed) {
      last_followed = h;
      EXPECT_LE(h - 0.200, p.plane_update_tol_m + 1e-12);
    } else {
      EXPECT_EQ(u.decision, PlaneDecision::kRefused);
      EXPECT_EQ(count_level(u.events, FrameEvent::Level::kDebug), 1);
      ++refused;
    }
    ASSERT_TRUE(u.table.has_value());
    EXPECT_DOUBLE_EQ(u.table->height_m(), last_followed);
  }
  EXPECT_NEAR(last_followed, 0.229, 1e-12);
  EXPECT_EQ(refused, 3);
  EXPECT_DOUBLE_EQ(pp.state().anchor->height_m(), 0.200);
  // A fit close to the anchor again is accepted (small refinements).
  EXPECT_EQ(pp.update(plane_at(0.201)).decision, PlaneDecision::kFollowed);
}

TEST(PlanePersistence, NoFitKeepsTheLock) {
  SceneFilterParams p;
  PlanePersistence pp(p);
  pp.update(plane_at(0.2));
  pp.update(plane_at(0.201));
  const int hits = pp.state().hits;
  for (int i = 0; i < 100; ++i) {  // far more than plane_init_frames
    const auto u = pp.update(std::nullopt);
    EXPECT_EQ(u.decision, PlaneDecision::kKeptNoFit);
    ASSERT_TRUE(u.table.has_value());
    EXPECT_DOUBLE_EQ(u.table->height_m(), 0.201);
    EXPECT_TRUE(u.environment_emitted);
    EXPECT_FALSE(u.fallback);
  }
  EXPECT_EQ(pp.state().hits, hits);
}

TEST(PlanePersistence, InitFramesFallbackReportsTheErrorOnce) {
  SceneFilterParams p;
  p.plane_init_frames = 5;
  PlanePersistence pp(p);
  for (int i = 0; i < 4; ++i) {
    const auto u = pp.update(std::nullopt);
    EXPECT_EQ(u.decision, PlaneDecision::kNoPlane);
    EXPECT_FALSE(u.environment_emitted);  // before the first lock: nothing emitted
    EXPECT_FALSE(u.table.has_value());
    EXPECT_TRUE(u.events.empty());
  }
  const auto f = pp.update(std::nullopt);
  EXPECT_EQ(f.decision, PlaneDecision::kFallback);
  EXPECT_TRUE(f.fallback);
  EXPECT_TRUE(f.environment_emitted);
  EXPECT_EQ(count_level(f.events, FrameEvent::Level::kError), 1);
  for (int i = 0; i < 10; ++i) {
    const auto g = pp.update(std::nullopt);
    EXPECT_TRUE(g.fallback);
    EXPECT_TRUE(g.events.empty());  // once
  }
  // A late table still locks normally.
  const auto l = pp.update(plane_at(0.2));
  EXPECT_EQ(l.decision, PlaneDecision::kLocked);
  EXPECT_FALSE(l.fallback);
  EXPECT_FALSE(pp.state().fallback_active);
  pp.reset();
  EXPECT_FALSE(pp.locked());
  EXPECT_FALSE(pp.state().fallback_reported);
}

TEST(PlanePersistence, PlaneLockFalseUsesEachFramesFit) {
  SceneFilterParams p;
  p.plane_lock = false;
  PlanePersistence pp(p);
  for (int i = 0; i < 10; ++i) pp.update(plane_at(0.2));
  EXPECT_FALSE(pp.hardened());
  const auto u = pp.update(plane_at(0.5));  // far from everything before: still used
  EXPECT_EQ(u.decision, PlaneDecision::kUnlockedFit);
  EXPECT_DOUBLE_EQ(u.table->height_m(), 0.5);
  EXPECT_TRUE(u.events.empty());
  const auto none = pp.update(std::nullopt);  // no fit: no plane this frame
  EXPECT_FALSE(none.table.has_value());
  EXPECT_FALSE(none.environment_emitted);
}

TEST(PlanePersistence, ConstructorValidatesParameters) {
  SceneFilterParams p;
  p.plane_update_tol_m = -1.0;
  try {
    PlanePersistence pp(p);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("plane_update_tol_m"), std::string::npos);
  }
}
