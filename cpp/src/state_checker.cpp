// The planning state checker (StateChecker, declared in robot_collision.hpp): limits, the
// environment per link (link bound first, spheres only where the bound is not clear) and
// self-collision per link pair (descent of both links' bounding-sphere trees).
//
// Per-state caches live in per-thread scratch buffers (no allocation per call): body poses,
// posed sphere centres per link and world tree-node centres, each stamped with the state it
// was computed for. Entries of the fixed links (pose independent of the arm state) are
// loaded once per model and thread, with a stamp that every state accepts.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "grasp_core/robot_collision.hpp"

namespace grasp_core {

namespace {

/// Allowance of the link-level bounding tests [m]: covers the float32 rounding of the
/// distance field and double rounding of posed centres, so "clear" stays conservative.
constexpr double kBoundSlack_m = 1e-6;
const double kSqrt3 = std::sqrt(3.0);
/// Stamp of entries valid for every state (fixed links); state stamps stay below it.
constexpr std::uint32_t kPermanent = std::numeric_limits<std::uint32_t>::max();

using Model = RobotCollisionModel;

/// Scratch buffers of one thread for one model, reused by every evaluation on that thread.
struct Scratch {
  std::vector<Mat3> R;
  std::vector<Vec3> p, c, node_w;
  std::vector<std::uint32_t> node_stamp, link_stamp;
  std::vector<int> near_boxes;
  std::uint32_t stamp = 0;
  std::uint64_t model = 0;  ///< id of the model whose entries are loaded (0: none)
  std::uint64_t used = 0;   ///< when it was last taken (per-thread count)
  bool busy = false;

  void load(const Model& m) {
    const std::size_t nb = static_cast<std::size_t>(m.chain().num_bodies());
    R.resize(nb);
    p.resize(nb);
    c = m.fixed_sphere_world();
    node_w = m.fixed_node_world();
    link_stamp.assign(m.links().size(), 0);
    node_stamp.assign(m.nodes().size(), 0);
    for (std::size_t l = 0; l < m.links().size(); ++l) {
      if (!m.link_fixed(static_cast<int>(l))) continue;
      link_stamp[l] = kPermanent;
      std::vector<int> todo = {m.link_roots()[l]};
      while (!todo.empty()) {
        const Model::Node& n = m.nodes()[static_cast<std::size_t>(todo.back())];
        node_stamp[static_cast<std::size_t>(todo.back())] = kPermanent;
        todo.pop_back();
        if (n.left >= 0) { todo.push_back(n.left); todo.push_back(n.right); }
      }
    }
    stamp = 0;
    model = m.id();
  }

  /// A new state: every per-state entry becomes stale.
  void next_state() {
    if (++stamp != kPermanent) return;
    for (auto* v : {&node_stamp, &link_stamp})
      for (std::uint32_t& s : *v)
        if (s != kPermanent) s = 0;
    stamp = 1;
  }
};

/// A free scratch of this thread for model `id`: a few are kept (the least recently used is
/// given to a new model), so checkers of different models used in turn keep theirs loaded.
/// Null when all are in use (nested evaluations): the caller then makes its own.
Scratch* thread_scratch(std::uint64_t id) {
  constexpr std::size_t kSlots = 4;
  thread_local std::array<Scratch, kSlots> slots;
  thread_local std::uint64_t clock = 0;
  Scratch* pick = nullptr;
  for (Scratch& s : slots)
    if (!s.busy && s.model == id) { pick = &s; break; }
  if (pick == nullptr)
    for (Scratch& s : slots)
      if (!s.busy && (pick == nullptr || s.used < pick->used)) pick = &s;
  if (pick != nullptr) pick->used = ++clock;
  return pick;
}

/// The obstacle boxes of a prepared scene (see PreparedScene).
void obstacle_boxes(PreparedScene& ps) {
  const CollisionScene& sc = *ps.scene;
  auto add = [&](PreparedScene::Kind kind, int box, const Vec3& lo, const Vec3& hi) {
    for (int k = 0; k < 3; ++k) {
      ps.lo[k].push_back(lo[k]);
      ps.hi[k].push_back(hi[k]);
    }
    ps.kind.push_back(kind);
    ps.box.push_back(box);
  };
  const Vec3 slack = Vec3::Constant(kBoundSlack_m);
  add(PreparedScene::Kind::all, -1, Vec3::Constant(kInfinity), Vec3::Constant(-kInfinity));
  if (sc.has_env && !sc.field.empty()) {
    const DistanceField& f = sc.field;
    const Vec3 n(static_cast<double>(f.nx), static_cast<double>(f.ny), static_cast<double>(f.nz));
    add(PreparedScene::Kind::grid, -1, f.origin - slack, f.origin + n * f.voxel_m + slack);
  }
  for (std::size_t k = 0; k < sc.boxes.size(); ++k) {
    const ObstacleBox& b = sc.boxes[k];
    const Vec3 e = b.R.cwiseAbs() * b.half + Vec3::Constant(sc.collision_margin_m + 2.0 * kBoundSlack_m);
    add(PreparedScene::Kind::box, static_cast<int>(k), b.center - e, b.center + e);
  }
  if (sc.has_points) {
    const ObstacleBox& b = sc.points.box();
    const Vec3 e = b.R.cwiseAbs() * b.half +
                   Vec3::Constant(sc.collision_margin_m + sc.points.fine_m() + 2.0 * kBoundSlack_m);
    add(PreparedScene::Kind::points, -1, b.center - e, b.center + e);
  }
  for (std::size_t k = 1; k < ps.kind.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      ps.lo[a][0] = std::min(ps.lo[a][0], ps.lo[a][k]);
      ps.hi[a][0] = std::max(ps.hi[a][0], ps.hi[a][k]);
    }
}

class Evaluator {
 public:
  Evaluator(const Model& m, const PreparedScene& ps, bool allow_target)
      : m_(m), s_(m.spec()), ps_(ps), sc_(*ps.scene), allow_(allow_target && sc_.has_cleared),
        shared_(thread_scratch(m.id())), own_(shared_ ? nullptr : std::make_unique<Scratch>()),
        w_(shared_ ? *shared_ : *own_) {
    w_.busy = true;
    if (w_.model != m.id()) w_.load(m);
    w_.near_boxes.reserve(sc_.boxes.size());
  }
  ~Evaluator() { w_.busy = false; }
  Evaluator(const Evaluator&) = delete;
  Evaluator& operator=(const Evaluator&) = delete;

  bool valid(const double* q) {
    for (int j = 0; j < kArmJoints; ++j)
      if (!(q[j] >= s_.q_min_rad[j] && q[j] <= s_.q_max_rad[j])) return false;
    q_ = q;
    m_.chain().poses(q, w_.R.data(), w_.p.data());
    w_.next_state();
    if (!env_ok()) return false;
    return m_.complete_link_pairs() ? self_ok_trees() : self_ok_lists();
  }

  const Vec3* centres(const double* q) {
    m_.chain().poses(q, w_.R.data(), w_.p.data());
    w_.next_state();
    for (std::size_t l = 0; l < m_.links().size(); ++l) pose_link(static_cast<int>(l));
    return w_.c.data();
  }

 private:
  Vec3 world(const Model::Bound& b) const {
    return w_.p[static_cast<std::size_t>(b.body)] + w_.R[static_cast<std::size_t>(b.body)] * b.center;
  }

  void pose_link(int l) {
    if (w_.link_stamp[static_cast<std::size_t>(l)] >= w_.stamp) return;  // this state, or fixed
    const auto& link = m_.links()[static_cast<std::size_t>(l)];
    const Mat3& R = w_.R[static_cast<std::size_t>(link.body)];
    const Vec3& p = w_.p[static_cast<std::size_t>(link.body)];
    for (int i : link.spheres) {
      // p + R c, summed like numpy's einsum over j (x, y, z order)
      w_.c[static_cast<std::size_t>(i)] = p + R * s_.sphere_center[static_cast<std::size_t>(i)];
    }
    w_.link_stamp[static_cast<std::size_t>(l)] = w_.stamp;
  }

  /// Link-level map test at the bound (cb, rad) overlapping the grid: with v the grid voxel
  /// nearest cb (its index clamped into the grid) and c_v its centre, every sphere (c, r) of
  /// the link has field(c) >= field(v) - |cb - c_v| - (rad - r) - sqrt(3) voxel / 2 (the field
  /// is 1-Lipschitz between voxel centres; outside the grid it is +inf), so the map is clear
  /// for every sphere when field(v) - |cb - c_v| - sqrt(3) voxel / 2 - rad - margin -
  /// inflation >= the allowance.
  bool map_bound_clear(const Vec3& cb, double rad) const {
    const DistanceField& f = sc_.field;
    const long long n[3] = {f.nx, f.ny, f.nz};
    long long idx[3];
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double x = std::floor((cb[k] - f.origin[k]) / f.voxel_m);
      idx[k] = x < 0.0 ? 0 : (x > static_cast<double>(n[k] - 1) ? n[k] - 1 : static_cast<long long>(x));
      const double e = cb[k] - (f.origin[k] + (static_cast<double>(idx[k]) + 0.5) * f.voxel_m);
      d2 += e * e;
    }
    const double d = static_cast<double>(f.values[static_cast<std::size_t>((idx[0] * f.ny + idx[1]) * f.nz + idx[2])]);
    return d < kInfinity && d - std::sqrt(d2) - 0.5 * kSqrt3 * f.voxel_m - rad - sc_.collision_margin_m -
                                f.inflation_m >= kBoundSlack_m;
  }

  /// The environment for every link with environment spheres: most link bounds are above the
  /// floor and outside the box around all obstacles (one test each); the others go on to
  /// link_env_ok.
  bool env_ok() {
    const Mat3* R = w_.R.data();
    const Vec3* P = w_.p.data();
    const double lo[3] = {ps_.lo[0][0], ps_.lo[1][0], ps_.lo[2][0]};
    const double hi[3] = {ps_.hi[0][0], ps_.hi[1][0], ps_.hi[2][0]};
    const double floor_z = sc_.floor_z_m;
    for (const Model::EnvBound& e : m_.env_bounds()) {
      const double* m = R[e.body].data();  // column-major
      const double* p = P[e.body].data();
      const double x = p[0] + (m[0] * e.center[0] + m[3] * e.center[1] + m[6] * e.center[2]);
      const double y = p[1] + (m[1] * e.center[0] + m[4] * e.center[1] + m[7] * e.center[2]);
      const double z = p[2] + (m[2] * e.center[0] + m[5] * e.center[1] + m[8] * e.center[2]);
      const double ex = std::max(std::max(lo[0] - x, x - hi[0]), 0.0);
      const double ey = std::max(std::max(lo[1] - y, y - hi[1]), 0.0);
      const double ez = std::max(std::max(lo[2] - z, z - hi[2]), 0.0);
      const bool outside = ex * ex + ey * ey + ez * ez > e.radius * e.radius;
      if (outside && (z - e.radius) - floor_z >= kBoundSlack_m && !(allow_ && e.hand)) continue;
      if (!link_env_ok(e.link, Vec3(x, y, z), !outside)) return false;
    }
    return true;
  }

  /// Floor, map, boxes and points for every environment sphere of link l, its environment
  /// bound at cb: the bound against each obstacle's box first (when it is inside the box
  /// around all of them), the spheres only against what the bound cannot clear.
  bool link_env_ok(int l, const Vec3& cb, bool near_obstacles) {
    const auto& link = m_.links()[static_cast<std::size_t>(l)];
    const double rad = link.env.radius, rad2 = rad * rad;
    const double margin = sc_.collision_margin_m;
    const bool floor_clear = (cb.z() - rad) - sc_.floor_z_m >= kBoundSlack_m;
    const bool cleared_here = allow_ && link.has_hand &&
                              !(sc_.cleared.box().distance(cb) - rad > sc_.cleared.pad_m() + kBoundSlack_m);
    bool map_clear = !(sc_.has_env && (cleared_here || sc_.field.empty()));
    bool points_clear = true;
    auto& near = w_.near_boxes;
    near.clear();
    const double x = cb.x(), y = cb.y(), z = cb.z();
    auto outside = [&](std::size_t k) {  // farther than rad from obstacle box k
      const double ex = std::max(std::max(ps_.lo[0][k] - x, x - ps_.hi[0][k]), 0.0);
      const double ey = std::max(std::max(ps_.lo[1][k] - y, y - ps_.hi[1][k]), 0.0);
      const double ez = std::max(std::max(ps_.lo[2][k] - z, z - ps_.hi[2][k]), 0.0);
      return ex * ex + ey * ey + ez * ez > rad2;
    };
    const std::size_t no = ps_.kind.size();
    if (near_obstacles) {
      for (std::size_t k = 1; k < no; ++k) {
        if (x < ps_.lo[0][k] - rad || x > ps_.hi[0][k] + rad || y < ps_.lo[1][k] - rad ||
            y > ps_.hi[1][k] + rad || z < ps_.lo[2][k] - rad || z > ps_.hi[2][k] + rad || outside(k))
          continue;  // clear of obstacle k
        switch (ps_.kind[k]) {
          case PreparedScene::Kind::grid:
            map_clear = map_clear && map_bound_clear(cb, rad);
            break;
          case PreparedScene::Kind::box: {
            const ObstacleBox& b = sc_.boxes[static_cast<std::size_t>(ps_.box[k])];
            if (!(b.distance(cb) >= rad + margin + kBoundSlack_m)) near.push_back(ps_.box[k]);
            break;
          }
          case PreparedScene::Kind::points:
            points_clear = sc_.points.box().distance(cb) - rad - margin - sc_.points.fine_m() >= kBoundSlack_m;
            break;
          case PreparedScene::Kind::all:
            break;
        }
      }
    }
    if (floor_clear && map_clear && points_clear && near.empty()) return true;
    pose_link(l);
    for (int i : link.env_spheres) {
      const Vec3& c = w_.c[static_cast<std::size_t>(i)];
      const double r = s_.sphere_radius[static_cast<std::size_t>(i)];
      if (!floor_clear && !((c.z() - r) - sc_.floor_z_m >= 0.0)) return false;
      if (!map_clear && !sphere_map_ok(i, c, r)) return false;
      for (int k : near)
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

  /// World centre of tree node k of a link on `body` (x, y, z), computed once per state
  /// (stamped; the fixed links' nodes are loaded with the scratch).
  const double* node_world(int body, int k) {
    double* w = w_.node_w[static_cast<std::size_t>(k)].data();
    std::uint32_t& st = w_.node_stamp[static_cast<std::size_t>(k)];
    if (st < w_.stamp) {
      const double* m = w_.R[static_cast<std::size_t>(body)].data();  // column-major
      const double* p = w_.p[static_cast<std::size_t>(body)].data();
      const double* c = m_.nodes()[static_cast<std::size_t>(k)].center.data();
      w[0] = p[0] + (m[0] * c[0] + m[3] * c[1] + m[6] * c[2]);
      w[1] = p[1] + (m[1] * c[0] + m[4] * c[1] + m[7] * c[2]);
      w[2] = p[2] + (m[2] * c[0] + m[5] * c[1] + m[8] * c[2]);
      st = w_.stamp;
    }
    return w;
  }

  /// Self-collision with whole link pairs: the links' bounding spheres (tree roots) first,
  /// posed once per state and tested for every pair in one loop; the trees only below the
  /// pairs whose roots overlap.
  bool self_ok_trees() {
    const auto& links = m_.links();
    const PairTable* tables = m_.pair_tables().data();
    const int* roots = m_.link_roots().data();
    const double pad = s_.self_margin_m + kBoundSlack_m;
    for (std::size_t l = 0; l < links.size(); ++l) node_world(links[l].body, roots[l]);
    const Vec3* nw = w_.node_w.data();
    for (const Model::PairCheck& pc : m_.check_order()) {
      if (pc.table >= 0) {
        const PairTable::Cell cell = tables[pc.table].at(q_);
        if (cell == PairTable::clear) continue;
        if (cell == PairTable::blocked) return false;
      }
      const double reach = pc.radius_sum + pad;
      if (reach > 0.0 && (nw[pc.root_a] - nw[pc.root_b]).squaredNorm() >= reach * reach) continue;
      if (!pair_descent(m_.link_pairs()[static_cast<std::size_t>(pc.pair)])) return false;
    }
    return true;
  }

  /// Descent of both links' trees for one link pair whose roots overlap.
  bool pair_descent(const Model::LinkPair& lp) {
    const double margin = s_.self_margin_m;
    const double pad = margin + kBoundSlack_m;
    const Model::Node* nodes = m_.nodes().data();
    const int ba = m_.links()[static_cast<std::size_t>(lp.la)].body;
    const int bb = m_.links()[static_cast<std::size_t>(lp.lb)].body;
    constexpr int kStack = 128;
    int stack_a[kStack], stack_b[kStack];
    int top = 0;
    bool posed = false;
    auto split = [&](int a, int b) {
      if (top + 2 > kStack) throw std::logic_error("self-collision tree descent: stack overflow");
      const Model::Node& A = nodes[a];
      const Model::Node& B = nodes[b];
      const bool split_b = A.sphere >= 0 || (B.sphere < 0 && B.radius > A.radius);
      stack_a[top] = split_b ? a : A.left;
      stack_b[top] = split_b ? B.left : b;
      stack_a[top + 1] = split_b ? a : A.right;
      stack_b[top + 1] = split_b ? B.right : b;
      top += 2;
    };
    const int ra = m_.link_roots()[static_cast<std::size_t>(lp.la)];
    const int rb = m_.link_roots()[static_cast<std::size_t>(lp.lb)];
    if (nodes[ra].sphere >= 0 && nodes[rb].sphere >= 0) {  // one sphere each
      stack_a[0] = ra;
      stack_b[0] = rb;
      top = 1;
    } else {
      split(ra, rb);
    }
    while (top > 0) {
      --top;
      const int a = stack_a[top], b = stack_b[top];
      const Model::Node& A = nodes[a];
      const Model::Node& B = nodes[b];
      if (A.sphere >= 0 && B.sphere >= 0) {
        if (!posed) { pose_link(lp.la); pose_link(lp.lb); posed = true; }
        if (!sphere_pair_ok(A.sphere, B.sphere, margin)) return false;
        continue;
      }
      const double reach = A.radius + B.radius + pad;
      const double* wa = node_world(ba, a);
      const double* wb = node_world(bb, b);
      const double dx = wa[0] - wb[0], dy = wa[1] - wb[1], dz = wa[2] - wb[2];
      if (reach > 0.0 && dx * dx + dy * dy + dz * dz >= reach * reach) continue;
      split(a, b);
    }
    return true;
  }

  bool sphere_pair_ok(int i, int j, double margin) const {
    const Vec3& ci = w_.c[static_cast<std::size_t>(i)];
    const Vec3& cj = w_.c[static_cast<std::size_t>(j)];
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
    for (const Model::PairCheck& pc : m_.check_order()) {
      const auto& lp = m_.link_pairs()[static_cast<std::size_t>(pc.pair)];
      if (lp.table >= 0) {
        const PairTable::Cell cell = m_.pair_tables()[static_cast<std::size_t>(lp.table)].at(q_);
        if (cell == PairTable::clear) continue;
        if (cell == PairTable::blocked) return false;
      }
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

  const Model& m_;
  const RobotCollisionSpec& s_;
  const PreparedScene& ps_;
  const CollisionScene& sc_;
  const bool allow_;
  Scratch* shared_;               ///< the thread's scratch for this model, if one is free
  std::unique_ptr<Scratch> own_;  ///< only when none is
  Scratch& w_;
  const double* q_ = nullptr;  ///< the state being checked
};

}  // namespace

PreparedScene::PreparedScene(std::shared_ptr<const CollisionScene> s) : scene(std::move(s)) {
  if (!scene) scene = std::make_shared<const CollisionScene>();
  obstacle_boxes(*this);
}

StateChecker::StateChecker(std::shared_ptr<const RobotCollisionModel> robot,
                           std::shared_ptr<const CollisionScene> scene)
    : robot_(std::move(robot)), scene_(std::make_shared<const PreparedScene>(std::move(scene))) {
  if (!robot_) throw std::invalid_argument("state checker: robot model is required");
}

void StateChecker::set_scene(std::shared_ptr<const CollisionScene> scene) {
  auto prepared = std::make_shared<const PreparedScene>(std::move(scene));
  const std::lock_guard<std::mutex> lock(scene_mutex_);
  scene_ = std::move(prepared);
}

std::shared_ptr<const PreparedScene> StateChecker::scene() const {
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
