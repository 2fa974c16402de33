// Nav2's Regulated Pure Pursuit controller (Macenski et al. 2023): pure pursuit of a carrot on the
// path at a look-ahead distance (fixed, or scaled with the speed), its linear speed regulated down
// on tight curvature, near obstacles (the costmap's distance field at the robot) and on the
// approach to the path's end; it rotates in place toward the carrot when the heading error is
// large and to the goal's heading at the end; and before each command it checks the commanded arc
// up to the carrot (or a time limit) against the costmap with the robot's footprint, stopping
// (blocked, so the navigator recovers) rather than driving into an obstacle.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "starnav/control/local_controller.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/map/footprint_checker.hpp"

namespace starnav {

namespace {

// Nav2's parameters and defaults, in SI units (angles in degrees where the key says so).
struct RegulatedPurePursuitConfig {
  double desired_linear_vel_mps = 0.5;
  double lookahead_dist_m = 0.6;
  double min_lookahead_dist_m = 0.3;
  double max_lookahead_dist_m = 0.9;
  double lookahead_time_s = 1.5;
  bool use_velocity_scaled_lookahead_dist = false;
  bool use_regulated_linear_velocity_scaling = true;
  double regulated_linear_scaling_min_radius_m = 0.9;
  double regulated_linear_scaling_min_speed_mps = 0.25;
  bool use_cost_regulated_linear_velocity_scaling = true;
  double cost_scaling_dist_m = 0.6;
  double cost_scaling_gain = 1.0;
  double approach_velocity_scaling_dist_m = 0.6;
  double min_approach_linear_velocity_mps = 0.05;
  bool use_collision_detection = true;
  double max_allowed_time_to_collision_up_to_carrot_s = 1.0;
  bool use_rotate_to_heading = true;
  double rotate_to_heading_angular_vel_radps = 1.8;
  double rotate_to_heading_min_angle_rad = 0.785;
  double max_angular_accel_radps2 = 3.2;
  double control_period_s = 0.05;  // Nav2's controller_frequency of 20 Hz
  double max_robot_pose_search_dist_m = 10.0;
};

const ParamTable<RegulatedPurePursuitConfig>& regulated_pure_pursuit_params() {
  static const ParamTable<RegulatedPurePursuitConfig> table = [] {
    using C = RegulatedPurePursuitConfig;
    const double deg = kPi / 180.0;
    ParamTable<C> t;
    t.real("desired_linear_vel_mps", &C::desired_linear_vel_mps, positive(), "m/s", "the cruise speed (capped by the robot's limit)");
    t.real("lookahead_dist_m", &C::lookahead_dist_m, positive(), "m", "the carrot's distance (fixed look-ahead)");
    t.real("min_lookahead_dist_m", &C::min_lookahead_dist_m, positive(), "m", "the speed-scaled look-ahead's lower bound");
    t.real("max_lookahead_dist_m", &C::max_lookahead_dist_m, positive(), "m", "... and upper bound");
    t.real("lookahead_time_s", &C::lookahead_time_s, positive(), "s", "speed-scaled look-ahead: speed times this");
    t.boolean("use_velocity_scaled_lookahead_dist", &C::use_velocity_scaled_lookahead_dist,
              "the look-ahead grows with the speed (within its bounds) instead of being fixed");
    t.boolean("use_regulated_linear_velocity_scaling", &C::use_regulated_linear_velocity_scaling,
              "slow down on curvature tighter than regulated_linear_scaling_min_radius_m");
    t.real("regulated_linear_scaling_min_radius_m", &C::regulated_linear_scaling_min_radius_m, positive(), "m",
           "turning radius below which the speed scales down in proportion");
    t.real("regulated_linear_scaling_min_speed_mps", &C::regulated_linear_scaling_min_speed_mps, non_negative(), "m/s",
           "the regulated speed's floor (curvature and obstacles)");
    t.boolean("use_cost_regulated_linear_velocity_scaling", &C::use_cost_regulated_linear_velocity_scaling,
              "slow down when an obstacle is nearer than cost_scaling_dist_m");
    t.real("cost_scaling_dist_m", &C::cost_scaling_dist_m, positive(), "m",
           "distance from the robot's centre to the nearest obstacle below which the speed scales down");
    t.real("cost_scaling_gain", &C::cost_scaling_gain, open(0.0, 1.0e9), "", "the obstacle scaling's gain (speed x gain x d / dist)");
    t.real("approach_velocity_scaling_dist_m", &C::approach_velocity_scaling_dist_m, non_negative(), "m",
           "path length to the end below which the speed scales down");
    t.real("min_approach_linear_velocity_mps", &C::min_approach_linear_velocity_mps, positive(), "m/s", "the approach's speed floor");
    t.boolean("use_collision_detection", &C::use_collision_detection,
              "check the commanded arc up to the carrot against the costmap; stop (blocked) before a collision");
    t.real("max_allowed_time_to_collision_up_to_carrot_s", &C::max_allowed_time_to_collision_up_to_carrot_s, positive(), "s",
           "the collision check's horizon (or the carrot's distance, if nearer)");
    t.boolean("use_rotate_to_heading", &C::use_rotate_to_heading,
              "rotate in place toward the carrot when the heading error is large, and to the goal's heading at the end");
    t.real("rotate_to_heading_angular_vel_degps", &C::rotate_to_heading_angular_vel_radps, positive(), "deg/s",
           "yaw rate of those rotations (capped by the robot's limit)", deg);
    t.real("rotate_to_heading_min_angle_deg", &C::rotate_to_heading_min_angle_rad, open(0.0, 180.0), "deg",
           "heading error to the carrot above which the robot rotates in place", deg);
    t.real("max_angular_accel_degps2", &C::max_angular_accel_radps2, positive(), "deg/s^2", "yaw acceleration limit of the rotations",
           deg);
    t.real("control_period_s", &C::control_period_s, open(0.0, 10.0), "s", "time between two commands (the command is held)");
    t.real("max_robot_pose_search_dist_m", &C::max_robot_pose_search_dist_m, positive(), "m",
           "the robot's place on the path is searched this far along it from the last one (a path passing near itself "
           "is followed in order, and a step costs this much path, not all of it)");
    return t;
  }();
  return table;
}

class RegulatedPurePursuit final : public LocalController {
 public:
  explicit RegulatedPurePursuit(const RegulatedPurePursuitConfig& c) : c_(c) {}
  std::string_view name() const override { return "regulated_pure_pursuit"; }
  void set_path(std::span<const Vec2> points) override {
    if (points.empty()) throw Error("empty path", {}, 0, "path");
    for (const Vec2& p : points)
      if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw Error("a path point is not finite", {}, 0, "path");
    path_.assign(points.begin(), points.end());
    along_.assign(path_.size(), 0.0);
    for (std::size_t i = 1; i < path_.size(); ++i) along_[i] = along_[i - 1] + (path_[i] - path_[i - 1]).norm();
    segment_ = 0;
  }
  void clear() override {
    path_.clear();
    along_.clear();
    segment_ = 0;
  }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  double control_period_s() const override { return c_.control_period_s; }
  void keep_diagnostics(bool on) override { keep_ = on; }
  std::optional<ControlDiagnostics> diagnostics() const override { return keep_ ? std::optional(last_) : std::nullopt; }

  ControlOutput compute(const ControlInput& in) override {
    ControlOutput out = step(in);
    if (keep_) {
      last_.t_s = in.t_s;
      last_.pose = in.pose;
      last_.status = out.status;
      last_.command = out.twist;
    }
    return out;
  }

 private:
  // The collision check of the footprint the navigator gives (built again only when it changes).
  const FootprintMotionChecker& motion(const Footprint& f) {
    if (!motion_ || f.length_m != footprint_.length_m || f.width_m != footprint_.width_m) {
      FootprintModel m;
      m.circle = false;
      m.half_length_m = 0.5 * f.length_m;
      m.half_width_m = 0.5 * f.width_m;
      motion_.emplace(m);
      footprint_ = f;
    }
    return *motion_;
  }

  ControlOutput step(const ControlInput& in) {
    if (keep_) last_ = {};
    if (path_.empty()) return {};
    const Vec2 p = in.pose.translation();
    advance_progress(p);
    const double to_goal = (in.goal - p).norm();
    const double wz_limit = std::min(c_.rotate_to_heading_angular_vel_radps, in.limits.max_yaw_rate_radps);

    // At the goal: turn to its heading, if any, then stop.
    if (in.goal_xy_reached || to_goal <= in.goal_tolerance_m) {
      if (!in.goal_yaw || std::abs(wrap_angle(*in.goal_yaw - in.pose.yaw)) <= in.goal_yaw_tolerance_rad)
        return {{}, ControlStatus::Arrived};
      const double error = wrap_angle(*in.goal_yaw - in.pose.yaw);
      return rotate(in, error, wz_limit);
    }

    const double speed = std::hypot(in.velocity.vx, in.velocity.vy);
    const double lookahead = c_.use_velocity_scaled_lookahead_dist
                                 ? std::clamp(speed * c_.lookahead_time_s, c_.min_lookahead_dist_m, c_.max_lookahead_dist_m)
                                 : c_.lookahead_dist_m;
    const Vec2 carrot = carrot_at(p, lookahead);
    const Vec2 local = in.pose.inverse_transform(carrot);  // base_link
    if (keep_) {
      last_.points.emplace_back("carrot", carrot);
      last_.terms.emplace_back("lookahead_m", lookahead);
    }
    const double bearing = std::atan2(local.y(), local.x());
    if (c_.use_rotate_to_heading && std::abs(bearing) > c_.rotate_to_heading_min_angle_rad) return rotate(in, bearing, wz_limit);

    // The arc through the carrot: curvature 2 y / L^2.
    const double d2 = local.squaredNorm();
    const double curvature = d2 > 1e-12 ? 2.0 * local.y() / d2 : 0.0;
    double v = std::min(c_.desired_linear_vel_mps, in.limits.max_vx_mps);
    double curvature_v = v, cost_v = v;
    if (c_.use_regulated_linear_velocity_scaling && std::abs(curvature) > 1e-12) {
      const double radius = 1.0 / std::abs(curvature);
      if (radius < c_.regulated_linear_scaling_min_radius_m) curvature_v *= radius / c_.regulated_linear_scaling_min_radius_m;
    }
    if (c_.use_cost_regulated_linear_velocity_scaling && in.clearance) {
      const GridGeometry& g = in.clearance->geometry();
      if (const std::optional<Cell> cell = g.world_to_cell(p)) {
        in.clearance->refresh({cell->x, cell->y, cell->x + 1, cell->y + 1});
        const double d = in.clearance->distance_m(g.index(cell->x, cell->y));
        if (std::isfinite(d) && d < c_.cost_scaling_dist_m) cost_v *= c_.cost_scaling_gain * d / c_.cost_scaling_dist_m;
        if (keep_) last_.terms.emplace_back("obstacle_distance_m", std::isfinite(d) ? d : -1.0);
      }
    }
    // Regulated, but never below the floor (nor above the cruise speed).
    v = std::min(v, std::max(std::min(curvature_v, cost_v), c_.regulated_linear_scaling_min_speed_mps));
    // The approach: slower as the path's end nears.
    const double remaining = remaining_length(p);
    if (c_.approach_velocity_scaling_dist_m > 0.0 && remaining < c_.approach_velocity_scaling_dist_m)
      v = std::min(v, std::max(v * remaining / c_.approach_velocity_scaling_dist_m, c_.min_approach_linear_velocity_mps));
    double wz = v * curvature;
    if (std::abs(wz) > in.limits.max_yaw_rate_radps) {
      // The robot cannot turn that fast: the same arc, slower.
      v *= in.limits.max_yaw_rate_radps / std::abs(wz);
      wz = std::copysign(in.limits.max_yaw_rate_radps, wz);
    }
    if (keep_) {
      last_.terms.emplace_back("curvature_1pm", curvature);
      last_.terms.emplace_back("remaining_m", remaining);
    }
    const BodyTwist command{v, 0.0, wz};
    // The commanded arc up to the carrot (or the horizon), checked with the footprint.
    const double horizon = std::min(c_.max_allowed_time_to_collision_up_to_carrot_s, v > 1e-9 ? std::sqrt(d2) / v : 0.0);
    const bool clear = !c_.use_collision_detection || !in.clearance || horizon <= 0.0 ||
                       motion(in.footprint).clear(*in.clearance, in.pose, command, horizon, std::max(0.02, in.clearance->geometry().resolution / std::max(v, 0.05)));
    if (keep_) record_arc(in.pose, command, std::max(horizon, 0.5), clear);
    if (!clear) return {{}, ControlStatus::Blocked};
    return {command, ControlStatus::Tracking};
  }

  // A rotation in place toward `error` (rad), at most `wz_limit`, slowing near zero error, within
  // the angular acceleration from the current yaw rate; checked for the footprint too.
  ControlOutput rotate(const ControlInput& in, double error, double wz_limit) {
    double wz = std::copysign(std::min(wz_limit, std::abs(error) / std::max(c_.control_period_s, 1e-3)), error);
    const double dw = c_.max_angular_accel_radps2 * c_.control_period_s;
    wz = std::clamp(wz, in.velocity.wz - dw, in.velocity.wz + dw);
    const BodyTwist command{0.0, 0.0, wz};
    const bool clear = !c_.use_collision_detection || !in.clearance ||
                       motion(in.footprint).clear(*in.clearance, in.pose, command, std::max(c_.control_period_s, 0.1));
    if (keep_) {
      last_.terms.emplace_back("heading_error_deg", rad_to_deg(error));
      record_arc(in.pose, command, std::max(c_.control_period_s, 0.5), clear);
    }
    if (!clear) return {{}, ControlStatus::Blocked};
    return {command, ControlStatus::Tracking};
  }

  void record_arc(const Pose2& pose, const BodyTwist& command, double duration_s, bool clear) {
    ControlCandidate c;
    c.twist = command;
    c.status = clear ? CandidateStatus::Valid : CandidateStatus::Collides;
    for (int k = 1; k <= 20; ++k) c.trajectory.push_back(advance_on_arc(pose, command.vx, command.vy, command.wz, duration_s * k / 20.0));
    last_.candidates.push_back(std::move(c));
    last_.chosen = clear ? 0 : -1;
  }

  // The segment nearest the robot, searched forward from the last one up to the search distance
  // along the path (progress never goes back, so a path that passes near itself is followed in order).
  void advance_progress(const Vec2& p) {
    if (path_.size() < 2) return;
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_segment = segment_;
    const double search_end = along_[segment_] + c_.max_robot_pose_search_dist_m;
    for (std::size_t i = segment_; i + 1 < path_.size() && along_[i] <= search_end; ++i) {
      const double d = (closest_on_segment(p, i) - p).squaredNorm();
      if (d < best) best = d, best_segment = i;
    }
    segment_ = best_segment;
  }
  Vec2 closest_on_segment(const Vec2& p, std::size_t i) const {
    const Vec2 a = path_[i], b = path_[i + 1], ab = b - a;
    const double l2 = ab.squaredNorm();
    const double s = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return a + s * ab;
  }
  // The first point of the path ahead at `lookahead` from the robot (the circle's crossing of the
  // first segment that leaves it), else the path's end.
  Vec2 carrot_at(const Vec2& p, double lookahead) const {
    if (path_.size() < 2) return path_.back();
    Vec2 from = closest_on_segment(p, segment_);
    for (std::size_t i = segment_; i + 1 < path_.size(); ++i) {
      const Vec2 to = path_[i + 1];
      if ((to - p).norm() >= lookahead) {
        // |from + s (to - from) - p| = lookahead, s in [0, 1]: the larger root.
        const Vec2 d = to - from, f = from - p;
        const double a = d.squaredNorm(), b = 2.0 * f.dot(d), cc = f.squaredNorm() - lookahead * lookahead;
        const double disc = std::max(0.0, b * b - 4.0 * a * cc);
        const double s = a > 0.0 ? std::clamp((-b + std::sqrt(disc)) / (2.0 * a), 0.0, 1.0) : 1.0;
        return from + s * d;
      }
      from = to;
    }
    return path_.back();
  }
  double remaining_length(const Vec2& p) const {
    if (path_.size() < 2) return (path_.back() - p).norm();
    return (path_[segment_ + 1] - closest_on_segment(p, segment_)).norm() + along_.back() - along_[segment_ + 1];
  }

  RegulatedPurePursuitConfig c_;
  std::optional<FootprintMotionChecker> motion_;
  Footprint footprint_;
  std::vector<Vec2> path_;
  std::vector<double> along_;  // path length from the start to each point
  std::size_t segment_ = 0;
  bool keep_ = false;
  ControlDiagnostics last_;
};

}  // namespace

LocalControllerDef regulated_pure_pursuit_controller() {
  LocalControllerDef d;
  d.info.role = Role::LocalController;
  d.info.name = "regulated_pure_pursuit";
  d.info.section = "rpp";
  d.info.summary = "Nav2's Regulated Pure Pursuit: a carrot on the path, speed regulated by curvature, obstacles and approach; "
                   "rotates to heading; checks its arc on the costmap";
  d.info.capabilities = {Capability::GoalHeading, Capability::ChecksFootprint};
  d.info.params = regulated_pure_pursuit_params().specs();
  // Its keys are Nav2's with their units' suffixes: a Nav2 parameter file maps onto them (docs/ros2.md).
  d.info.nav2_counterpart = "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController";
  d.make = [](const LocalControllerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<LocalController> {
    const RegulatedPurePursuitConfig c = configured(regulated_pure_pursuit_params(), settings, ctx.file);
    if (c.min_lookahead_dist_m > c.max_lookahead_dist_m)
      throw Error("min_lookahead_dist_m " + format_readable(c.min_lookahead_dist_m) + " m is above max_lookahead_dist_m " +
                      format_readable(c.max_lookahead_dist_m) + " m",
                  ctx.file, 0, "min_lookahead_dist_m");
    if (c.use_rotate_to_heading && ctx.robot.drive == DriveKind::Ackermann)
      throw Error("an Ackermann robot cannot rotate in place: set use_rotate_to_heading to false", ctx.file, 0, "use_rotate_to_heading");
    return std::make_unique<RegulatedPurePursuit>(c);
  };
  return d;
}

}  // namespace starnav
