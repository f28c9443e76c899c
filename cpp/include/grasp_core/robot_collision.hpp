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
// bound wholly outside the map's grid is clear of the map at once (every sphere's lookup
// would be +inf): most links of random states are, and this saves ~90 lookups per state.
// Self-collision: per checked link pair a descent of both links' bounding-sphere trees
// (or link pair -> geom pair -> sphere pair when the pair list is not whole link pairs).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "grasp_core/collision_scene.hpp"
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
  struct GeomPair { int ga = 0, gb = 0, begin = 0, end = 0; };   ///< sphere pairs [begin, end)
  struct LinkPair { int la = 0, lb = 0, begin = 0, end = 0; };   ///< geom pairs [begin, end)

  const std::vector<Link>& links() const { return links_; }
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

 private:
  RobotCollisionSpec spec_;
  RobotChain chain_;
  std::vector<Link> links_;
  std::vector<int> link_of_body_;
  std::vector<Bound> geom_bounds_;
  std::vector<GeomPair> geom_pairs_;
  std::vector<LinkPair> link_pairs_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<Node> nodes_;
  std::vector<int> link_roots_;
  bool complete_ = false;

  int build_tree(std::vector<int>& spheres, std::size_t begin, std::size_t end);
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
  std::shared_ptr<const CollisionScene> scene() const;

  std::shared_ptr<const RobotCollisionModel> robot_;
  std::shared_ptr<const CollisionScene> scene_;
  mutable std::mutex scene_mutex_;
  std::atomic<bool> allow_target_{false};
  mutable std::atomic<std::uint64_t> checked_{0};
};

}  // namespace grasp_core
