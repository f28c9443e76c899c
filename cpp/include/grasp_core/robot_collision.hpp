// State validity of the arm against itself and one perceived scene (the C++ twin of
// python/grasp_pipeline/motion/validity.py, StateValidator.check_batch semantics).
//
// A joint state q (7 values, rad) is valid when
// * q_min <= q <= q_max on every joint;
// * every self-collision sphere pair keeps |c_i - c_j| - (r_i + r_j) >= self_margin_m;
// * every environment sphere (spheres of moving links) keeps
//     floor:  (z - r) - floor_z_m >= 0,
//     map:    field(c) - ((r + collision_margin_m) + inflation_m) >= 0   (see DistanceField),
//     boxes:  box.distance(c) - (r + collision_margin_m) >= 0 for every object box;
//   with allow_target_contact, the map value of a hand sphere within pad of the cleared
//   box is the cleared region's answer instead (see ClearedRegion).
//
// Speed: bounding spheres per link (in the link frame, posed by one transform) are tested
// first and settle most links without posing their spheres; they are conservative (a
// link-level "clear" implies every member sphere passes the exact test, with a 1 µm
// allowance for the float32 distance field), so results equal the sphere-level test. A link
// bound wholly outside the box around every obstacle of the scene (map grid, object boxes,
// object points, each grown by its clearance) is clear of all of them with one test; else
// each obstacle's own box is tried, and the map by the distance field at the grid voxel
// nearest the bound's centre.
// Self-collision: link pairs with at most two hinges between them are decided ahead of time
// where that can be proven (pair_table.hpp): never tested when clear everywhere within the
// joint limits, else a lookup in a table over those joints settles most states. The other
// states and pairs: a descent of both links' bounding-sphere trees (or link pair -> geom
// pair -> sphere pair when the pair list is not whole link pairs).
// Links whose pose does not depend on the arm state (the base) have their world sphere and
// tree-node centres computed once, with the same arithmetic as per state.
// The state checker itself is in state_checker.cpp.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "grasp_core/collision_scene.hpp"
#include "grasp_core/pair_table.hpp"
#include "grasp_core/robot_chain.hpp"

namespace grasp_core {

/// Everything exported once from the robot model (see the Python exporter, motion/core_checker.py).
struct RobotCollisionSpec {
  std::vector<ChainBody> bodies;
  std::vector<int> sphere_body;
  std::vector<Vec3> sphere_center;   ///< in the body frame [m]
  std::vector<double> sphere_radius; ///< [m]
  std::vector<int> sphere_geom;      ///< spheres of one geom share a bounding sphere
  std::vector<std::uint8_t> env_sphere, hand_sphere;
  std::vector<std::pair<int, int>> pairs;  ///< self-collision sphere pairs
  std::array<double, kArmJoints> q_min_rad{}, q_max_rad{};
  double self_margin_m = 0.0;
};

class RobotCollisionModel {
 public:
  /// Throws std::invalid_argument on inconsistent sizes / indices / non-finite values.
  explicit RobotCollisionModel(RobotCollisionSpec spec);

  const RobotChain& chain() const { return chain_; }
  const RobotCollisionSpec& spec() const { return spec_; }
  int num_spheres() const { return static_cast<int>(spec_.sphere_radius.size()); }

  struct Bound {          ///< a bounding sphere in one body's frame
    int body = 0;
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
  };
  struct Link {           ///< one body carrying spheres
    int body = 0;
    std::vector<int> spheres, env_spheres;
    Bound all, env;       ///< bounds of all / of the environment spheres
    bool has_hand = false;
  };
  /// The environment bound of a link with environment spheres (Link::env, flattened).
  struct EnvBound {
    int link = 0, body = 0;
    double center[3] = {0, 0, 0};
    double radius = 0.0;
    bool hand = false;
  };
  struct GeomPair { int ga = 0, gb = 0, begin = 0, end = 0; };   ///< sphere pairs [begin, end)
  struct LinkPair {
    int la = 0, lb = 0, begin = 0, end = 0;  ///< geom pairs [begin, end)
    bool always_clear = false;  ///< clear everywhere within the joint limits (never tested)
    int table = -1;             ///< its joint-space table (pair_tables()), -1 for none
  };

  const std::vector<Link>& links() const { return links_; }
  const std::vector<EnvBound>& env_bounds() const { return env_bounds_; }
  const std::vector<Bound>& geom_bounds() const { return geom_bounds_; }
  const std::vector<GeomPair>& geom_pairs() const { return geom_pairs_; }
  const std::vector<LinkPair>& link_pairs() const { return link_pairs_; }
  const std::vector<std::pair<int, int>>& sorted_pairs() const { return pairs_; }
  const std::vector<int>& link_of_body() const { return link_of_body_; }

  /// Bounding-sphere tree over one link's spheres (body frame); leaves hold one sphere.
  struct Node {
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    int left = -1, right = -1;  ///< children (-1 for a leaf)
    int sphere = -1;            ///< the leaf's sphere
  };
  const std::vector<Node>& nodes() const { return nodes_; }
  /// Root node of each link's tree.
  const std::vector<int>& link_roots() const { return link_roots_; }
  /// True when the pair list is every sphere pair of its link pairs (then the trees are used).
  bool complete_link_pairs() const { return complete_; }

  /// True when link l's pose does not depend on the arm state.
  bool link_fixed(int l) const { return link_fixed_[static_cast<std::size_t>(l)] != 0; }
  /// World centres of the spheres (S) and tree nodes of the fixed links (others: zero).
  const std::vector<Vec3>& fixed_sphere_world() const { return fixed_sphere_w_; }
  const std::vector<Vec3>& fixed_node_world() const { return fixed_node_w_; }
  /// Joint-space tables of the link pairs with at most two hinges between their links.
  const std::vector<PairTable>& pair_tables() const { return tables_; }
  /// A link pair as the checker tests it per state.
  struct PairCheck {
    int pair = 0;              ///< index into link_pairs()
    int root_a = 0, root_b = 0;  ///< the two links' tree roots
    double radius_sum = 0.0;   ///< of the two roots
    int table = -1;            ///< as LinkPair::table
  };
  /// The link pairs the checker tests per state, in the order it tests them (not the
  /// always-clear ones; those with a table first).
  const std::vector<PairCheck>& check_order() const { return check_order_; }
  /// Identity of this model among all models built in the process (per-thread caches key on it).
  std::uint64_t id() const { return id_; }

 private:
  RobotCollisionSpec spec_;
  RobotChain chain_;
  std::vector<Link> links_;
  std::vector<EnvBound> env_bounds_;
  std::vector<int> link_of_body_;
  std::vector<Bound> geom_bounds_;
  std::vector<GeomPair> geom_pairs_;
  std::vector<LinkPair> link_pairs_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<Node> nodes_;
  std::vector<int> link_roots_;
  bool complete_ = false;
  std::vector<std::uint8_t> link_fixed_;
  std::vector<PairTable> tables_;
  std::vector<PairCheck> check_order_;
  std::vector<Vec3> fixed_sphere_w_, fixed_node_w_;
  std::uint64_t id_ = 0;

  int build_tree(std::vector<int>& spheres, std::size_t begin, std::size_t end);
  void precompute_fixed_links();
  void build_pair_tables();
};

/// What the checker derives from a scene once, when the scene is set.
struct PreparedScene {
  explicit PreparedScene(std::shared_ptr<const CollisionScene> s);
  std::shared_ptr<const CollisionScene> scene;
  /// Axis-aligned boxes around the obstacles the environment spheres are tested against,
  /// each grown by its clearance (plus the bound allowance): the map's grid (when the map has
  /// one), every object box (grown by the margin; its rotation taken as a rotation), the
  /// object points' box (grown by margin + rounding). A link bound farther from one of them
  /// than its radius is clear of that obstacle. Entry 0 is the box around all others.
  enum class Kind : std::uint8_t { all, grid, box, points };
  std::vector<double> lo[3], hi[3];
  std::vector<Kind> kind;
  std::vector<int> box;  ///< the object box of each entry (-1 for the grid and the points)
};

class StateChecker {
 public:
  StateChecker(std::shared_ptr<const RobotCollisionModel> robot,
               std::shared_ptr<const CollisionScene> scene);

  void set_scene(std::shared_ptr<const CollisionScene> scene);
  void set_allow_target_contact(bool allow) { allow_target_.store(allow, std::memory_order_relaxed); }
  bool allow_target_contact() const { return allow_target_.load(std::memory_order_relaxed); }

  /// One state (7 values).
  bool check(const double* q) const;
  /// n states, row-major (n, 7); out[k] = 1 if valid.
  void check_batch(const double* Q, std::size_t n, std::uint8_t* out) const;
  /// Every state qa + (qb - qa) * k / n, k = (include_start ? 0 : 1) .. n, with
  /// n = max(1, ceil(max|qb - qa| / max_step_rad)); coarse-to-fine order, first invalid ends it.
  bool check_segment(const double* qa, const double* qb, double max_step_rad, bool include_start) const;
  /// Dense check of the polyline W (m, 7): per segment k the states qa + (qb - qa) * i / n,
  /// i = 1 .. n, n = max(1, ceil(max|qb - qa| / max_step_rad)) (the start W[0] is not checked),
  /// in path order; returns false at the first invalid state with its segment and i - 1.
  bool first_invalid_on_path(const double* W, std::size_t m, double max_step_rad, long long* segment,
                             long long* index) const;
  /// World sphere centres (S) for q (diagnostics and tests).
  void sphere_centres(const double* q, Vec3* out) const;

  std::uint64_t checked_states() const { return checked_.load(std::memory_order_relaxed); }
  const RobotCollisionModel& robot() const { return *robot_; }

 private:
  std::shared_ptr<const PreparedScene> scene() const;

  std::shared_ptr<const RobotCollisionModel> robot_;
  std::shared_ptr<const PreparedScene> scene_;
  mutable std::mutex scene_mutex_;
  std::atomic<bool> allow_target_{false};
  mutable std::atomic<std::uint64_t> checked_{0};
};

}  // namespace grasp_core
