// Object tracker across frames (method.md §4). See tracker.hpp.
#include "grasp_core/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grasp_core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename T>
void push_window(std::deque<T>& w, const T& x, int window) {
  w.push_back(x);
  while (static_cast<int>(w.size()) > window) w.pop_front();
}

double median_of(const std::deque<double>& w) {
  return median(std::vector<double>(w.begin(), w.end()));
}

}  // namespace

Tracker::Tracker(const ObbParams& p) : p_(p) {}

std::optional<double> Tracker::gate_for(const std::vector<Vec3>& centres, double frac) {
  if (centres.size() < 2) return std::nullopt;
  double dmin = kInf;
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (std::size_t j = i + 1; j < centres.size(); ++j)
      dmin = std::min(dmin, (centres[i] - centres[j]).norm());
  if (!std::isfinite(dmin)) return std::nullopt;
  return frac * dmin;
}

std::optional<double> Tracker::prior_theta(const Vec3& centre, std::optional<double> gate) const {
  const Track* best = nullptr;
  double best_d = kInf;
  for (const auto& t : tracks_) {
    const double d = (t.smoothed.center - centre).norm();
    if (d < best_d) {
      best_d = d;
      best = &t;
    }
  }
  if (!best) return std::nullopt;
  if (gate && !(best_d <= *gate)) return std::nullopt;
  return best->smoothed.theta_rad;
}

std::vector<int> Tracker::update(const std::vector<ObjectEstimate>& ests,
                                 const std::vector<ViewQuality>& q, double now_s) {
  std::vector<Vec3> centres;
  centres.reserve(ests.size());
  for (const auto& e : ests) centres.push_back(e.center);
  last_gate_ = gate_for(centres, p_.assoc_gate_frac);

  std::vector<bool> used(tracks_.size(), false);
  std::vector<int> tids;
  tids.reserve(ests.size());
  for (std::size_t i = 0; i < ests.size(); ++i) {
    const ViewQuality qi = i < q.size() ? q[i] : ViewQuality::OBLIQUE;
    int best = -1;
    double best_d = kInf;
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      if (used[k]) continue;
      const double d = (tracks_[k].smoothed.center - ests[i].center).norm();
      if (d < best_d) {
        best_d = d;
        best = static_cast<int>(k);
      }
    }
    if (best >= 0 && (!last_gate_ || best_d <= *last_gate_)) {
      used[best] = true;
      observe(tracks_[best], ests[i], qi, now_s);
      tids.push_back(tracks_[best].tid);
      continue;
    }
    Track t;
    t.tid = next_tid_++;
    t.quality = qi;
    t.last_seen_s = now_s;
    smooth(t, ests[i]);
    tracks_.push_back(std::move(t));
    used.push_back(true);  // a new track is used for this frame too
    tids.push_back(tracks_.back().tid);
  }
  std::stable_sort(tracks_.begin(), tracks_.end(),
                   [](const Track& a, const Track& b) { return a.tid < b.tid; });
  return tids;
}

void Tracker::observe(Track& t, const ObjectEstimate& est, ViewQuality q, double now_s) const {
  t.last_seen_s = now_s;
  if (q < t.quality) return;  // an oblique frame never overwrites a nadir estimate
  if (q > t.quality) {        // quality rose: a NADIR median never mixes oblique samples
    t.center_.clear();
    t.width_m_.clear();
    t.perp_width_m_.clear();
    t.height_m_.clear();
    t.theta_rad_.clear();
    t.anisotropy_.clear();
  }
  t.quality = q;
  smooth(t, est);
}

void Tracker::smooth(Track& t, const ObjectEstimate& est) const {
  const int w = p_.window;
  push_window(t.center_, est.center, w);
  push_window(t.width_m_, est.width_m, w);
  push_window(t.perp_width_m_, est.perp_width_m, w);
  push_window(t.height_m_, est.height_m, w);
  push_window(t.theta_rad_, est.theta_rad, w);
  push_window(t.anisotropy_, est.anisotropy, w);

  // pca_*, resting, notes and point count come from this frame.
  ObjectEstimate s = est;
  std::vector<double> cx, cy, cz;
  for (const auto& c : t.center_) {
    cx.push_back(c.x());
    cy.push_back(c.y());
    cz.push_back(c.z());
  }
  s.center = Vec3(median(cx), median(cy), median(cz));
  s.width_m = median_of(t.width_m_);
  s.perp_width_m = median_of(t.perp_width_m_);
  s.height_m = median_of(t.height_m_);
  s.anisotropy = median_of(t.anisotropy_);
  s.theta_rad = circular_median_mod_pi(
      std::vector<double>(t.theta_rad_.begin(), t.theta_rad_.end()), t.theta_rad_.front());

  // Rebuilt from the smoothed values (ours); n = this frame's plane normal.
  const Vec3 n = est.R_box.col(2);
  Vec3 u, v;
  in_plane_basis(n, &u, &v);
  const double th = s.theta_rad;
  s.R_box.col(0) = std::cos(th) * u + std::sin(th) * v;
  s.R_box.col(1) = -std::sin(th) * u + std::cos(th) * v;
  s.R_box.col(2) = n.normalized();
  s.extents = Vec3(s.width_m, s.perp_width_m, s.height_m);
  s.yaw_defined = s.anisotropy >= p_.isotropy_ratio_max;
  apply_size_guards(s, p_);  // width_ok / height_ok / grasp_ok and their notes
  t.smoothed = std::move(s);
}

void Tracker::retire(double now_s) {
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) {
                                 const double age = now_s - t.last_seen_s;
                                 const double limit = t.quality == ViewQuality::NADIR
                                                          ? p_.nadir_hold_s
                                                          : p_.max_age_s;
                                 return age > limit;
                               }),
                tracks_.end());
}

void Tracker::reset() {
  tracks_.clear();
  last_gate_.reset();
}

std::vector<EstimateResult> estimate_with_priors(const std::vector<PointsD>& clusters,
                                                 const Plane& plane, const ObbParams& p,
                                                 const Tracker& tracker,
                                                 std::optional<double> band,
                                                 double max_abs_coordinate_m) {
  // The per-point work (PCA, decomposition, height, width scan) does not depend on the
  // prior: it is done once per cluster and both passes finish from it.
  std::vector<PreparedEstimate> prepared;
  prepared.reserve(clusters.size());
  std::vector<EstimateResult> first;
  first.reserve(clusters.size());
  std::vector<Vec3> centres;
  for (const auto& c : clusters) {
    prepared.push_back(prepare_estimate(c, plane, p, max_abs_coordinate_m));
    first.push_back(finish_estimate(prepared.back(), p, std::nullopt, band));
    if (first.back().estimate) centres.push_back(first.back().estimate->center);
  }
  const auto gate = Tracker::gate_for(centres, p.assoc_gate_frac);
  std::vector<EstimateResult> out;
  out.reserve(clusters.size());
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    if (!first[i].estimate) {
      out.push_back(std::move(first[i]));
      continue;
    }
    const auto prior = tracker.prior_theta(first[i].estimate->center, gate);
    if (!prior) {
      out.push_back(std::move(first[i]));
      continue;
    }
    EstimateResult second = finish_estimate(prepared[i], p, prior, band);
    out.push_back(second.estimate ? std::move(second) : std::move(first[i]));
  }
  return out;
}

}  // namespace grasp_core
