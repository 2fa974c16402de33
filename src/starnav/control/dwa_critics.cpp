#include "starnav/control/dwa_critics.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/polyline.hpp"

namespace starnav {

namespace {

// Below these a velocity counts as zero for the oscillation test.
constexpr double kTranslationDeadband = 0.01;  // m/s
constexpr double kYawDeadband = 0.01;          // rad/s

int sign_of(double v, double deadband) { return v > deadband ? 1 : (v < -deadband ? -1 : 0); }

std::array<int, 3> signs(const BodyTwist& t) {
  return {sign_of(t.vx, kTranslationDeadband), sign_of(t.vy, kTranslationDeadband), sign_of(t.wz, kYawDeadband)};
}

// In the goal window only the heading matters; within the forward point's distance of the goal the
// forward point says nothing about the approach but would forbid the last small corrections
// sideways (as DWB turns them off there).
bool alignment_off(const DwaScene& scene, double forward_m) {
  return scene.in_goal_window || (scene.local_goal_is_goal && scene.distance_to_goal_m <= forward_m);
}

}  // namespace

Vec2 dwa_forward_point(const Pose2& end, const BodyTwist& twist, double forward_m, bool align_by_motion) {
  double dir = end.yaw;
  if (align_by_motion && std::hypot(twist.vx, twist.vy) > kTranslationDeadband)
    dir = end.yaw + std::atan2(twist.vy, twist.vx);
  return end.translation() + forward_m * Vec2(std::cos(dir), std::sin(dir));
}

double dwa_goal_distance(const DwaScene& scene, const Vec2& p) {
  const ClearanceWindow& map = *scene.map;
  const Cell c = map.cell_of(p);
  if (!map.contains(c.x, c.y)) return kInvalidTrajectory;
  const double wave = scene.goal_distance[map.index(c.x, c.y)];
  if (!std::isfinite(wave)) return kInvalidTrajectory;
  return std::max((p - scene.local_goal).norm(), wave - map.resolution() * std::sqrt(2.0));
}

double PathAlignCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (alignment_off(scene, forward_m_) || r.poses.empty()) return 0.0;
  return distance_to_polyline(dwa_forward_point(r.poses.back(), r.twist, forward_m_, scene.align_by_motion),
                              scene.align_path);
}

double PathDistCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (scene.in_goal_window || r.poses.empty()) return 0.0;
  return distance_to_polyline(r.poses.back().translation(), scene.local_path);
}

double GoalAlignCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (alignment_off(scene, forward_m_) || r.poses.empty()) return 0.0;
  const Vec2 ahead = dwa_forward_point(r.poses.back(), r.twist, forward_m_, scene.align_by_motion);
  if (scene.local_goal_is_goal) return (ahead - scene.align_goal).norm();
  const double d = dwa_goal_distance(scene, ahead);
  // A forward point beyond a wall or the window says nothing about the motion: no preference.
  return std::isfinite(d) ? d : 0.0;
}

double GoalDistCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (scene.in_goal_window || r.poses.empty()) return 0.0;
  return dwa_goal_distance(scene, r.poses.back().translation());
}

double ObstacleCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  const ClearanceWindow& map = *scene.map;
  double worst = 0.0;
  for (const Pose2& p : r.poses) {
    const Cell c = map.cell_of(p.translation());
    if (!map.contains(c.x, c.y)) return kInvalidTrajectory;
    worst = std::max(worst, scene.obstacle_cost[map.index(c.x, c.y)]);
  }
  return worst;
}

double VelocityCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (scene.in_goal_window || !(scene.limits.max_speed_xy > 0.0)) return 0.0;
  return std::max(0.0, 1.0 - std::hypot(r.twist.vx, r.twist.vy) / scene.limits.max_speed_xy);
}

double TwirlingCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (scene.in_goal_window || !(scene.limits.max_wz > 0.0)) return 0.0;
  return std::abs(r.twist.wz) / scene.limits.max_wz;
}

double PathAngleCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (scene.in_goal_window || !scene.path_heading || r.poses.empty()) return 0.0;
  return std::abs(wrap_angle(*scene.path_heading - r.poses.back().yaw));
}

double PreferForwardCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (!(scene.limits.max_vx > 0.0)) return 0.0;
  return std::max(0.0, -r.twist.vx) / scene.limits.max_vx;
}

void OscillationCritic::prepare(const DwaScene& scene) {
  // From rest a reversal is a new motion, not an oscillation (and a robot penalised for turning
  // back would otherwise stand for ever).
  if (signs(scene.velocity) == std::array<int, 3>{}) {
    reset();
    return;
  }
  for (std::size_t a = 0; a < 3; ++a) {
    if (!reversed_[a]) continue;
    const Pose2& at = reversed_at_[a];
    if ((scene.pose.translation() - at.translation()).norm() >= reset_m_ ||
        std::abs(wrap_angle(scene.pose.yaw - at.yaw)) >= reset_rad_)
      reversed_[a] = false;
  }
}

double OscillationCritic::score(const DwaScene& /*scene*/, const DwaRollout& r) const {
  const std::array<int, 3> s = signs(r.twist);
  for (std::size_t a = 0; a < 3; ++a)
    if (reversed_[a] && s[a] != 0 && s[a] == -sign_[a]) return 1.0;
  return 0.0;
}

void OscillationCritic::chosen(const DwaScene& scene, const BodyTwist& twist) {
  const std::array<int, 3> s = signs(twist);
  for (std::size_t a = 0; a < 3; ++a) {
    if (s[a] == 0) continue;
    if (sign_[a] != 0 && s[a] != sign_[a]) {
      reversed_[a] = true;
      reversed_at_[a] = scene.pose;
    }
    sign_[a] = s[a];
  }
}

void OscillationCritic::reset() {
  sign_ = {};
  reversed_ = {};
}

double RotateToGoalCritic::score(const DwaScene& scene, const DwaRollout& r) const {
  if (!scene.in_goal_window || !scene.goal_yaw) return 0.0;
  const double w = r.twist.wz;
  const double braking = scene.limits.acc_yaw > 0.0 ? w * std::abs(w) / (2.0 * scene.limits.acc_yaw) : 0.0;
  const double stop_yaw = scene.pose.yaw + w * scene.period_s + braking;
  return std::abs(wrap_angle(*scene.goal_yaw - stop_yaw));
}

std::vector<std::unique_ptr<DwaCritic>> make_dwa_critics(const DwaConfig& c, bool holonomic) {
  std::vector<std::unique_ptr<DwaCritic>> out;
  const auto add = [&](double weight, auto make) {
    if (weight > 0.0) out.push_back(make(weight));
  };
  add(c.path_align_weight, [&](double w) { return std::make_unique<PathAlignCritic>(w, c.forward_point_m); });
  add(c.path_dist_weight, [](double w) { return std::make_unique<PathDistCritic>(w); });
  add(c.goal_align_weight, [&](double w) { return std::make_unique<GoalAlignCritic>(w, c.forward_point_m); });
  add(c.goal_dist_weight, [](double w) { return std::make_unique<GoalDistCritic>(w); });
  add(c.obstacle_weight, [](double w) { return std::make_unique<ObstacleCritic>(w); });
  add(c.velocity_weight, [](double w) { return std::make_unique<VelocityCritic>(w); });
  add(holonomic ? c.twirling_weight : 0.0, [](double w) { return std::make_unique<TwirlingCritic>(w); });
  add(c.path_angle_weight, [](double w) { return std::make_unique<PathAngleCritic>(w); });
  add(c.prefer_forward_weight, [](double w) { return std::make_unique<PreferForwardCritic>(w); });
  add(c.oscillation_weight, [&](double w) {
    return std::make_unique<OscillationCritic>(w, c.oscillation_reset_m, c.oscillation_reset_rad);
  });
  add(c.rotate_to_goal_weight, [](double w) { return std::make_unique<RotateToGoalCritic>(w); });
  return out;
}

}  // namespace starnav
