#include "grasp_core/pair_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>

namespace grasp_core {

namespace {

/// Cells are proven over their box widened by this much on each side [rad], so a state that
/// rounding puts in a neighbouring cell is still covered.
constexpr double kCellOverlap_rad = 1e-9;

/// One hinge on the path between the two links.
struct Hinge {
  int joint = 0;        ///< arm-state index
  bool turns_b = true;  ///< turns link b relative to link a (else link a relative to b)
  std::vector<double> lever;  ///< per sphere of the turned link: bound on its distance to the axis
};

std::vector<int> ancestors(const RobotChain& ch, int b) {  // b, parent(b), ..., 0
  std::vector<int> out;
  for (int x = b; x >= 0; x = ch.body(x).parent) {
    out.push_back(x);
    if (x == 0) break;
  }
  return out;
}

double axis_distance(const Vec3& x, const Vec3& unit_axis) { return (x - x.dot(unit_axis) * unit_axis).norm(); }

/// Levers about the hinge of body k of the spheres (local centres) of a body m below it or
/// k itself; `down` = the bodies from m up to k's child on the path (empty when m = k).
/// Every hinge on the path turns about an axis through its body's origin, so k's child's
/// origin is fixed in k's frame and every further body adds at most its offset's length.
std::vector<double> levers(const RobotChain& ch, int k, const std::vector<int>& down, const std::vector<Vec3>& centres) {
  const Vec3& u = ch.body(k).axis;
  std::vector<double> out;
  if (down.empty()) {  // the spheres' own body: the exact distance
    for (const Vec3& c : centres) out.push_back(axis_distance(c, u));
    return out;
  }
  double arm = axis_distance(ch.body(down.back()).p, u);
  for (std::size_t i = 0; i + 1 < down.size(); ++i) arm += ch.body(down[i]).p.norm();
  for (const Vec3& c : centres) out.push_back(arm + c.norm());
  return out;
}

/// The hinges between the links; false when one has an offset anchor.
bool path_hinges(const PairTableInput& in, std::vector<Hinge>& out) {
  const RobotChain& ch = *in.chain;
  const std::vector<int> ua = ancestors(ch, in.body_a), ub = ancestors(ch, in.body_b);
  int common = 0;
  for (int x : ua)
    if (std::find(ub.begin(), ub.end(), x) != ub.end()) { common = x; break; }
  for (int side = 0; side < 2; ++side) {
    const std::vector<int>& up = side == 0 ? ua : ub;
    const std::vector<Vec3>& centres = side == 0 ? in.centre_a : in.centre_b;
    for (std::size_t i = 0; i < up.size() && up[i] != common; ++i) {
      const ChainBody& b = ch.body(up[i]);
      if (b.joint < 0) continue;
      for (const Hinge& h : out)
        if (h.joint == b.joint) return false;  // one joint driving two hinges: not handled
      if (!b.anchor.isZero()) return false;
      const std::vector<int> down(up.begin(), up.begin() + static_cast<std::ptrdiff_t>(i));
      out.push_back(Hinge{b.joint, side == 1, levers(ch, up[i], down, centres)});
    }
  }
  return true;
}

/// A box [lo, hi) per axis in grid-cell units (whole cells, or parts of one cell when a
/// cell is refined), with the sphere pairs not yet proven clear in it.
struct Box {
  std::array<double, 2> lo{{0, 0}}, hi{{1, 1}};
  std::vector<int> active;
};

/// Levels of halving below one grid cell tried before a cell is left unknown.
constexpr int kRefineLevels = 2;

class TableBuilder {
 public:
  TableBuilder(const PairTableInput& in, std::vector<Hinge> hinges, PairTable& t)
      : in_(in), hinges_(std::move(hinges)), t_(t) {
    const std::vector<int> ua = ancestors(*in.chain, in.body_a), ub = ancestors(*in.chain, in.body_b);
    for (int side = 0; side < 2; ++side) {  // the bodies below the common ancestor, downwards
      const std::vector<int>& up = side == 0 ? ua : ub;
      const std::vector<int>& other = side == 0 ? ub : ua;
      std::vector<int>& path = side == 0 ? path_a_ : path_b_;
      for (int b : up) {
        if (std::find(other.begin(), other.end(), b) != other.end()) break;
        path.insert(path.begin(), b);
      }
    }
  }

  void run() {
    t_.dims = static_cast<int>(hinges_.size());
    for (int d = 0; d < t_.dims; ++d) {
      const int j = hinges_[static_cast<std::size_t>(d)].joint;
      t_.joint[static_cast<std::size_t>(d)] = j;
      t_.n[static_cast<std::size_t>(d)] = in_.cells_per_joint;
      width_[d] = (in_.q_max_rad[j] - in_.q_min_rad[j]) / in_.cells_per_joint;
      t_.q0[static_cast<std::size_t>(d)] = in_.q_min_rad[j];
      t_.inv_width[static_cast<std::size_t>(d)] = width_[d] > 0.0 ? 1.0 / width_[d] : 0.0;
    }
    t_.cells.assign(static_cast<std::size_t>(t_.n[0] * (t_.dims > 1 ? t_.n[1] : 1)), PairTable::unknown);
    Box root;
    for (int d = 0; d < t_.dims; ++d) root.hi[static_cast<std::size_t>(d)] = static_cast<double>(t_.n[static_cast<std::size_t>(d)]);
    for (std::size_t k = 0; k < in_.pairs.size(); ++k) root.active.push_back(static_cast<int>(k));
    std::vector<Box> open = {std::move(root)};
    while (!open.empty()) {
      Box box = std::move(open.back());
      open.pop_back();
      const PairTable::Cell verdict = evaluate(box);
      if (verdict != PairTable::unknown) { fill(box, verdict); continue; }
      const int axis = split_axis(box, 2);
      if (axis < 0) {  // one cell: decide it below the grid's resolution if possible
        fill(box, refine(box));
        continue;
      }
      Box a = box, b = std::move(box);
      const std::size_t u = static_cast<std::size_t>(axis);
      a.hi[u] = b.lo[u] = std::floor(0.5 * (a.lo[u] + a.hi[u]));
      open.push_back(std::move(a));
      open.push_back(std::move(b));
    }
    t_.all_clear = std::all_of(t_.cells.begin(), t_.cells.end(), [](std::uint8_t c) { return c == PairTable::clear; });
  }

 private:
  /// The axis to halve (its half-width costs the most), among those at least min_width
  /// cells wide; -1 when none is.
  int split_axis(const Box& box, double min_width) const {
    int axis = -1;
    double worst = -1.0;
    for (int d = 0; d < t_.dims; ++d) {
      const std::size_t u = static_cast<std::size_t>(d);
      if (box.hi[u] - box.lo[u] < min_width) continue;
      const double cost = max_lever(box, d) * (box.hi[u] - box.lo[u]) * width_[d];
      if (cost > worst) { worst = cost; axis = d; }
    }
    return axis;
  }

  /// A cell that is neither clear nor blocked as a whole may still be clear when halved
  /// (its bounds are loose): clear when every part down to kRefineLevels halvings is proven
  /// clear; unknown at the first part that is not (a cell across the collision boundary
  /// gives up after a few evaluations).
  PairTable::Cell refine(const Box& cell) {
    std::vector<std::pair<Box, int>> open = {{cell, 0}};
    while (!open.empty()) {
      auto [box, level] = std::move(open.back());
      open.pop_back();
      const PairTable::Cell v = level == 0 ? PairTable::unknown : evaluate(box);
      if (v == PairTable::clear) continue;
      const int axis = split_axis(box, 0.0);
      if (v == PairTable::blocked || level == kRefineLevels * t_.dims || axis < 0) return PairTable::unknown;
      Box a = box, b = std::move(box);
      const std::size_t u = static_cast<std::size_t>(axis);
      a.hi[u] = b.lo[u] = 0.5 * (a.lo[u] + a.hi[u]);
      open.push_back({std::move(a), level + 1});
      open.push_back({std::move(b), level + 1});
    }
    return PairTable::clear;
  }

  double max_lever(const Box& box, int d) const {
    const Hinge& h = hinges_[static_cast<std::size_t>(d)];
    double lever = 0.0;
    for (int k : box.active) {
      const auto [i, j] = in_.pairs[static_cast<std::size_t>(k)];
      lever = std::max(lever, h.lever[static_cast<std::size_t>(h.turns_b ? j : i)]);
    }
    return lever;
  }

  /// Pose of the last body of `path` in the frame of the links' common ancestor (the same
  /// recursion as RobotChain::poses; every hinge on the path turns about its body's origin).
  void pose_below_common(const double* q, const std::vector<int>& path, Mat3& R, Vec3& p) const {
    R.setIdentity();
    p.setZero();
    for (int b : path) {
      const ChainBody& c = in_.chain->body(b);
      p = p + R * c.p;
      R = R * c.R;
      if (c.joint >= 0) R = R * Eigen::AngleAxisd(q[c.joint] - c.q0_rad, c.axis).toRotationMatrix();
    }
  }

  /// Clear, blocked or unknown over the box; drops the pairs proven clear from box.active.
  PairTable::Cell evaluate(Box& box) {
    double q[kArmJoints] = {0, 0, 0, 0, 0, 0, 0};
    double half[2] = {0, 0};
    for (int d = 0; d < t_.dims; ++d) {
      const std::size_t u = static_cast<std::size_t>(d);
      const double lo = t_.q0[u] + box.lo[u] * width_[d], hi = t_.q0[u] + box.hi[u] * width_[d];
      q[t_.joint[u]] = 0.5 * (lo + hi);
      half[d] = 0.5 * (hi - lo) + kCellOverlap_rad;
    }
    Mat3 Ra, Rb;
    Vec3 pa, pb;
    pose_below_common(q, path_a_, Ra, pa);
    pose_below_common(q, path_b_, Rb, pb);
    std::vector<int>& keep = keep_;
    keep.clear();
    for (int k : box.active) {
      const auto [i, j] = in_.pairs[static_cast<std::size_t>(k)];
      const Vec3 ci = pa + Ra * in_.centre_a[static_cast<std::size_t>(i)];
      const Vec3 cj = pb + Rb * in_.centre_b[static_cast<std::size_t>(j)];
      const double d = (ci - cj).norm() - in_.radius_a[static_cast<std::size_t>(i)] -
                       in_.radius_b[static_cast<std::size_t>(j)] - in_.margin_m;
      double spread = 0.0;
      for (int h = 0; h < t_.dims; ++h) {
        const Hinge& hg = hinges_[static_cast<std::size_t>(h)];
        spread += hg.lever[static_cast<std::size_t>(hg.turns_b ? j : i)] * half[h];
      }
      if (d + spread < -kPairTableAllowance_m) return PairTable::blocked;
      if (d - spread < kPairTableAllowance_m) keep.push_back(k);
    }
    box.active.swap(keep);
    return box.active.empty() ? PairTable::clear : PairTable::unknown;
  }

  void fill(const Box& box, PairTable::Cell v) {
    const int n1 = t_.dims > 1 ? t_.n[1] : 1;
    for (int a = static_cast<int>(box.lo[0]); a < static_cast<int>(box.hi[0]); ++a)
      for (int b = static_cast<int>(box.lo[1]); b < static_cast<int>(box.hi[1]); ++b)
        t_.cells[static_cast<std::size_t>(a * n1 + b)] = v;
  }

  const PairTableInput& in_;
  std::vector<Hinge> hinges_;
  PairTable& t_;
  double width_[2] = {0, 0};
  std::vector<int> path_a_, path_b_;  ///< bodies from below the common ancestor to each link
  std::vector<int> keep_;             ///< scratch of evaluate()
};

/// Tables kept at most (each a few kB).
constexpr std::size_t kCachedTables = 256;

/// Everything a table depends on, as bytes: every body from the world to either link (fixed
/// transform, hinge), the spheres and pairs, the limits, the margin and the resolution.
std::string cache_key(const PairTableInput& in) {
  std::vector<double> v;
  auto add = [&v](const auto& m) { v.insert(v.end(), m.data(), m.data() + m.size()); };
  std::vector<int> bodies = ancestors(*in.chain, in.body_a);
  const std::vector<int> ub = ancestors(*in.chain, in.body_b);
  bodies.insert(bodies.end(), ub.begin(), ub.end());
  for (int b : bodies) {
    const ChainBody& c = in.chain->body(b);
    v.insert(v.end(), {static_cast<double>(b), static_cast<double>(c.parent), static_cast<double>(c.joint), c.q0_rad});
    add(c.R);
    add(c.p);
    add(c.axis);
    add(c.anchor);
  }
  v.push_back(-1.0);
  for (const Vec3& c : in.centre_a) add(c);
  v.insert(v.end(), in.radius_a.begin(), in.radius_a.end());
  v.push_back(-1.0);
  for (const Vec3& c : in.centre_b) add(c);
  v.insert(v.end(), in.radius_b.begin(), in.radius_b.end());
  v.push_back(-1.0);
  for (const auto& [i, j] : in.pairs) v.insert(v.end(), {static_cast<double>(i), static_cast<double>(j)});
  v.push_back(-1.0);
  v.insert(v.end(), in.q_min_rad.begin(), in.q_min_rad.end());
  v.insert(v.end(), in.q_max_rad.begin(), in.q_max_rad.end());
  v.insert(v.end(), {in.margin_m, static_cast<double>(in.cells_per_joint)});
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}

}  // namespace

bool build_pair_table(const PairTableInput& in, PairTable& out) {
  if (in.chain == nullptr || in.pairs.empty() || in.cells_per_joint < 1) return false;
  std::vector<Hinge> hinges;
  if (!path_hinges(in, hinges) || hinges.size() > 2) return false;
  // A robot model is built again for every finger opening; the tables of pairs away from
  // the fingers are the same each time, so built tables are kept by everything they
  // depend on (bounded; a race builds a table twice, with the same result).
  static std::mutex mutex;
  static std::map<std::string, PairTable> cache;
  const std::string key = cache_key(in);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(key);
    if (it != cache.end()) {
      out = it->second;
      return true;
    }
  }
  out = PairTable{};
  TableBuilder(in, std::move(hinges), out).run();
  const std::lock_guard<std::mutex> lock(mutex);
  if (cache.size() >= kCachedTables) cache.clear();
  cache.emplace(key, out);
  return true;
}

}  // namespace grasp_core
