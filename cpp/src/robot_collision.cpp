#include "grasp_core/robot_collision.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>

namespace grasp_core {

namespace {

/// Sphere pairs from which a link pair gets a fine joint-space table (64 cells per joint).
constexpr std::size_t kFinePairTable = 64;

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
  for (std::size_t k = 0; k < links_.size(); ++k) {
    Link& l = links_[k];
    l.all = bound_of(l.body, l.spheres, s);
    l.env = bound_of(l.body, l.env_spheres, s);
    if (l.env_spheres.empty()) continue;
    env_bounds_.push_back(EnvBound{static_cast<int>(k), l.body, {l.env.center.x(), l.env.center.y(), l.env.center.z()},
                                   l.env.radius, l.has_hand});
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
  std::vector<std::pair<int, int>> seen;
  for (const LinkPair& lp : link_pairs_) {
    seen.assign(pairs_.begin() + geom_pairs_[static_cast<std::size_t>(lp.begin)].begin,
                pairs_.begin() + geom_pairs_[static_cast<std::size_t>(lp.end - 1)].end);
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
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
  precompute_fixed_links();
  build_pair_tables();
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id.fetch_add(1, std::memory_order_relaxed);
}

void RobotCollisionModel::build_pair_tables() {
  const std::size_t ns = spec_.sphere_radius.size();
  std::vector<int> slot_a(ns, -1), slot_b(ns, -1);  // sphere -> index in the table input
  for (LinkPair& lp : link_pairs_) {
    PairTableInput in;
    in.chain = &chain_;
    in.body_a = links_[static_cast<std::size_t>(lp.la)].body;
    in.body_b = links_[static_cast<std::size_t>(lp.lb)].body;
    if (in.body_a == in.body_b) continue;
    auto slot = [&](std::vector<int>& slots, std::vector<Vec3>& c, std::vector<double>& r, int i) {
      int& k = slots[static_cast<std::size_t>(i)];
      if (k < 0) {
        k = static_cast<int>(c.size());
        c.push_back(spec_.sphere_center[static_cast<std::size_t>(i)]);
        r.push_back(spec_.sphere_radius[static_cast<std::size_t>(i)]);
      }
      return k;
    };
    const int first = geom_pairs_[static_cast<std::size_t>(lp.begin)].begin;
    const int last = geom_pairs_[static_cast<std::size_t>(lp.end - 1)].end;
    for (int k = first; k < last; ++k) {
      const auto& pr = pairs_[static_cast<std::size_t>(k)];
      in.pairs.emplace_back(slot(slot_a, in.centre_a, in.radius_a, pr.first), slot(slot_b, in.centre_b, in.radius_b, pr.second));
    }
    for (int k = first; k < last; ++k) {
      slot_a[static_cast<std::size_t>(pairs_[static_cast<std::size_t>(k)].first)] = -1;
      slot_b[static_cast<std::size_t>(pairs_[static_cast<std::size_t>(k)].second)] = -1;
    }
    in.q_min_rad = spec_.q_min_rad;
    in.q_max_rad = spec_.q_max_rad;
    in.margin_m = spec_.self_margin_m;
    // few sphere pairs: a cheap test per state, so a coarse table (the fingers' tables are
    // built again for every finger opening)
    in.cells_per_joint = in.pairs.size() < kFinePairTable ? 16 : 64;
    PairTable table;
    if (!build_pair_table(in, table)) continue;
    lp.always_clear = table.all_clear;
    if (lp.always_clear || table.all_unknown()) continue;
    lp.table = static_cast<int>(tables_.size());
    tables_.push_back(std::move(table));
  }
  // the order of the per-state tests: pairs with a table first (a lookup settles most states)
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k = 0; k < link_pairs_.size(); ++k) {
      const LinkPair& lp = link_pairs_[k];
      if (lp.always_clear || (lp.table >= 0) != (pass == 0)) continue;
      const int ra = link_roots_[static_cast<std::size_t>(lp.la)], rb = link_roots_[static_cast<std::size_t>(lp.lb)];
      check_order_.push_back(PairCheck{static_cast<int>(k), ra, rb,
                                       nodes_[static_cast<std::size_t>(ra)].radius + nodes_[static_cast<std::size_t>(rb)].radius,
                                       lp.table});
    }
}

void RobotCollisionModel::precompute_fixed_links() {
  // the same expressions as the checker's per-state posing (p + R c), at any arm state
  const int nb = chain_.num_bodies();
  std::vector<Mat3> R(static_cast<std::size_t>(nb));
  std::vector<Vec3> p(static_cast<std::size_t>(nb));
  const double q[kArmJoints] = {0, 0, 0, 0, 0, 0, 0};
  chain_.poses(q, R.data(), p.data());
  fixed_sphere_w_.assign(spec_.sphere_radius.size(), Vec3::Zero());
  fixed_node_w_.assign(nodes_.size(), Vec3::Zero());
  for (std::size_t l = 0; l < links_.size(); ++l) {
    const Link& link = links_[l];
    link_fixed_.push_back(chain_.body_fixed(link.body));
    if (!link_fixed_.back()) continue;
    const Mat3& Rb = R[static_cast<std::size_t>(link.body)];
    const Vec3& pb = p[static_cast<std::size_t>(link.body)];
    for (int i : link.spheres)
      fixed_sphere_w_[static_cast<std::size_t>(i)] = pb + Rb * spec_.sphere_center[static_cast<std::size_t>(i)];
    std::vector<int> todo = {link_roots_[l]};
    while (!todo.empty()) {
      const Node& n = nodes_[static_cast<std::size_t>(todo.back())];
      fixed_node_w_[static_cast<std::size_t>(todo.back())] = pb + Rb * n.center;
      todo.pop_back();
      if (n.left >= 0) { todo.push_back(n.left); todo.push_back(n.right); }
    }
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

}  // namespace grasp_core
