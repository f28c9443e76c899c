// Self-collision of a link pair decided ahead of time, over the joints between them.
//
// Two links of a chain move relative to each other only through the hinges on the path
// between them. Over a box of those joint values, a point of a link turned by hinge k moves
// by at most (its distance to the axis of k) * (the angle change), so a sphere pair's
// clearance over the box lies within its clearance at the box centre plus or minus the sum
// over the hinges of lever * half-width. For a pair with at most two hinges between its
// links, the joint box of the limits is cut into a grid of cells (a table); branch and bound
// over the grid marks each cell
//   clear:   every listed sphere pair keeps clearance >= margin + allowance in the whole cell,
//   blocked: one listed sphere pair has clearance < margin - allowance in the whole cell,
//   unknown: neither (the per-state test decides there).
// A cell that is neither as a whole is halved a few more times to try to prove it clear.
// The per-state verdict of a clear or blocked cell is the one the sphere test would give, so
// verdicts are unchanged. Hinges with an offset anchor are not handled (no table). The
// lever bounds are checked against sampled states in tests/cpp/test_pair_table.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "grasp_core/robot_chain.hpp"
#include "grasp_core/types.hpp"

namespace grasp_core {

/// Allowance the tables keep from the margin [m] (far above the rounding of the per-state
/// test, so a cell's verdict holds for the floating-point test too).
constexpr double kPairTableAllowance_m = 1e-7;

struct PairTableInput {
  const RobotChain* chain = nullptr;
  int body_a = 0, body_b = 0;
  std::vector<Vec3> centre_a, centre_b;    ///< sphere centres in their body frames [m]
  std::vector<double> radius_a, radius_b;  ///< [m]
  std::vector<std::pair<int, int>> pairs;  ///< (index into a, index into b)
  std::array<double, kArmJoints> q_min_rad{}, q_max_rad{};
  double margin_m = 0.0;
  int cells_per_joint = 64;
};

struct PairTable {
  enum Cell : std::uint8_t { unknown = 0, clear = 1, blocked = 2 };
  int dims = 0;                        ///< hinges between the links (0, 1 or 2)
  std::array<int, 2> joint{{0, 0}};    ///< arm-state index of each grid axis
  std::array<int, 2> n{{1, 1}};        ///< cells per axis
  std::array<double, 2> q0{{0, 0}}, inv_width{{0, 0}};  ///< first cell's lower edge, 1 / cell width
  std::vector<std::uint8_t> cells;     ///< row-major (axis 0 slowest)
  bool all_clear = false;

  bool all_unknown() const {
    for (std::uint8_t c : cells)
      if (c != unknown) return false;
    return true;
  }

  /// The cell of arm state q (within the limits; indices clamped into the grid).
  Cell at(const double* q) const {
    int idx = 0;
    for (int d = 0; d < dims; ++d) {
      const double x = (q[joint[d]] - q0[d]) * inv_width[d];
      const int i = x <= 0.0 ? 0 : (x >= static_cast<double>(n[d] - 1) ? n[d] - 1 : static_cast<int>(x));
      idx = idx * n[d] + i;
    }
    return static_cast<Cell>(cells[static_cast<std::size_t>(idx)]);
  }
};

/// The table of a link pair, or false when there is none (more than two hinges between the
/// links, or a hinge with an offset anchor). Built tables are kept, keyed by everything they
/// depend on, so a model built again (another finger opening) rebuilds only the tables of
/// the pairs that changed. Thread-safe.
bool build_pair_table(const PairTableInput& in, PairTable& out);

}  // namespace grasp_core
