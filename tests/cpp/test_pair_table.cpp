// Joint-space tables of link pairs (pair_table.cpp) on the spatial arm: a clear cell holds
// only states whose sphere pairs all pass the self-collision test, a blocked cell only states
// where one fails, on random states, on states at the clearance boundary and on states at
// the cells' edges; pairs proven clear everywhere never fail.
#include <gtest/gtest.h>

#include <random>

#include "grasp_core/pair_table.hpp"
#include "grasp_core/robot_collision.hpp"
#include "spatial_arm.hpp"

using namespace grasp_core;
using grasp_test::reference_centres;
using grasp_test::reference_self_clearance;
using grasp_test::spatial_arm_spec;

namespace {

using State = std::array<double, kArmJoints>;

State random_state(const RobotCollisionSpec& s, std::mt19937& rng) {
  State q{};
  for (int j = 0; j < kArmJoints; ++j) q[j] = std::uniform_real_distribution<double>(s.q_min_rad[j], s.q_max_rad[j])(rng);
  return q;
}

/// The pair's verdict from its table (or always clear) must agree with the sphere test.
void expect_consistent(const RobotCollisionModel& m, const RobotCollisionModel::LinkPair& lp, const State& q,
                       int& decided) {
  const auto& s = m.spec();
  const int ba = m.links()[static_cast<std::size_t>(lp.la)].body, bb = m.links()[static_cast<std::size_t>(lp.lb)].body;
  const double c = reference_self_clearance(s, reference_centres(s, q.data()), ba, bb);
  PairTable::Cell cell = PairTable::clear;
  if (!lp.always_clear) cell = m.pair_tables()[static_cast<std::size_t>(lp.table)].at(q.data());
  if (cell == PairTable::clear) {
    EXPECT_GE(c, 0.0) << "bodies " << ba << "," << bb;
  } else if (cell == PairTable::blocked) {
    EXPECT_LT(c, 0.0) << "bodies " << ba << "," << bb;
  }
  decided += cell != PairTable::unknown;
}

}  // namespace

TEST(PairTable, CellsAgreeWithTheSphereTest) {
  for (const double margin : {0.0, 0.01}) {
    const RobotCollisionSpec spec = spatial_arm_spec(margin);
    const RobotCollisionModel model(spec);
    int tables = 0, clear_pairs = 0, blocked_cells = 0, dims_seen = 0;
    for (const auto& t : model.pair_tables()) {
      dims_seen |= 1 << t.dims;
      for (auto v : t.cells) blocked_cells += v == PairTable::blocked;
    }
    std::mt19937 rng(3);
    for (const auto& lp : model.link_pairs()) {
      if (!lp.always_clear && lp.table < 0) continue;
      tables += lp.table >= 0;
      clear_pairs += lp.always_clear;
      const int ba = model.links()[static_cast<std::size_t>(lp.la)].body, bb = model.links()[static_cast<std::size_t>(lp.lb)].body;
      int decided = 0;
      std::vector<State> free, hit;
      for (int k = 0; k < 20000; ++k) {
        const State q = random_state(spec, rng);
        expect_consistent(model, lp, q, decided);
        (reference_self_clearance(spec, reference_centres(spec, q.data()), ba, bb) >= 0.0 ? free : hit).push_back(q);
      }
      // states at the clearance boundary (bisection between a free and a colliding state)
      for (std::size_t k = 0; k < std::min<std::size_t>(200, std::min(free.size(), hit.size())); ++k) {
        State a = free[k], b = hit[k];
        for (int it = 0; it < 60; ++it) {
          State mid{};
          for (int j = 0; j < kArmJoints; ++j) mid[j] = 0.5 * (a[j] + b[j]);
          (reference_self_clearance(spec, reference_centres(spec, mid.data()), ba, bb) >= 0.0 ? a : b) = mid;
        }
        expect_consistent(model, lp, a, decided);
        expect_consistent(model, lp, b, decided);
      }
      if (lp.table >= 0) {  // states on the cells' edges
        const PairTable& t = model.pair_tables()[static_cast<std::size_t>(lp.table)];
        for (int k = 0; k < 2000; ++k) {
          State q = random_state(spec, rng);
          for (int d = 0; d < t.dims; ++d) {
            const int i = std::uniform_int_distribution<int>(0, t.n[static_cast<std::size_t>(d)])(rng);
            q[t.joint[static_cast<std::size_t>(d)]] = t.q0[static_cast<std::size_t>(d)] + i / t.inv_width[static_cast<std::size_t>(d)];
          }
          for (int d = 0; d < t.dims; ++d) {
            const int j = t.joint[static_cast<std::size_t>(d)];
            q[j] = std::clamp(q[j], spec.q_min_rad[j], spec.q_max_rad[j]);
          }
          expect_consistent(model, lp, q, decided);
        }
      }
      EXPECT_GT(decided, 10000) << "bodies " << ba << "," << bb;  // the table settles most states
    }
    EXPECT_GE(tables, 2);
    EXPECT_EQ(dims_seen, 6);     // tables over one and over two hinges
    EXPECT_GE(clear_pairs, 1);   // and at least one pair that never collides
    EXPECT_GT(blocked_cells, 0);
  }
}

TEST(PairTable, NoTableWithMoreThanTwoHingesOrAnOffsetAnchor) {
  RobotCollisionSpec spec = spatial_arm_spec();
  const RobotChain chain(spec.bodies);
  PairTableInput in;
  in.chain = &chain;
  in.centre_a = {Vec3::Zero()};
  in.centre_b = {Vec3::Zero()};
  in.radius_a = {0.01};
  in.radius_b = {0.01};
  in.pairs = {{0, 0}};
  in.q_min_rad = spec.q_min_rad;
  in.q_max_rad = spec.q_max_rad;
  PairTable t;
  in.body_a = 1;
  in.body_b = 5;  // joints 0..3 between the base and link 5
  EXPECT_FALSE(build_pair_table(in, t));
  in.body_b = 3;  // joints 0 and 1
  EXPECT_TRUE(build_pair_table(in, t));
  EXPECT_EQ(t.dims, 2);
  spec.bodies[3].anchor = Vec3(0.01, 0, 0);
  const RobotChain anchored(spec.bodies);
  in.chain = &anchored;
  EXPECT_FALSE(build_pair_table(in, t));
  in.chain = &chain;
  in.body_a = 5;
  in.body_b = 6;  // the tool is fixed on link 5: no hinge, one cell
  EXPECT_TRUE(build_pair_table(in, t));
  EXPECT_EQ(t.dims, 0);
  EXPECT_EQ(t.cells.size(), 1u);
}
