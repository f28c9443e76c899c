#include "grasp_core/robot_collision.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

namespace grasp_core {

namespace {

/// Allowance of the link-level bounding tests [m]: covers the float32 rounding of the
/// distance field and double rounding of posed centres, so "clear" stays conservative.
constexpr double kBoundSlack_m = 1e-6;
const double kSqrt3 = std::sqrt(3.0);

void fail(const std::string& what) { throw std::invalid_argument("robot collision model: " + what); }

RobotCollisionModel::Bound bound_of(int body, const std::vector<int>& idx, const RobotCollisionSpec& s) {
  RobotCollisionModel::Bound b;
  b.body = body;
  if (idx.empty()) return b;
  Vec3 c = Vec3::Zero();
  for (int i : idx) c += s.sphere_center[static_cast<std::size_t>(i)];
  c /= static_cast<double>(idx.size());
  double r = 0.0;
  for (int i : idx)
    r = std::max(r, (s.sphere_center[static_cast<std::size_t>(i)] - c).norm() + s.sphere_radius[static_cast<std::size_t>(i)]);
  b.center = c;
  b.radius = r;
  return b;
}

void validate(const RobotCollisionSpec& s) {
  const std::size_t n = s.sphere_radius.size();
  if (s.sphere_body.size() != n || s.sphere_center.size() != n || s.sphere_geom.size() != n ||
      s.env_sphere.size() != n || s.hand_sphere.size() != n)
    fail("per-sphere arrays must have the same length");
  const int nb = static_cast<int>(s.bodies.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (s.sphere_body[i] < 0 || s.sphere_body[i] >= nb) fail("sphere body index out of range");
    if (s.sphere_geom[i] < 0) fail("negative sphere geom id");
    if (!s.sphere_center[i].allFinite() || !(s.sphere_radius[i] >= 0.0) || !std::isfinite(s.sphere_radius[i]))
      fail("sphere centres must be finite and radii finite >= 0");
  }
  for (const auto& pr : s.pairs)
    if (pr.first < 0 || pr.second < 0 || static_cast<std::size_t>(pr.first) >= n ||
        static_cast<std::size_t>(pr.second) >= n)
      fail("self-collision pair index out of range");
  for (int j = 0; j < kArmJoints; ++j)
    if (!std::isfinite(s.q_min_rad[j]) || !std::isfinite(s.q_max_rad[j]) || s.q_min_rad[j] > s.q_max_rad[j])
      fail("joint limits must be finite with q_min <= q_max");
  if (!std::isfinite(s.self_margin_m)) fail("self margin must be finite");
}

}  // namespace

RobotCollisionModel::RobotCollisionModel(RobotCollisionSpec spec) : spec_(std::move(spec)) {
  validate(spec_);
  chain_ = RobotChain(spec_.bodies);
  const RobotCollisionSpec& s = spec_;
  link_of_body_.assign(s.bodies.size(), -1);
  for (std::size_t i = 0; i < s.sphere_radius.size(); ++i) {
    const int b = s.sphere_body[i];
    if (link_of_body_[static_cast<std::size_t>(b)] < 0) {
      link_of_body_[static_cast<std::size_t>(b)] = static_cast<int>(links_.size());
      links_.push_back(Link{});
      links_.back().body = b;
    }
    Link& l = links_[static_cast<std::size_t>(link_of_body_[static_cast<std::size_t>(b)])];
    l.spheres.push_back(static_cast<int>(i));
    if (s.env_sphere[i]) l.env_spheres.push_back(static_cast<int>(i));
    if (s.hand_sphere[i] && s.env_sphere[i]) l.has_hand = true;
  }
  for (Link& l : links_) {
    l.all = bound_of(l.body, l.spheres, s);
    l.env = bound_of(l.body, l.env_spheres, s);
  }
  // geom bounds (a geom's spheres are in one body)
  std::map<int, std::vector<int>> by_geom;
  for (std::size_t i = 0; i < s.sphere_radius.size(); ++i) by_geom[s.sphere_geom[i]].push_back(static_cast<int>(i));
  std::map<int, int> geom_slot;
  for (const auto& [g, idx] : by_geom) {
    const int b = s.sphere_body[static_cast<std::size_t>(idx[0])];
    for (int i : idx)
      if (s.sphere_body[static_cast<std::size_t>(i)] != b) fail("spheres of one geom on different bodies");
    geom_slot[g] = static_cast<int>(geom_bounds_.size());
    geom_bounds_.push_back(bound_of(b, idx, s));
  }
  // sphere pairs sorted by (link pair, geom pair)
  using Key = std::tuple<int, int, int, int>;
  std::vector<std::pair<Key, std::pair<int, int>>> keyed;
  keyed.reserve(s.pairs.size());
  for (auto pr : s.pairs) {
    int la = link_of_body_[static_cast<std::size_t>(s.sphere_body[static_cast<std::size_t>(pr.first)])];
    int lb = link_of_body_[static_cast<std::size_t>(s.sphere_body[static_cast<std::size_t>(pr.second)])];
    if (la > lb) { std::swap(la, lb); std::swap(pr.first, pr.second); }
    const int ga = geom_slot[s.sphere_geom[static_cast<std::size_t>(pr.first)]];
    const int gb = geom_slot[s.sphere_geom[static_cast<std::size_t>(pr.second)]];
    keyed.push_back({Key{la, lb, ga, gb}, pr});
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    const auto& [la, lb, ga, gb] = keyed[k].first;
    pairs_.push_back(keyed[k].second);
    const bool new_geom = k == 0 || keyed[k].first != keyed[k - 1].first;
    const bool new_link = k == 0 || std::get<0>(keyed[k - 1].first) != la || std::get<1>(keyed[k - 1].first) != lb;
    if (new_link) link_pairs_.push_back(LinkPair{la, lb, static_cast<int>(geom_pairs_.size()), 0});
    if (new_geom) geom_pairs_.push_back(GeomPair{ga, gb, static_cast<int>(k), 0});
    geom_pairs_.back().end = static_cast<int>(k) + 1;
    link_pairs_.back().end = static_cast<int>(geom_pairs_.size());
  }
  // bounding-sphere trees; usable when every link pair is complete and has no duplicates
  complete_ = true;
  for (const LinkPair& lp : link_pairs_) {
    std::set<std::pair<int, int>> seen;
    for (int g = lp.begin; g < lp.end; ++g)
      for (int k = geom_pairs_[static_cast<std::size_t>(g)].begin; k < geom_pairs_[static_cast<std::size_t>(g)].end; ++k)
        seen.insert(pairs_[static_cast<std::size_t>(k)]);
    const std::size_t full = links_[static_cast<std::size_t>(lp.la)].spheres.size() *
                             links_[static_cast<std::size_t>(lp.lb)].spheres.size();
    const std::size_t count = static_cast<std::size_t>(geom_pairs_[static_cast<std::size_t>(lp.end - 1)].end -
                                                       geom_pairs_[static_cast<std::size_t>(lp.begin)].begin);
    if (lp.la == lp.lb || seen.size() != full || count != full) complete_ = false;
  }
  for (Link& l : links_) {
    std::vector<int> idx = l.spheres;
    link_roots_.push_back(build_tree(idx, 0, idx.size()));
  }
}

int RobotCollisionModel::build_tree(std::vector<int>& idx, std::size_t begin, std::size_t end) {
  const RobotCollisionSpec& s = spec_;
  Vec3 lo = s.sphere_center[static_cast<std::size_t>(idx[begin])], hi = lo;
  for (std::size_t k = begin; k < end; ++k) {
    lo = lo.cwiseMin(s.sphere_center[static_cast<std::size_t>(idx[k])]);
    hi = hi.cwiseMax(s.sphere_center[static_cast<std::size_t>(idx[k])]);
  }
  Node n;
  n.center = 0.5 * (lo + hi);
  for (std::size_t k = begin; k < end; ++k) {
    const std::size_t i = static_cast<std::size_t>(idx[k]);
    n.radius = std::max(n.radius, (s.sphere_center[i] - n.center).norm() + s.sphere_radius[i]);
  }
  const int self = static_cast<int>(nodes_.size());
  nodes_.push_back(n);
  if (end - begin == 1) {
    nodes_[static_cast<std::size_t>(self)].sphere = idx[begin];
    return self;
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::size_t mid = begin + (end - begin) / 2;
  std::nth_element(idx.begin() + static_cast<std::ptrdiff_t>(begin), idx.begin() + static_cast<std::ptrdiff_t>(mid),
                   idx.begin() + static_cast<std::ptrdiff_t>(end), [&](int a, int b) {
                     return s.sphere_center[static_cast<std::size_t>(a)][axis] < s.sphere_center[static_cast<std::size_t>(b)][axis];
                   });
  const int left = build_tree(idx, begin, mid);
  const int right = build_tree(idx, mid, end);
  nodes_[static_cast<std::size_t>(self)].left = left;
  nodes_[static_cast<std::size_t>(self)].right = right;
  return self;
}

namespace {

/// Per-call scratch space and the checks of one state.
/// Scratch buffers of one thread, reused by every evaluation on that thread (no allocation
/// per call). Node stamps only grow, so entries left by another model never match.
struct Scratch {
  std::vector<Mat3> R;
  std::vector<Vec3> p, c, node_w;
  std::vector<std::uint8_t> posed;
  std::vector<int> near_boxes;
  std::vector<std::uint32_t> node_stamp;
  std::uint32_t stamp = 0;
  bool busy = false;
};

Scratch& thread_scratch() {
  thread_local Scratch s;
  return s;
}

class Evaluator {
 public:
  Evaluator(const RobotCollisionModel& m, const CollisionScene& sc, bool allow_target)
      : m_(m), s_(m.spec()), sc_(sc), allow_(allow_target && sc.has_cleared),
        own_(thread_scratch().busy ? std::make_unique<Scratch>() : nullptr),
        w_(own_ ? *own_ : thread_scratch()),
        R_(w_.R), p_(w_.p), c_(w_.c), posed_(w_.posed), near_boxes_(w_.near_boxes),
        node_w_(w_.node_w), node_stamp_(w_.node_stamp), stamp_(w_.stamp) {
    w_.busy = true;
    R_.resize(static_cast<std::size_t>(m.chain().num_bodies()));
    p_.resize(R_.size());
    c_.resize(s_.sphere_radius.size());
    posed_.resize(m.links().size());
    node_w_.resize(m.nodes().size());
    node_stamp_.resize(m.nodes().size(), 0);
    near_boxes_.reserve(sc.boxes.size());
  }
  ~Evaluator() { w_.busy = false; }
  Evaluator(const Evaluator&) = delete;
  Evaluator& operator=(const Evaluator&) = delete;

  bool valid(const double* q) {
    for (int j = 0; j < kArmJoints; ++j)
      if (!(q[j] >= s_.q_min_rad[j] && q[j] <= s_.q_max_rad[j])) return false;
    m_.chain().poses(q, R_.data(), p_.data());
    std::fill(posed_.begin(), posed_.end(), 0);
    if (++stamp_ == 0) {  // wrapped: invalidate every cached node
      std::fill(node_stamp_.begin(), node_stamp_.end(), 0);
      stamp_ = 1;
    }
    const auto& links = m_.links();
    for (std::size_t l = 0; l < links.size(); ++l)
      if (!links[l].env_spheres.empty() && !link_env_ok(static_cast<int>(l))) return false;
    return self_ok();
  }

  const Vec3* centres(const double* q) {
    m_.chain().poses(q, R_.data(), p_.data());
    std::fill(posed_.begin(), posed_.end(), 0);
    for (std::size_t l = 0; l < m_.links().size(); ++l) pose_link(static_cast<int>(l));
    return c_.data();
  }

 private:
  Vec3 world(const RobotCollisionModel::Bound& b) const {
    return p_[static_cast<std::size_t>(b.body)] + R_[static_cast<std::size_t>(b.body)] * b.center;
  }

  void pose_link(int l) {
    if (posed_[static_cast<std::size_t>(l)]) return;
    const auto& link = m_.links()[static_cast<std::size_t>(l)];
    const Mat3& R = R_[static_cast<std::size_t>(link.body)];
    const Vec3& p = p_[static_cast<std::size_t>(link.body)];
    for (int i : link.spheres) {
      // p + R c, summed like numpy's einsum over j (x, y, z order)
      const Vec3& c = s_.sphere_center[static_cast<std::size_t>(i)];
      c_[static_cast<std::size_t>(i)] = p + R * c;
    }
    posed_[static_cast<std::size_t>(l)] = 1;
  }

  /// Floor, map and boxes for every environment sphere of link l.
  bool link_env_ok(int l) {
    const auto& link = m_.links()[static_cast<std::size_t>(l)];
    const Vec3 cb = world(link.env);
    const double rad = link.env.radius;
    const double margin = sc_.collision_margin_m;
    const bool floor_clear = (cb.z() - rad) - sc_.floor_z_m >= kBoundSlack_m;
    bool map_clear = true;
    const bool cleared_here = allow_ && link.has_hand &&
                              !(sc_.cleared.box().distance(cb) - rad > sc_.cleared.pad_m() + kBoundSlack_m);
    if (sc_.has_env && !sc_.field.empty()) {
      // The bound lies wholly outside the grid: every sphere's lookup is +inf (clear).
      // Else, inside the grid, the value at cb bounds every sphere's value (1-Lipschitz field).
      if (sc_.field.distance_to_grid(cb) > rad + kBoundSlack_m) {
        map_clear = !cleared_here;
      } else {
        const double d = sc_.field.at(cb);
        map_clear = !cleared_here && d < kInfinity &&
                    d - kSqrt3 * sc_.field.voxel_m - rad - margin - sc_.field.inflation_m >= kBoundSlack_m;
      }
    } else if (sc_.has_env) {
      map_clear = !cleared_here;
    }
    near_boxes_.clear();
    for (std::size_t k = 0; k < sc_.boxes.size(); ++k) {
      const ObstacleBox& b = sc_.boxes[k];
      const double reach = rad + margin + kBoundSlack_m;
      const double far = reach + b.bound_radius_m;
      if ((cb - b.center).squaredNorm() >= far * far) continue;
      if (b.distance(cb) >= reach) continue;
      near_boxes_.push_back(static_cast<int>(k));
    }
    const bool points_clear = !sc_.has_points ||
        sc_.points.box().distance(cb) - rad - margin - sc_.points.fine_m() >= kBoundSlack_m;
    if (floor_clear && map_clear && points_clear && near_boxes_.empty()) return true;
    pose_link(l);
    for (int i : link.env_spheres) {
      const Vec3& c = c_[static_cast<std::size_t>(i)];
      const double r = s_.sphere_radius[static_cast<std::size_t>(i)];
      if (!floor_clear && !((c.z() - r) - sc_.floor_z_m >= 0.0)) return false;
      if (!map_clear && !sphere_map_ok(i, c, r)) return false;
      for (int k : near_boxes_)
        if (!(sc_.boxes[static_cast<std::size_t>(k)].distance(c) - (r + margin) >= 0.0)) return false;
      if (!points_clear && sc_.points.blocked(c, r + margin)) return false;
    }
    return true;
  }

  bool sphere_map_ok(int i, const Vec3& c, double r) const {
    if (!sc_.has_env) return true;
    const double thr = (r + sc_.collision_margin_m) + sc_.field.inflation_m;
    if (allow_ && s_.hand_sphere[static_cast<std::size_t>(i)] && sc_.cleared.near(c)) return !sc_.cleared.blocked(c, thr);
    return sc_.field.at(c) - thr >= 0.0;
  }

  bool self_ok() { return m_.complete_link_pairs() ? self_ok_trees() : self_ok_lists(); }

  /// World centre of tree node k (of a link on `body`), computed once per state.
  const Vec3& node_world(int body, int k) {
    const std::size_t u = static_cast<std::size_t>(k);
    if (node_stamp_[u] != stamp_) {
      node_w_[u] = p_[static_cast<std::size_t>(body)] + R_[static_cast<std::size_t>(body)] * m_.nodes()[u].center;
      node_stamp_[u] = stamp_;
    }
    return node_w_[u];
  }

  /// Descent of both links' trees for every checked link pair.
  bool self_ok_trees() {
    const double margin = s_.self_margin_m;
    const auto& links = m_.links();
    const auto& nodes = m_.nodes();
    const auto& roots = m_.link_roots();
    constexpr int kStack = 128;
    std::pair<int, int> stack[kStack];
    for (const auto& lp : m_.link_pairs()) {
      const int ba = links[static_cast<std::size_t>(lp.la)].body, bb = links[static_cast<std::size_t>(lp.lb)].body;
      int top = 0;
      stack[top++] = {roots[static_cast<std::size_t>(lp.la)], roots[static_cast<std::size_t>(lp.lb)]};
      bool posed = false;
      while (top > 0) {
        const auto [a, b] = stack[--top];
        const auto& A = nodes[static_cast<std::size_t>(a)];
        const auto& B = nodes[static_cast<std::size_t>(b)];
        if (A.sphere >= 0 && B.sphere >= 0) {
          if (!posed) { pose_link(lp.la); pose_link(lp.lb); posed = true; }
          if (!sphere_pair_ok(A.sphere, B.sphere, margin)) return false;
          continue;
        }
        const double reach = A.radius + B.radius + margin + kBoundSlack_m;
        if (reach > 0.0 && (node_world(ba, a) - node_world(bb, b)).squaredNorm() >= reach * reach) continue;
        if (top + 2 > kStack) throw std::logic_error("self-collision tree descent: stack overflow");
        if (A.sphere >= 0 || (B.sphere < 0 && B.radius > A.radius)) {
          stack[top++] = {a, B.left};
          stack[top++] = {a, B.right};
        } else {
          stack[top++] = {A.left, b};
          stack[top++] = {A.right, b};
        }
      }
    }
    return true;
  }

  bool sphere_pair_ok(int i, int j, double margin) const {
    const Vec3& ci = c_[static_cast<std::size_t>(i)];
    const Vec3& cj = c_[static_cast<std::size_t>(j)];
    const double dx = ci.x() - cj.x(), dy = ci.y() - cj.y(), dz = ci.z() - cj.z();
    const double rsum = s_.sphere_radius[static_cast<std::size_t>(i)] + s_.sphere_radius[static_cast<std::size_t>(j)];
    return std::sqrt(dx * dx + dy * dy + dz * dz) - rsum >= margin;
  }

  bool self_ok_lists() {
    const double margin = s_.self_margin_m;
    const auto& links = m_.links();
    const auto& gb = m_.geom_bounds();
    const auto& gps = m_.geom_pairs();
    const auto& pairs = m_.sorted_pairs();
    for (const auto& lp : m_.link_pairs()) {
      const auto& A = links[static_cast<std::size_t>(lp.la)];
      const auto& B = links[static_cast<std::size_t>(lp.lb)];
      if ((world(A.all) - world(B.all)).norm() - (A.all.radius + B.all.radius) - margin >= kBoundSlack_m) continue;
      for (int g = lp.begin; g < lp.end; ++g) {
        const auto& gp = gps[static_cast<std::size_t>(g)];
        const auto& ga = gb[static_cast<std::size_t>(gp.ga)];
        const auto& gbb = gb[static_cast<std::size_t>(gp.gb)];
        if ((world(ga) - world(gbb)).norm() - (ga.radius + gbb.radius) - margin >= kBoundSlack_m) continue;
        pose_link(lp.la);
        pose_link(lp.lb);
        for (int k = gp.begin; k < gp.end; ++k) {
          const auto& pr = pairs[static_cast<std::size_t>(k)];
          if (!sphere_pair_ok(pr.first, pr.second, margin)) return false;
        }
      }
    }
    return true;
  }

  const RobotCollisionModel& m_;
  const RobotCollisionSpec& s_;
  const CollisionScene& sc_;
  const bool allow_;
  std::unique_ptr<Scratch> own_;  ///< only when the thread's scratch is in use already
  Scratch& w_;
  std::vector<Mat3>& R_;
  std::vector<Vec3>& p_;
  std::vector<Vec3>& c_;
  std::vector<std::uint8_t>& posed_;
  std::vector<int>& near_boxes_;
  std::vector<Vec3>& node_w_;
  std::vector<std::uint32_t>& node_stamp_;
  std::uint32_t& stamp_;
};

}  // namespace

StateChecker::StateChecker(std::shared_ptr<const RobotCollisionModel> robot,
                           std::shared_ptr<const CollisionScene> scene)
    : robot_(std::move(robot)), scene_(std::move(scene)) {
  if (!robot_) throw std::invalid_argument("state checker: robot model is required");
  if (!scene_) scene_ = std::make_shared<const CollisionScene>();
}

void StateChecker::set_scene(std::shared_ptr<const CollisionScene> scene) {
  if (!scene) scene = std::make_shared<const CollisionScene>();
  const std::lock_guard<std::mutex> lock(scene_mutex_);
  scene_ = std::move(scene);
}

std::shared_ptr<const CollisionScene> StateChecker::scene() const {
  const std::lock_guard<std::mutex> lock(scene_mutex_);
  return scene_;
}

bool StateChecker::check(const double* q) const {
  const auto sc = scene();
  Evaluator ev(*robot_, *sc, allow_target_contact());
  checked_.fetch_add(1, std::memory_order_relaxed);
  return ev.valid(q);
}

void StateChecker::check_batch(const double* Q, std::size_t n, std::uint8_t* out) const {
  const auto sc = scene();
  Evaluator ev(*robot_, *sc, allow_target_contact());
  for (std::size_t k = 0; k < n; ++k) out[k] = ev.valid(Q + k * kArmJoints) ? 1 : 0;
  checked_.fetch_add(n, std::memory_order_relaxed);
}

bool StateChecker::check_segment(const double* qa, const double* qb, double max_step_rad,
                                 bool include_start) const {
  if (!(max_step_rad > 0.0) || !std::isfinite(max_step_rad))
    throw std::invalid_argument("check_segment: max_step_rad must be finite and > 0");
  double span = 0.0;
  for (int j = 0; j < kArmJoints; ++j) span = std::max(span, std::abs(qb[j] - qa[j]));
  const double steps = std::ceil(span / max_step_rad);
  if (!(steps < 1e9)) throw std::invalid_argument("check_segment: more than 1e9 states on the segment");
  const long long n = std::max(1LL, static_cast<long long>(steps));
  const auto sc = scene();
  Evaluator ev(*robot_, *sc, allow_target_contact());
  double q[kArmJoints];
  std::uint64_t done = 0;
  auto state_ok = [&](long long k) {
    const double s = static_cast<double>(k) / static_cast<double>(n);
    for (int j = 0; j < kArmJoints; ++j) q[j] = qa[j] + (qb[j] - qa[j]) * s;
    ++done;
    return ev.valid(q);
  };
  bool ok = true;
  // the end state first, then coarse-to-fine: multiples of stride not seen at a coarser level
  long long stride = 1;
  while (stride * 2 <= n) stride *= 2;
  ok = state_ok(n);
  for (long long st = stride; ok && st >= 1; st /= 2)
    for (long long k = st; ok && k < n; k += st)
      if (st == stride || (k / st) % 2 == 1) ok = state_ok(k);
  if (ok && include_start) ok = state_ok(0);
  checked_.fetch_add(done, std::memory_order_relaxed);
  return ok;
}

bool StateChecker::first_invalid_on_path(const double* W, std::size_t m, double max_step_rad,
                                         long long* segment, long long* index) const {
  if (!(max_step_rad > 0.0) || !std::isfinite(max_step_rad))
    throw std::invalid_argument("first_invalid_on_path: max_step_rad must be finite and > 0");
  *segment = -1;
  *index = -1;
  const auto sc = scene();
  Evaluator ev(*robot_, *sc, allow_target_contact());
  double q[kArmJoints];
  std::uint64_t done = 0;
  bool ok = true;
  for (std::size_t k = 0; ok && k + 1 < m; ++k) {
    const double* qa = W + k * kArmJoints;
    const double* qb = qa + kArmJoints;
    double span = 0.0;
    for (int j = 0; j < kArmJoints; ++j) span = std::max(span, std::abs(qb[j] - qa[j]));
    const double steps = std::ceil(span / max_step_rad);
    if (!(steps < 1e9)) throw std::invalid_argument("first_invalid_on_path: more than 1e9 states on a segment");
    const long long n = std::max(1LL, static_cast<long long>(steps));
    for (long long i = 1; i <= n; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(n);
      for (int j = 0; j < kArmJoints; ++j) q[j] = qa[j] + (qb[j] - qa[j]) * s;
      ++done;
      if (!ev.valid(q)) {
        ok = false;
        *segment = static_cast<long long>(k);
        *index = i - 1;
        break;
      }
    }
  }
  checked_.fetch_add(done, std::memory_order_relaxed);
  return ok;
}

void StateChecker::sphere_centres(const double* q, Vec3* out) const {
  const auto sc = scene();
  Evaluator ev(*robot_, *sc, false);
  const Vec3* c = ev.centres(q);
  std::copy(c, c + robot_->num_spheres(), out);
}

}  // namespace grasp_core
