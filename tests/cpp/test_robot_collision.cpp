// Robot chain FK and the planning state checker on a small synthetic planar arm and on the
// spatial arm of spatial_arm.hpp (against sphere-by-sphere references).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>

#include "grasp_core/collision_scene.hpp"
#include "grasp_core/robot_collision.hpp"
#include "spatial_arm.hpp"

using namespace grasp_core;

namespace {

constexpr double kLinkA_m = 0.5;  // joint 0 -> joint 1
constexpr double kTool_m = 0.45;  // joint 1 -> tool sphere
constexpr double kBaseZ_m = 1.0;
constexpr double kR_m = 0.05;

/// world, base (z = 1), link A (hinge z, joint 0), link B (hinge z, joint 1), tool (fixed).
RobotCollisionSpec arm_spec() {
  RobotCollisionSpec s;
  s.bodies.resize(5);
  s.bodies[1].p = Vec3(0, 0, kBaseZ_m);
  s.bodies[2].parent = 1; s.bodies[2].joint = 0;
  s.bodies[3].parent = 2; s.bodies[3].p = Vec3(kLinkA_m, 0, 0); s.bodies[3].joint = 1;
  s.bodies[4].parent = 3; s.bodies[4].p = Vec3(kTool_m, 0, 0);
  auto add = [&](int body, Vec3 c, double r, bool env, bool hand) {
    s.sphere_body.push_back(body); s.sphere_center.push_back(c); s.sphere_radius.push_back(r);
    s.sphere_geom.push_back(body); s.env_sphere.push_back(env); s.hand_sphere.push_back(hand);
  };
  add(1, Vec3::Zero(), 0.1, false, false);              // 0 base
  add(2, Vec3(0.25, 0, 0), kR_m, true, false);          // 1 link A
  add(3, Vec3(0.15, 0, 0), kR_m, true, false);          // 2 link B
  add(4, Vec3::Zero(), kR_m, true, true);               // 3 tool
  s.pairs = {{0, 3}};
  for (int j = 0; j < kArmJoints; ++j) { s.q_min_rad[j] = -3.0; s.q_max_rad[j] = 3.0; }
  return s;
}

std::array<double, kArmJoints> q_of(double a, double b) { return {a, b, 0, 0, 0, 0, 0}; }

StateChecker checker(std::shared_ptr<CollisionScene> scene) {
  return StateChecker(std::make_shared<RobotCollisionModel>(arm_spec()), scene);
}

std::shared_ptr<CollisionScene> free_scene() {
  auto s = std::make_shared<CollisionScene>();
  s->collision_margin_m = 0.005;
  s->floor_z_m = 0.0;
  return s;
}

/// Distance field of one occupied voxel (distances between voxel centres).
DistanceField one_voxel_field(const Vec3& occupied_m, double voxel_m) {
  DistanceField f;
  f.nx = f.ny = f.nz = 40;
  f.voxel_m = voxel_m;
  f.inflation_m = std::sqrt(3.0) * voxel_m;
  f.origin = occupied_m - Vec3::Constant(20.5 * voxel_m);
  f.values.resize(40 * 40 * 40);
  for (long long i = 0; i < 40; ++i)
    for (long long j = 0; j < 40; ++j)
      for (long long k = 0; k < 40; ++k)
        f.values[static_cast<std::size_t>((i * 40 + j) * 40 + k)] =
            static_cast<float>(voxel_m * std::sqrt(double((i - 20) * (i - 20) + (j - 20) * (j - 20) + (k - 20) * (k - 20))));
  return f;
}

}  // namespace

TEST(RobotChain, PlanarArmForwardKinematics) {
  const RobotChain chain(arm_spec().bodies);
  std::vector<Mat3> R(5);
  std::vector<Vec3> p(5);
  const auto q = q_of(0.7, -1.1);
  chain.poses(q.data(), R.data(), p.data());
  EXPECT_LT((p[3] - Vec3(kLinkA_m * std::cos(0.7), kLinkA_m * std::sin(0.7), kBaseZ_m)).norm(), 1e-12);
  const Vec3 tool = p[3] + kTool_m * Vec3(std::cos(-0.4), std::sin(-0.4), 0);
  EXPECT_LT((p[4] - tool).norm(), 1e-12);
  EXPECT_LT((R[4] - Eigen::AngleAxisd(-0.4, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-12);
}

TEST(RobotChain, RejectsBadStructure) {
  auto bodies = arm_spec().bodies;
  bodies[2].parent = 3;
  EXPECT_THROW(RobotChain{bodies}, std::invalid_argument);
  bodies = arm_spec().bodies;
  bodies[2].joint = 7;
  EXPECT_THROW(RobotChain{bodies}, std::invalid_argument);
  auto spec = arm_spec();
  spec.pairs = {{0, 9}};
  EXPECT_THROW(RobotCollisionModel{spec}, std::invalid_argument);
}

TEST(StateChecker, LimitsFloorAndSelfCollision) {
  auto scene = free_scene();
  StateChecker c = checker(scene);
  EXPECT_TRUE(c.check(q_of(0, 0).data()));
  EXPECT_FALSE(c.check(q_of(3.1, 0).data()));                // joint limit
  EXPECT_FALSE(c.check(q_of(0, 2.99).data()));               // tool folded back onto the base
  scene = free_scene();
  scene->floor_z_m = kBaseZ_m - 0.04;                        // spheres of r = 5 cm dip below
  c.set_scene(scene);
  EXPECT_FALSE(c.check(q_of(0, 0).data()));
}

TEST(StateChecker, BoxesAndDistanceField) {
  auto scene = free_scene();
  const Vec3 tool(kLinkA_m + kTool_m, 0, kBaseZ_m);
  scene->boxes.emplace_back(tool + Vec3(0.2, 0, 0), Mat3::Identity(), Vec3::Constant(0.2));
  StateChecker c = checker(scene);
  EXPECT_TRUE(c.check(q_of(0, 0).data()));                   // 10 cm - r - margin > 0
  scene = free_scene();
  scene->boxes.emplace_back(tool + Vec3(0.14, 0, 0), Mat3::Identity(), Vec3::Constant(0.2));
  c.set_scene(scene);
  EXPECT_FALSE(c.check(q_of(0, 0).data()));                  // 4 cm gap < r + margin
  scene = free_scene();
  scene->has_env = true;
  scene->field = one_voxel_field(tool + Vec3(0.0, 0.2, 0), 0.01);
  c.set_scene(scene);
  EXPECT_TRUE(c.check(q_of(0, 0).data()));
  scene = free_scene();
  scene->has_env = true;
  scene->field = one_voxel_field(tool + Vec3(0.0, 0.06, 0), 0.01);
  c.set_scene(scene);
  EXPECT_FALSE(c.check(q_of(0, 0).data()));                  // 6 cm < r + margin + inflation
}

TEST(StateChecker, ObjectPointsBlockEverySphereWithinMarginAndRounding) {
  // one object cell 6.2 cm from the tool: clear (r + margin + fine = 5.93 cm); at 5.8 cm: not.
  // Object points are never cleared: target contact allowed changes nothing for them.
  const Vec3 tool(kLinkA_m + kTool_m, 0, kBaseZ_m);
  const double fine = 0.5 * std::sqrt(3.0) * 0.005;
  auto with_point = [&](double gap_m) {
    auto s = free_scene();
    const Vec3 p = tool + Vec3(0.0, gap_m, 0.0);
    s->points = ClearedRegion(ObstacleBox(p, Mat3::Identity(), Vec3::Zero()), 0.1, {p}, fine, 0.0);
    s->has_points = true;
    return s;
  };
  StateChecker c = checker(with_point(0.062));
  EXPECT_TRUE(c.check(q_of(0, 0).data()));
  c.set_scene(with_point(0.058));
  EXPECT_FALSE(c.check(q_of(0, 0).data()));
  c.set_allow_target_contact(true);
  EXPECT_FALSE(c.check(q_of(0, 0).data()));
  c.set_scene(with_point(0.22));  // far from every sphere
  EXPECT_TRUE(c.check(q_of(0, 0).data()));
}

TEST(StateChecker, SegmentFindsAnObstacleBetweenValidEnds) {
  auto scene = free_scene();
  scene->boxes.emplace_back(Vec3(kLinkA_m + kTool_m, 0, kBaseZ_m), Mat3::Identity(), Vec3::Constant(0.02));
  StateChecker c = checker(scene);
  const auto a = q_of(0, -1.0), b = q_of(0, 1.0);
  EXPECT_TRUE(c.check(a.data()));
  EXPECT_TRUE(c.check(b.data()));
  EXPECT_FALSE(c.check_segment(a.data(), b.data(), 0.01, false));
  const auto b2 = q_of(0, -0.5);
  EXPECT_TRUE(c.check_segment(a.data(), b2.data(), 0.01, true));
  EXPECT_THROW(c.check_segment(a.data(), b.data(), 0.0, false), std::invalid_argument);
  std::vector<double> Q = {0, 0, 0, 0, 0, 0, 0, 0, 2.99, 0, 0, 0, 0, 0};
  std::uint8_t out[2] = {9, 9};
  c.check_batch(Q.data(), 2, out);
  EXPECT_EQ(out[0], 0);  // the tool sits in the box at q = 0
  EXPECT_EQ(out[1], 0);
}

TEST(ClearedRegion, NearestDistanceEqualsBruteForce) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<Vec3> pts;
  for (int i = 0; i < 800; ++i) pts.emplace_back(u(gen), u(gen), 0.1 * u(gen));
  const double pad = 0.09, fine = 0.002, infl = 0.017;
  const ClearedRegion region(ObstacleBox(Vec3::Zero(), Mat3::Identity(), Vec3::Constant(0.1)), pad, pts, fine, infl);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(1.5 * u(gen), 1.5 * u(gen), u(gen));
    double best = kInfinity;
    for (const Vec3& q : pts) best = std::min(best, (p - q).norm());
    const double expected = best < pad ? (best - fine) + infl : kInfinity;
    EXPECT_DOUBLE_EQ(region.distance(p), expected);
  }
}

TEST(ClearedRegion, BlockedEqualsTheNearestDistanceTest) {
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::uniform_real_distribution<double> t(-0.02, 0.12);
  std::vector<Vec3> pts;
  for (int i = 0; i < 2000; ++i) pts.emplace_back(u(gen), u(gen), 0.1 * u(gen));
  const double pad = 0.09, fine = 0.002, infl = 0.017;
  const ClearedRegion region(ObstacleBox(Vec3::Zero(), Mat3::Identity(), Vec3::Constant(0.1)), pad, pts, fine, infl);
  EXPECT_FALSE(ClearedRegion().blocked(Vec3::Zero(), 1.0));
  int blocked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p(1.2 * u(gen), 1.2 * u(gen), 0.5 * u(gen));
    double thr = t(gen);
    if (k % 4 == 0) {  // thresholds at the decision boundary of the nearest point
      const double d = region.distance(p);
      if (d < kInfinity) thr = d + (k % 8 == 0 ? 0.0 : 1e-17);
    }
    const bool want = !(region.distance(p) - thr >= 0.0);
    ASSERT_EQ(region.blocked(p, thr), want) << k;
    blocked += want;
  }
  EXPECT_GT(blocked, 1000);
  EXPECT_LT(blocked, 19000);
}

TEST(StateChecker, PartialPairListUsesTheListPath) {
  auto spec = arm_spec();
  // a second tool sphere, paired with nothing: the pair list no longer covers whole link pairs
  spec.sphere_body.push_back(4); spec.sphere_center.push_back(Vec3(0.1, 0, 0));
  spec.sphere_radius.push_back(kR_m); spec.sphere_geom.push_back(4);
  spec.env_sphere.push_back(1); spec.hand_sphere.push_back(1);
  const auto model = std::make_shared<RobotCollisionModel>(spec);
  EXPECT_FALSE(model->complete_link_pairs());
  StateChecker c(model, free_scene());
  EXPECT_TRUE(c.check(q_of(0, 0).data()));
  EXPECT_FALSE(c.check(q_of(0, 2.99).data()));  // the paired tool sphere still hits the base
  EXPECT_TRUE(StateChecker(std::make_shared<RobotCollisionModel>(arm_spec()), free_scene()).robot().complete_link_pairs());
}

TEST(StateChecker, FirstInvalidOnPathIsTheFirstInvalidDenseState) {
  auto scene = free_scene();
  scene->boxes.emplace_back(Vec3(0.0, 0.95, kBaseZ_m), Mat3::Identity(), Vec3(0.1, 0.1, 0.1));
  StateChecker c = checker(scene);
  const double step = 0.01;
  // waypoints sweeping joint 0 from 0 to 1 rad and on to 2.5 rad: the tool meets the box near pi/2
  const double W[3][kArmJoints] = {{0, 0, 0, 0, 0, 0, 0}, {1.0, 0, 0, 0, 0, 0, 0}, {2.5, 0, 0, 0, 0, 0, 0}};
  long long seg = -2, idx = -2;
  EXPECT_FALSE(c.first_invalid_on_path(&W[0][0], 3, step, &seg, &idx));
  // the same answer by checking the dense states one by one in order
  long long want_seg = -1, want_idx = -1;
  for (int k = 0; k < 2 && want_seg < 0; ++k) {
    const long long n = static_cast<long long>(std::ceil((W[k + 1][0] - W[k][0]) / step));
    for (long long i = 1; i <= n; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(n);
      const auto q = q_of(W[k][0] + (W[k + 1][0] - W[k][0]) * s, 0);
      if (!c.check(q.data())) { want_seg = k; want_idx = i - 1; break; }
    }
  }
  EXPECT_EQ(seg, 1);
  EXPECT_EQ(seg, want_seg);
  EXPECT_EQ(idx, want_idx);
  EXPECT_TRUE(c.first_invalid_on_path(&W[0][0], 2, step, &seg, &idx));
  EXPECT_EQ(seg, -1);
  EXPECT_TRUE(c.first_invalid_on_path(&W[0][0], 1, step, &seg, &idx));  // no segment
  EXPECT_THROW(c.first_invalid_on_path(&W[0][0], 3, 0.0, &seg, &idx), std::invalid_argument);
}

TEST(StateChecker, EqualsSphereBySphereReferenceInAndAroundTheGrid) {
  // A small map (40 voxels of 1 cm around one occupied voxel near the arm's reach) and a box:
  // most states put the links' bounding spheres outside, across or inside the grid. The
  // checker's verdict must equal testing every sphere and pair (the reference below).
  auto scene = free_scene();
  scene->has_env = true;
  scene->field = one_voxel_field(Vec3(0.6, 0.3, kBaseZ_m), 0.01);
  scene->boxes.emplace_back(Vec3(-0.5, 0.5, kBaseZ_m), Mat3::Identity(), Vec3::Constant(0.1));
  const auto model = std::make_shared<RobotCollisionModel>(arm_spec());
  StateChecker c(model, scene);
  const RobotCollisionSpec& s = model->spec();
  const CollisionScene& sc = *scene;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Vec3> C(static_cast<std::size_t>(model->num_spheres()));
  int valid = 0, n = 0;
  for (int k = 0; k < 20000; ++k, ++n) {
    const auto q = q_of(u(rng), u(rng));
    c.sphere_centres(q.data(), C.data());
    bool ok = true;
    for (std::size_t i = 0; i < C.size(); ++i) {
      if (!s.env_sphere[i]) continue;
      const double r = s.sphere_radius[i];
      ok = ok && (C[i].z() - r) - sc.floor_z_m >= 0.0;
      ok = ok && sc.field.at(C[i]) - ((r + sc.collision_margin_m) + sc.field.inflation_m) >= 0.0;
      for (const ObstacleBox& b : sc.boxes) ok = ok && b.distance(C[i]) - (r + sc.collision_margin_m) >= 0.0;
    }
    for (const auto& pr : s.pairs)
      ok = ok && (C[static_cast<std::size_t>(pr.first)] - C[static_cast<std::size_t>(pr.second)]).norm() -
                         (s.sphere_radius[static_cast<std::size_t>(pr.first)] + s.sphere_radius[static_cast<std::size_t>(pr.second)]) >=
                     s.self_margin_m;
    ASSERT_EQ(c.check(q.data()), ok) << "q = " << q[0] << ", " << q[1];
    valid += ok;
  }
  EXPECT_GT(valid, n / 5);
  EXPECT_LT(valid, n - n / 20);
}

namespace {

/// Sphere-by-sphere reference of the checker (every test spelled out, the target-cleared map
/// by the nearest kept point), with the independent forward kinematics of spatial_arm.hpp:
/// the smallest slack over all tests (valid when >= 0; -1 outside the joint limits).
double reference_slack(const RobotCollisionSpec& s, const CollisionScene& sc, bool allow, const double* q) {
  for (int j = 0; j < kArmJoints; ++j)
    if (!(q[j] >= s.q_min_rad[j] && q[j] <= s.q_max_rad[j])) return -1.0;
  const std::vector<Vec3> C = grasp_test::reference_centres(s, q);
  double slack = grasp_test::reference_self_clearance(s, C);
  for (std::size_t i = 0; i < C.size(); ++i) {
    if (!s.env_sphere[i]) continue;
    const double r = s.sphere_radius[i], m = sc.collision_margin_m;
    slack = std::min(slack, (C[i].z() - r) - sc.floor_z_m);
    if (sc.has_env) {
      const double thr = (r + m) + sc.field.inflation_m;
      const bool cleared = allow && sc.has_cleared && s.hand_sphere[i] && sc.cleared.near(C[i]);
      slack = std::min(slack, (cleared ? sc.cleared.distance(C[i]) : sc.field.at(C[i])) - thr);
    }
    for (const ObstacleBox& b : sc.boxes) slack = std::min(slack, b.distance(C[i]) - (r + m));
    if (sc.has_points) slack = std::min(slack, sc.points.distance(C[i]) - (r + m));
  }
  return slack;
}

bool reference_valid(const RobotCollisionSpec& s, const CollisionScene& sc, bool allow, const double* q) {
  return reference_slack(s, sc, allow, q) >= 0.0;
}

/// The spatial arm's scene: floor, a map of one occupied voxel, two turned boxes, object
/// points and the target-cleared region around the occupied voxel (with kept points).
std::shared_ptr<CollisionScene> spatial_scene() {
  auto sc = std::make_shared<CollisionScene>();
  sc->collision_margin_m = 0.005;
  sc->floor_z_m = 0.02;
  sc->has_env = true;
  const Vec3 occupied(0.4, 0.2, 0.55);
  sc->field = one_voxel_field(occupied, 0.01);
  sc->boxes.emplace_back(Vec3(-0.4, 0.3, 0.45), grasp_test::turn(30, 0, 0, 1), Vec3(0.15, 0.1, 0.2));
  sc->boxes.emplace_back(Vec3(0.1, -0.5, 0.25), grasp_test::turn(20, 1, 1, 0), Vec3(0.1, 0.2, 0.1));
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.03);
  std::vector<Vec3> blob;
  for (int k = 0; k < 300; ++k) blob.emplace_back(0.3 + n(rng), -0.3 + n(rng), 0.65 + n(rng));
  Vec3 lo = blob[0], hi = blob[0];
  for (const Vec3& b : blob) { lo = lo.cwiseMin(b); hi = hi.cwiseMax(b); }
  sc->points = ClearedRegion(ObstacleBox(0.5 * (lo + hi), Mat3::Identity(), hi - lo), 0.1, blob, 0.004, 0.0);
  sc->has_points = true;
  const std::vector<Vec3> kept = {occupied + Vec3(0.03, 0, 0), occupied + Vec3(0, -0.04, 0.02)};
  sc->cleared = ClearedRegion(ObstacleBox(occupied, Mat3::Identity(), Vec3::Constant(0.06)), 0.08, kept, 0.002,
                              sc->field.inflation_m);
  sc->has_cleared = true;
  return sc;
}

}  // namespace

TEST(StateChecker, SpatialArmEqualsSphereBySphereReference) {
  // Random states and states at the validity boundary (bisection between a valid and an
  // invalid one, by the reference): check, check_batch and the reference agree, with and
  // without target contact; the pair tables and the link bounds only shortcut.
  const RobotCollisionSpec spec = grasp_test::spatial_arm_spec(0.002);
  const auto model = std::make_shared<RobotCollisionModel>(spec);
  const auto scene = spatial_scene();
  StateChecker c(model, scene);
  std::mt19937 rng(17);
  for (const bool allow : {false, true}) {
    c.set_allow_target_contact(allow);
    std::vector<double> Q;
    std::vector<std::uint8_t> want;
    std::vector<std::array<double, kArmJoints>> good, bad;
    for (int k = 0; k < 12000; ++k) {
      std::array<double, kArmJoints> q{};  // a few states beyond the limits (joints 4..6 are fixed at 0)
      for (int j = 0; j < 4; ++j)
        q[j] = std::uniform_real_distribution<double>(spec.q_min_rad[j] - 0.02, spec.q_max_rad[j] + 0.02)(rng);
      if (k % 100 == 0) q[4 + k / 100 % 3] = 1e-3;
      const bool ok = reference_valid(spec, *scene, allow, q.data());
      (ok ? good : bad).push_back(q);
      Q.insert(Q.end(), q.begin(), q.end());
      want.push_back(ok);
    }
    for (std::size_t k = 0; k < std::min<std::size_t>(1500, std::min(good.size(), bad.size())); ++k) {
      auto a = good[k], b = bad[k];
      for (int it = 0; it < 34; ++it) {  // to ~1e-10 of the boundary, far above rounding
        std::array<double, kArmJoints> mid{};
        for (int j = 0; j < kArmJoints; ++j) mid[j] = 0.5 * (a[j] + b[j]);
        (reference_valid(spec, *scene, allow, mid.data()) ? a : b) = mid;
      }
      for (const auto& q : {a, b}) {
        Q.insert(Q.end(), q.begin(), q.end());
        want.push_back(reference_valid(spec, *scene, allow, q.data()));
      }
    }
    const std::size_t n = want.size();
    std::vector<std::uint8_t> got(n, 9);
    c.check_batch(Q.data(), n, got.data());
    std::size_t valid = 0;
    for (std::size_t k = 0; k < n; ++k) {
      ASSERT_EQ(got[k], want[k]) << "state " << k << " allow " << allow << " reference slack "
                                 << reference_slack(spec, *scene, allow, Q.data() + kArmJoints * k);
      ASSERT_EQ(c.check(Q.data() + kArmJoints * k), want[k] != 0) << "state " << k;
      valid += want[k];
    }
    EXPECT_GT(valid, n / 5);
    EXPECT_LT(valid, n - n / 5);
  }
}

TEST(RobotChain, PosesEqualIndependentKinematics) {
  // fixed rotations of every kind (identity, exact quarter turns, rounded, 45 degrees), a
  // hinge turning about -z, angles within and beyond the fast sine/cosine's range
  const RobotCollisionSpec spec = grasp_test::spatial_arm_spec();
  const RobotChain chain(spec.bodies);
  std::mt19937 rng(23);
  std::vector<Mat3> R(spec.bodies.size()), Rr;
  std::vector<Vec3> p(spec.bodies.size()), pr;
  for (int k = 0; k < 5000; ++k) {
    const double span = k < 4000 ? 3.5 : 300.0;
    std::array<double, kArmJoints> q{};
    for (double& x : q) x = std::uniform_real_distribution<double>(-span, span)(rng);
    chain.poses(q.data(), R.data(), p.data());
    grasp_test::reference_poses(spec, q.data(), Rr, pr);
    for (std::size_t b = 0; b < R.size(); ++b) {
      ASSERT_LT((R[b] - Rr[b]).cwiseAbs().maxCoeff(), 1e-13) << "body " << b << " span " << span;
      ASSERT_LT((p[b] - pr[b]).cwiseAbs().maxCoeff(), 1e-13) << "body " << b;
    }
  }
}
