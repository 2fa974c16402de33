#include "starnav/control/mppi_critics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"

namespace starnav {

namespace {

constexpr float kTwoPi = static_cast<float>(2.0 * kPi);

// The path point `offset` beyond the furthest reached, at most the last.
std::size_t offset_point(const MppiScene& s, int offset) {
  return std::min(s.furthest_reached() + static_cast<std::size_t>(std::max(offset, 0)), s.path.size() - 1);
}

}  // namespace

Eigen::ArrayXXf mppi_angle_difference(const Eigen::ArrayXXf& a, const Eigen::ArrayXXf& b) {
  const Eigen::ArrayXXf d = a - b;
  return d - kTwoPi * (d * (1.0f / kTwoPi)).round();
}

std::size_t MppiScene::furthest_reached() const {
  if (furthest_cache) return *furthest_cache;
  std::size_t furthest = 0;
  if (!path.empty() && trajectories && trajectories->x.size() > 0) {
    const Eigen::Index last = trajectories->x.cols() - 1;
    const Eigen::Index n = trajectories->x.rows();
    const std::size_t m = path.size();
    // Per path point, every sample's squared distance: the nearest point per sample by columns.
    Eigen::ArrayXf best = Eigen::ArrayXf::Constant(n, std::numeric_limits<float>::infinity());
    Eigen::ArrayXi best_i = Eigen::ArrayXi::Zero(n);
    const auto lx = trajectories->x.col(last), ly = trajectories->y.col(last);
    for (std::size_t j = 0; j < m; ++j) {
      const Eigen::ArrayXf d = (lx - static_cast<float>(path[j].x())).square() + (ly - static_cast<float>(path[j].y())).square();
      best_i = (d < best).select(static_cast<int>(j), best_i);
      best = best.cwiseMin(d);
    }
    furthest = static_cast<std::size_t>(best_i.maxCoeff());
  }
  furthest_cache = furthest;
  return furthest;
}

void MppiScene::prepare_map() {
  const GridGeometry& g = map->geometry();
  origin_x_ = static_cast<float>(g.origin.x);
  origin_y_ = static_cast<float>(g.origin.y);
  cos_ = static_cast<float>(std::cos(g.origin.yaw));
  sin_ = static_cast<float>(std::sin(g.origin.yaw));
  inv_resolution_ = static_cast<float>(1.0 / g.resolution);
  width_ = static_cast<float>(g.width);
  height_ = static_cast<float>(g.height);
  clearance_.resize(static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height));
  for (std::size_t i = 0; i < clearance_.size(); ++i) {
    const double d = map->clearance_m(i);
    clearance_[i] = std::isfinite(d) ? static_cast<float>(d) : std::numeric_limits<float>::max();
  }
}

void MppiCritic::add(const Eigen::ArrayXf& term, MppiCosts& costs) const {
  const float w = static_cast<float>(weight_);
  if (power_ == 1) costs.total += w * term;
  else costs.total += (w * term).pow(static_cast<float>(power_));
}

void MppiConstraintCritic::score(const MppiScene& s, MppiCosts& costs) const {
  const MppiControls& c = *s.controls;
  const MppiLimits& l = s.limits;
  const float dt = static_cast<float>(s.model_dt_s);
  Eigen::ArrayXXf speed = c.vx;
  float hi = static_cast<float>(l.vx_max), lo = static_cast<float>(l.vx_min);
  if (l.holonomic()) {
    // The signed speed against the combined bounds (Nav2's omni rule).
    speed = c.vx.sign() * (c.vx.square() + c.vy.square()).sqrt();
    hi = static_cast<float>(std::hypot(l.vx_max, l.vy_max));
    lo = static_cast<float>((l.vx_min < 0.0 ? -1.0 : 1.0) * std::hypot(l.vx_min, l.vy_max));
  }
  Eigen::ArrayXXf out = (speed - hi).cwiseMax(0.0f) + (lo - speed).cwiseMax(0.0f);
  if (l.model == MppiMotionModel::Ackermann) {
    const float r = static_cast<float>(l.min_turning_r);
    // |vx / wz| below R_min (no turn: no radius to break).
    const Eigen::ArrayXXf radius = (c.wz.abs() > 1e-6f).select(c.vx.abs() / c.wz.abs().cwiseMax(1e-6f), std::numeric_limits<float>::infinity());
    out += (r - radius).cwiseMax(0.0f);
  }
  add((out * dt).rowwise().sum(), costs);
}

void MppiGoalCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.path_gate_m() >= threshold_m_) return;
  const MppiTrajectories& t = *s.trajectories;
  const Eigen::ArrayXXf d = ((t.x - static_cast<float>(s.goal.x())).square() + (t.y - static_cast<float>(s.goal.y())).square()).sqrt();
  add(d.rowwise().mean(), costs);
}

void MppiGoalAngleCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (!s.goal_yaw || s.path_gate_m() >= threshold_m_) return;
  const MppiTrajectories& t = *s.trajectories;
  const Eigen::ArrayXXf goal = Eigen::ArrayXXf::Constant(t.yaw.rows(), t.yaw.cols(), static_cast<float>(*s.goal_yaw));
  add(mppi_angle_difference(t.yaw, goal).abs().rowwise().mean(), costs);
}

void MppiPathAlignCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.path.size() < 2 || s.path_gate_m() < o_.threshold_m) return;
  const std::size_t reached = s.furthest_reached();
  // Only once the batch is well along the path (not while the robot first turns onto it); on a
  // stretch of poses shorter than that, once it reaches the stretch's end.
  std::size_t needed = static_cast<std::size_t>(o_.offset_from_furthest);
  if (s.path_left_m) needed = std::min(needed, s.path.size() - 1);
  if (reached < needed) return;
  // Not when obstacles block much of the path up to there: the obstacle and follow critics lead.
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < reached; ++i) blocked += s.path_free[i] ? 0 : 1;
  if (blocked > 2 && static_cast<double>(blocked) > o_.max_path_occupancy_ratio * static_cast<double>(reached)) return;
  // The path's length from its first point to each point up to the furthest reached.
  std::vector<float> along(reached + 1, 0.0f);
  for (std::size_t i = 1; i <= reached; ++i) along[i] = along[i - 1] + static_cast<float>((s.path[i] - s.path[i - 1]).norm());
  const MppiTrajectories& t = *s.trajectories;
  const Eigen::Index n = t.x.rows(), steps = t.x.cols();
  const int step = std::max(1, o_.trajectory_point_step);
  Eigen::ArrayXf term = Eigen::ArrayXf::Zero(n);
  const float x0 = static_cast<float>(s.pose.x), y0 = static_cast<float>(s.pose.y);
  for (Eigen::Index k = 0; k < n; ++k) {
    float travelled = 0.0f, summed = 0.0f;
    int samples = 0;
    float px = x0, py = y0;
    std::size_t j = 0;
    for (Eigen::Index p = step - 1; p < steps; p += step) {
      const float x = t.x(k, p), y = t.y(k, p);
      travelled += std::sqrt((x - px) * (x - px) + (y - py) * (y - py));
      px = x;
      py = y;
      // The path point as far along the path (from the robot's place on it) as the pose is along
      // its trajectory (from the robot).
      while (j < reached && along[j] < travelled) ++j;
      const std::size_t at = j > 0 && travelled - along[j - 1] < along[j] - travelled ? j - 1 : j;
      if (!s.path_free[at]) continue;  // an obstacle on the path there: the obstacle critic decides
      const float ex = static_cast<float>(s.path[at].x()) - x, ey = static_cast<float>(s.path[at].y()) - y;
      summed += std::sqrt(ex * ex + ey * ey);
      ++samples;
    }
    term(k) = samples > 0 ? summed / static_cast<float>(samples) : 0.0f;
  }
  add(term, costs);
}

void MppiPathFollowCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.path.size() < 2 || s.path_gate_m() < threshold_m_) return;
  std::size_t target = offset_point(s, offset_);
  // Past an obstacle on the path rather than into it.
  while (target + 2 < s.path.size() && !s.path_free[target]) ++target;
  const MppiTrajectories& t = *s.trajectories;
  const Eigen::Index last = t.x.cols() - 1;
  const Eigen::ArrayXf d = ((t.x.col(last) - static_cast<float>(s.path[target].x())).square() +
                            (t.y.col(last) - static_cast<float>(s.path[target].y())).square())
                               .sqrt();
  add(d, costs);
}

void MppiPathAngleCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.path.size() < 2 || s.path_gate_m() < threshold_m_) return;
  const Vec2 target = s.path[offset_point(s, offset_)];
  const Vec2 to = target - s.pose.translation();
  // On a stretch the planner drives in reverse the rear faces the path: the bearing turned by pi.
  const double flip = s.reversing ? kPi : 0.0;
  double error = std::abs(wrap_angle(std::atan2(to.y(), to.x()) + flip - s.pose.yaw));
  if (mode_ == 1) error = std::min(error, kPi - error);
  if (error < max_angle_rad_) return;
  const MppiTrajectories& t = *s.trajectories;
  Eigen::ArrayXXf bearing(t.x.rows(), t.x.cols());
  const float tx = static_cast<float>(target.x()), ty = static_cast<float>(target.y());
  const float fflip = static_cast<float>(flip);
  for (Eigen::Index c = 0; c < t.x.cols(); ++c)
    for (Eigen::Index r = 0; r < t.x.rows(); ++r) bearing(r, c) = std::atan2(ty - t.y(r, c), tx - t.x(r, c)) + fflip;
  Eigen::ArrayXXf diff = mppi_angle_difference(t.yaw, bearing).abs();
  if (mode_ == 1) diff = diff.cwiseMin(static_cast<float>(kPi) - diff);
  add(diff.rowwise().mean(), costs);
}

void MppiPreferForwardCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.path_gate_m() < threshold_m_) return;
  const float dt = static_cast<float>(s.model_dt_s);
  // The direction the path ahead is driven in: forward, or reverse on a planner's reverse stretch.
  const float sign = s.reversing ? 1.0f : -1.0f;
  add(((sign * s.controls->vx).cwiseMax(0.0f) * dt).rowwise().sum(), costs);
}

void MppiTwirlingCritic::score(const MppiScene& s, MppiCosts& costs) const {
  if (s.distance_to_goal_m() <= s.goal_tolerance_m) return;
  add(s.controls->wz.abs().rowwise().mean(), costs);
}

bool MppiObstaclesCritic::collides(const MppiScene& s, const Pose2& pose, float clearance) const {
  if (!o_.consider_footprint) return clearance < static_cast<float>(s.inscribed_radius_m);
  // Beyond the footprint's reach (and the checker's half-cell growth) nothing can touch it.
  if (clearance > static_cast<float>(s.circumscribed_radius_m + s.map->resolution())) return false;
  return s.footprint->collides(*s.map, pose);
}

void MppiObstaclesCritic::score(const MppiScene& s, MppiCosts& costs) const {
  const MppiTrajectories& t = *s.trajectories;
  const Eigen::Index n = t.x.rows(), steps = t.x.cols();
  const bool near_goal = s.distance_to_goal_m() < o_.near_goal_distance_m;
  const float r_in = static_cast<float>(s.inscribed_radius_m), margin = static_cast<float>(o_.collision_margin_distance_m);
  const float inflation = static_cast<float>(o_.inflation_radius_m);
  Eigen::ArrayXf critical = Eigen::ArrayXf::Zero(n), repulsive = Eigen::ArrayXf::Zero(n);
  std::vector<std::uint8_t> hit(static_cast<std::size_t>(n), 0);
  // Step by step over the whole batch (each step's poses lie together in memory); a sample stops
  // counting at its first collision.
  for (Eigen::Index p = 0; p < steps; ++p) {
    const float* xs = t.x.col(p).data();
    const float* ys = t.y.col(p).data();
    for (Eigen::Index k = 0; k < n; ++k) {
      if (hit[static_cast<std::size_t>(k)]) continue;
      const float d = s.clearance_at(xs[k], ys[k]);
      if (d >= inflation && d - r_in >= margin) continue;  // free space
      if (collides(s, Pose2(xs[k], ys[k], t.yaw(k, p)), d)) {
        hit[static_cast<std::size_t>(k)] = 1;
        continue;
      }
      if (d - r_in < margin) critical(k) += margin - (d - r_in);
      if (!near_goal && d < inflation) repulsive(k) += inflation - d;
    }
  }
  Eigen::ArrayXf term(n);
  bool all_collide = n > 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const bool h = hit[static_cast<std::size_t>(k)] != 0;
    all_collide = all_collide && h;
    term(k) = static_cast<float>(o_.critical_weight) * (h ? static_cast<float>(o_.collision_cost) : critical(k)) +
              static_cast<float>(o_.repulsion_weight) * repulsive(k) / static_cast<float>(steps);
  }
  add(term, costs);
  costs.failed = costs.failed || all_collide;
}

}  // namespace starnav
