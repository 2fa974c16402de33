#include "starnav/control/path_follower.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

const char* motion_mode_name(MotionMode mode) {
  switch (mode) {
    case MotionMode::Auto: return "auto";
    case MotionMode::TurnThenDrive: return "turn_then_drive";
    case MotionMode::Holonomic: return "holonomic";
    case MotionMode::PurePursuit: return "pure_pursuit";
  }
  return "auto";
}

MotionMode parse_motion_mode(const std::string& s, const std::string& field) {
  if (s == "auto") return MotionMode::Auto;
  if (s == "turn_then_drive") return MotionMode::TurnThenDrive;
  if (s == "holonomic") return MotionMode::Holonomic;
  if (s == "pure_pursuit") return MotionMode::PurePursuit;
  throw Error("unknown motion mode '" + s + "' (expected auto, turn_then_drive, holonomic or pure_pursuit)", {}, 0,
              field);
}

MotionMode resolve_motion_mode(MotionMode requested, DriveKind drive, const std::string& field) {
  const bool ackermann = drive == DriveKind::Ackermann;
  switch (requested) {
    case MotionMode::Auto: return ackermann ? MotionMode::PurePursuit : MotionMode::TurnThenDrive;
    case MotionMode::TurnThenDrive:
      if (ackermann)
        throw Error("turn_then_drive needs a robot that turns in place; an ackermann robot uses pure_pursuit", {}, 0,
                    field);
      return requested;
    case MotionMode::Holonomic:
      if (drive != DriveKind::Mecanum)
        throw Error(std::string("holonomic needs a mecanum robot, not ") + drive_kind_name(drive), {}, 0, field);
      return requested;
    case MotionMode::PurePursuit: return requested;
  }
  throw Error("unknown motion mode", {}, 0, field);
}

const char* follow_status_name(FollowStatus status) {
  switch (status) {
    case FollowStatus::NoPath: return "no_path";
    case FollowStatus::Turning: return "turning";
    case FollowStatus::Driving: return "driving";
    case FollowStatus::Arrived: return "arrived";
    case FollowStatus::Missed: return "missed";
  }
  return "no_path";
}

namespace {

// PathFollowerConfig's fields are named "follower.<field>" in errors.
void require_field(bool ok, const char* field, const std::string& what) { require(ok, std::string("follower.") + field, what); }
void require_follower_positive(double v, const char* field) { require_positive(v, std::string("follower.") + field); }

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

void PathFollowerConfig::validate() const {
  require_field(mode == MotionMode::Auto || mode == MotionMode::TurnThenDrive || mode == MotionMode::Holonomic ||
              mode == MotionMode::PurePursuit,
          "mode", "unknown motion mode");
  require_follower_positive(cruise_speed_mps, "cruise_speed_mps");
  require_follower_positive(min_speed_mps, "min_speed_mps");
  require_field(min_speed_mps <= cruise_speed_mps, "min_speed_mps", "must not exceed cruise_speed_mps");
  require_follower_positive(look_ahead_m, "look_ahead_m");
  require_follower_positive(pursuit_look_ahead_m, "pursuit_look_ahead_m");
  require_follower_positive(heading_gain, "heading_gain");
  require_follower_positive(max_yaw_rate_radps, "max_yaw_rate_radps");
  require_field(std::isfinite(turn_tolerance_rad) && turn_tolerance_rad > 0.0 && turn_tolerance_rad < kPi,
          "turn_tolerance_rad", "must lie in (0, pi)");
  require_follower_positive(vertex_tolerance_m, "vertex_tolerance_m");
  require_follower_positive(goal_tolerance_m, "goal_tolerance_m");
  // The final approach inserts a vertex farther than goal tolerance from the goal; it must lie
  // beyond the vertex tolerance or it would count as reached at once.
  require_field(vertex_tolerance_m < goal_tolerance_m, "vertex_tolerance_m", "must be < goal_tolerance_m");
  require_follower_positive(slow_down_distance_m, "slow_down_distance_m");
}

PathFollower::PathFollower(const PathFollowerConfig& config, const RobotConfig& robot) : config_(config) {
  config_.validate();
  robot.validate();
  drive_ = robot.drive;
  mode_ = resolve_motion_mode(config_.mode, drive_);
  if (drive_ == DriveKind::Ackermann) min_turning_radius_m_ = 2.0 * robot.half_wheelbase_m / std::tan(robot.max_steer_rad);
}

void PathFollower::clear() {
  points_.clear();
  arc_.clear();
  segment_ = 0;
  turning_ = true;
  hold_set_ = false;
  final_ = FollowStatus::NoPath;
}

void PathFollower::set_path(std::span<const Vec2> points) {
  if (points.empty()) throw Error("empty path", {}, 0, "path");
  std::vector<Vec2> merged;
  merged.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2& q = points[i];
    if (!std::isfinite(q.x()) || !std::isfinite(q.y()))
      throw Error("point " + std::to_string(i) + " is not finite", {}, 0, "path");
    if (merged.empty() || (q - merged.back()).norm() > 1e-9) merged.push_back(q);
  }
  clear();
  points_ = std::move(merged);
  rebuild_lengths();
}

void PathFollower::rebuild_lengths() {
  arc_.assign(points_.size(), 0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) arc_[i] = arc_[i - 1] + (points_[i] - points_[i - 1]).norm();
}

double PathFollower::vertex_turn(std::size_t v) const {
  const Vec2 in = points_[v] - points_[v - 1], out = points_[v + 1] - points_[v];
  return std::abs(std::atan2(cross2(in, out), in.dot(out)));
}

double PathFollower::vertex_speed(std::size_t v) const {
  const double cruise = config_.cruise_speed_mps, slow = config_.min_speed_mps;
  if (v + 1 >= points_.size()) return slow;  // the goal: stop
  const double turn = vertex_turn(v);
  switch (mode_) {
    case MotionMode::TurnThenDrive: return turn > config_.turn_tolerance_rad ? slow : cruise;
    // The velocity turns through `turn` at the vertex; passing it with the along-track component
    // that survives keeps the overshoot of a lagging drive small (a right angle is a stop).
    case MotionMode::Holonomic: return std::max(slow, cruise * std::max(0.0, std::cos(turn)));
    default: return cruise;  // pure pursuit rounds corners within its curvature limit
  }
}

double PathFollower::speed_cap(std::size_t segment, double along_segment) const {
  const double cruise = config_.cruise_speed_mps, ramp = config_.slow_down_distance_m;
  double cap = cruise;
  double d = arc_[segment + 1] - arc_[segment] - along_segment;  // to the next vertex
  for (std::size_t v = segment + 1; v < points_.size(); ++v) {
    const double end = vertex_speed(v);
    cap = std::min(cap, end + (cruise - end) * std::clamp(d / ramp, 0.0, 1.0));
    if (d >= ramp) break;
    if (v + 1 < points_.size()) d += arc_[v + 1] - arc_[v];
  }
  return std::max(cap, config_.min_speed_mps);
}

FollowOutput PathFollower::compute(const Pose2& pose) {
  FollowOutput out;
  if (points_.empty()) return out;
  const Vec2 p = pose.translation();
  if (final_ == FollowStatus::NoPath && points_.size() == 1) {
    if ((p - points_[0]).norm() <= config_.goal_tolerance_m) {
      final_ = FollowStatus::Arrived;
    } else {
      points_.insert(points_.begin(), p);
      rebuild_lengths();
    }
  }
  if (final_ != FollowStatus::NoPath) {
    out.status = final_;
    out.segment = segment_;
    out.distance_remaining_m = points_.size() > 1 ? 0.0 : (p - points_[0]).norm();
    return out;
  }
  if (mode_ == MotionMode::Holonomic && !hold_set_) {
    hold_yaw_ = pose.yaw;
    hold_set_ = true;
  }
  return mode_ == MotionMode::PurePursuit ? pure_pursuit(pose) : segment_tracking(pose);
}

FollowOutput PathFollower::segment_tracking(const Pose2& pose) {
  FollowOutput out;
  const Vec2 p = pose.translation();
  const double k = config_.heading_gain, wmax = config_.max_yaw_rate_radps;
  Vec2 a, u;
  double len = 0.0, along = 0.0;
  for (;;) {
    a = points_[segment_];
    len = arc_[segment_ + 1] - arc_[segment_];
    u = (points_[segment_ + 1] - a) / len;
    along = u.dot(p - a);
    if (len - along > config_.vertex_tolerance_m) break;
    if (segment_ + 2 < points_.size()) {
      // Stop and turn only where the path bends by more than the turn tolerance.
      turning_ = vertex_turn(segment_ + 1) > config_.turn_tolerance_rad;
      ++segment_;
      continue;
    }
    if ((p - points_.back()).norm() <= config_.goal_tolerance_m) {
      final_ = FollowStatus::Arrived;
      out.status = final_;
      out.segment = segment_;
      out.distance_remaining_m = len - along;
      out.cross_track_m = cross2(u, p - a);
      return out;
    }
    // The end of the path was reached off to the side: approach the goal from here.
    points_.insert(points_.end() - 1, p);
    rebuild_lengths();
    ++segment_;
    turning_ = true;
  }
  out.segment = segment_;
  out.distance_remaining_m = (len - along) + (arc_.back() - arc_[segment_ + 1]);
  out.cross_track_m = cross2(u, p - a);

  if (mode_ == MotionMode::TurnThenDrive && turning_) {
    const double err = angle_diff(std::atan2(u.y(), u.x()), pose.yaw);
    if (std::abs(err) > config_.turn_tolerance_rad) {
      out.status = FollowStatus::Turning;
      out.heading_error_rad = err;
      out.command.wz = std::clamp(k * err, -wmax, wmax);
      out.look_ahead = points_[segment_ + 1];
      return out;
    }
    turning_ = false;
  }

  // The look-ahead point lies on the segment's line, extended past its end, so the steering stays
  // well conditioned right up to the vertex.
  const Vec2 look = a + (along + config_.look_ahead_m) * u;
  out.look_ahead = look;
  out.status = FollowStatus::Driving;
  const double speed = speed_cap(segment_, along);
  if (mode_ == MotionMode::TurnThenDrive) {
    const Vec2 d = pose.inverse_transform(look);
    const double bearing = std::atan2(d.y(), d.x());
    out.heading_error_rad = bearing;
    out.command.vx = speed * std::max(0.0, std::cos(bearing));
    out.command.wz = std::clamp(k * bearing, -wmax, wmax);
  } else {
    const Vec2 v_world = speed * (look - p).normalized();
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    out.command.vx = c * v_world.x() + s * v_world.y();
    out.command.vy = -s * v_world.x() + c * v_world.y();
    out.heading_error_rad = angle_diff(hold_yaw_, pose.yaw);
    out.command.wz = std::clamp(k * out.heading_error_rad, -wmax, wmax);
  }
  return out;
}

FollowOutput PathFollower::pure_pursuit(const Pose2& pose) {
  FollowOutput out;
  const Vec2 p = pose.translation();
  const std::size_t last = points_.size() - 2;  // index of the last segment
  const double ld = config_.pursuit_look_ahead_m;
  // Closest point on the path among the segments from the current one to two look-ahead distances
  // beyond the current projection; the segment index never moves backward, so a path passing near
  // itself cannot pull the robot back.
  const auto along_on = [&](std::size_t j) {
    const Vec2 u = (points_[j + 1] - points_[j]) / (arc_[j + 1] - arc_[j]);
    const double along = u.dot(p - points_[j]);
    return std::clamp(along, 0.0, j == last ? std::numeric_limits<double>::infinity() : arc_[j + 1] - arc_[j]);
  };
  const double window_end = arc_[segment_] + along_on(segment_) + 2.0 * ld;
  double best_d = std::numeric_limits<double>::infinity();
  std::size_t best = segment_;
  for (std::size_t j = segment_; j <= last && arc_[j] <= window_end; ++j) {
    const Vec2 u = (points_[j + 1] - points_[j]) / (arc_[j + 1] - arc_[j]);
    const double dist = (p - (points_[j] + along_on(j) * u)).norm();
    if (dist < best_d) {
      best_d = dist;
      best = j;
    }
  }
  segment_ = best;
  const Vec2 a = points_[segment_];
  const Vec2 u = (points_[segment_ + 1] - a) / (arc_[segment_ + 1] - arc_[segment_]);
  const double along = along_on(segment_);
  const double s_path = arc_[segment_] + along;
  out.segment = segment_;
  out.distance_remaining_m = arc_.back() - s_path;
  out.cross_track_m = cross2(u, p - a);
  if (out.distance_remaining_m <= config_.vertex_tolerance_m) {
    // The robot cannot turn in place to correct a miss; the caller decides (replan, reverse).
    final_ = (p - points_.back()).norm() <= config_.goal_tolerance_m ? FollowStatus::Arrived : FollowStatus::Missed;
    out.status = final_;
    return out;
  }
  // Look-ahead point ld along the path, on the last segment's line beyond the end.
  const double s_look = s_path + ld;
  std::size_t j = segment_;
  while (j < last && arc_[j + 1] <= s_look) ++j;
  const Vec2 uj = (points_[j + 1] - points_[j]) / (arc_[j + 1] - arc_[j]);
  const Vec2 look = points_[j] + (s_look - arc_[j]) * uj;
  out.look_ahead = look;
  const Vec2 d = pose.inverse_transform(look);
  const double dist = d.norm();
  const double alpha = std::atan2(d.y(), d.x());
  out.heading_error_rad = alpha;
  double kappa = dist > 1e-9 ? 2.0 * std::sin(alpha) / dist : 0.0;
  if (min_turning_radius_m_ > 0.0) kappa = std::clamp(kappa, -1.0 / min_turning_radius_m_, 1.0 / min_turning_radius_m_);
  double speed = speed_cap(segment_, along);
  // Keep the curvature (the geometry of the turn) and slow down where the yaw rate would exceed its limit.
  if (std::abs(speed * kappa) > config_.max_yaw_rate_radps) speed = config_.max_yaw_rate_radps / std::abs(kappa);
  out.status = FollowStatus::Driving;
  out.command.vx = speed;
  out.command.wz = speed * kappa;
  return out;
}

}  // namespace starnav

// ---- the component -------------------------------------------------------------------------------

namespace starnav {

const char* control_status_name(ControlStatus s) {
  switch (s) {
    case ControlStatus::Idle: return "idle";
    case ControlStatus::Tracking: return "tracking";
    case ControlStatus::Arrived: return "arrived";
    case ControlStatus::CannotReach: return "cannot_reach";
    case ControlStatus::Blocked: return "blocked";
    case ControlStatus::AtCusp: return "at_cusp";
  }
  return "unknown";
}

Footprint footprint_of(const RobotConfig& config) { return {config.body_length_m, config.body_width_m}; }

FootprintModel body_footprint_model(const RobotConfig& config) {
  FootprintModel m;
  m.circle = false;
  m.half_length_m = 0.5 * config.body_length_m;
  m.half_width_m = 0.5 * config.body_width_m;
  m.center_x_m = make_robot_model(config)->body_center().x();
  return m;
}

double min_turning_radius_of(const RobotConfig& config) {
  return config.drive == DriveKind::Ackermann ? 2.0 * config.half_wheelbase_m / std::tan(config.max_steer_rad) : 0.0;
}

VelocityLimits velocity_limits_of(const RobotConfig& config) {
  // One wheel at its speed limit, the others as the motion needs (the inverse kinematics of
  // robot_model.cpp): the largest speed along each axis alone.
  VelocityLimits l;
  const double v = config.max_wheel_speed_radps * config.wheel_radius_m;
  l.max_vx_mps = v;
  switch (config.drive) {
    case DriveKind::Mecanum:
      l.max_vy_mps = v * std::tan(config.roller_angle_rad);
      l.max_yaw_rate_radps = v / (config.half_track_m + config.half_wheelbase_m);
      break;
    case DriveKind::Differential: l.max_yaw_rate_radps = v / config.half_track_m; break;
    case DriveKind::Ackermann: l.max_yaw_rate_radps = 0.0; break;
  }
  return l;
}

void LocalController::set_path_poses(std::span<const Pose2> poses, std::span<const std::uint8_t> reversing) {
  if (poses.size() != reversing.size()) throw Error("a direction for every pose of the path", {}, 0, "path");
  std::vector<Vec2> points;
  points.reserve(poses.size());
  for (const Pose2& p : poses) points.push_back(p.translation());
  set_path(points);
}

VelocityLimits with_speed_limit(VelocityLimits limits, double max_speed_mps) {
  limits.max_vx_mps = std::min(limits.max_vx_mps, max_speed_mps);
  limits.max_vy_mps = std::min(limits.max_vy_mps, max_speed_mps);
  limits.max_speed_mps = std::min(limits.max_speed_mps, max_speed_mps);
  return limits;
}

double translation_scale(const BodyTwist& twist, const VelocityLimits& limits) {
  double scale = 1.0;
  const auto bound = [&scale](double v, double limit) {
    if (std::abs(v) > limit) scale = std::min(scale, limit / std::abs(v));
  };
  bound(twist.vx, limits.max_vx_mps);
  bound(twist.vy, limits.max_vy_mps);
  bound(std::hypot(twist.vx, twist.vy), limits.max_speed_mps);
  return std::max(scale, 0.0);
}

const ParamTable<PathFollowerConfig>& path_follower_params() {
  static const ParamTable<PathFollowerConfig> table = [] {
    using C = PathFollowerConfig;
    ParamTable<C> t;
    t.choice("motion_mode", {"auto", "turn_then_drive", "holonomic", "pure_pursuit"},
             [](C& c, const std::string& v) { c.mode = parse_motion_mode(v, "motion_mode"); },
             [](const C& c) { return std::string(motion_mode_name(c.mode)); },
             "auto: pure_pursuit for an ackermann robot, turn_then_drive otherwise (also the scenario's top-level "
             "motion_mode and --motion-mode)");
    t.real("cruise_speed_mps", &C::cruise_speed_mps, positive(), "m/s", "nominal speed (the paper's 0.2)");
    t.real("min_speed_mps", &C::min_speed_mps, positive(), "m/s", "floor of the slow-down, <= cruise_speed_mps");
    t.real("look_ahead_m", &C::look_ahead_m, positive(), "m", "turn_then_drive, holonomic: look-ahead on the segment's line");
    t.real("pursuit_look_ahead_m", &C::pursuit_look_ahead_m, positive(), "m", "pure_pursuit: look-ahead along the path");
    t.real("heading_gain", &C::heading_gain, positive(), "1/s", "yaw rate per radian of heading error");
    t.real("max_yaw_rate_degps", &C::max_yaw_rate_radps, positive(), "deg/s", "yaw rate limit", kPi / 180.0);
    t.real("turn_tolerance_deg", &C::turn_tolerance_rad, open(0.0, 180.0), "deg",
           "turn_then_drive: heading error below which driving starts", kPi / 180.0);
    t.real("vertex_tolerance_m", &C::vertex_tolerance_m, positive(), "m",
           "a vertex is reached this far ahead along its segment (< goal_tolerance_m)");
    t.real("goal_tolerance_m", &C::goal_tolerance_m, positive(), "m", "the path's end is reached this close");
    t.real("slow_down_distance_m", &C::slow_down_distance_m, positive(), "m",
           "speed ramps down linearly over this distance before a stop");
    return t;
  }();
  return table;
}

ControlOutput PathFollowerController::compute(const ControlInput& input) {
  const FollowOutput out = follower_.compute(input.pose);
  ControlOutput c;
  c.twist = out.command;
  // The follower plans its speed from its own settings; the step's limits (a speed-limit zone)
  // cap it, the direction of travel kept. Pure pursuit drives an arc: its yaw rate scales along,
  // keeping the curvature; the other modes steer the heading by the yaw rate, which stays.
  if (const double scale = translation_scale(c.twist, input.limits); scale < 1.0) {
    c.twist.vx *= scale;
    c.twist.vy *= scale;
    if (follower_.mode() == MotionMode::PurePursuit) c.twist.wz *= scale;
  }
  switch (out.status) {
    case FollowStatus::NoPath: c.status = ControlStatus::Idle; break;
    case FollowStatus::Turning:
    case FollowStatus::Driving: c.status = ControlStatus::Tracking; break;
    case FollowStatus::Arrived: c.status = ControlStatus::Arrived; break;
    case FollowStatus::Missed: c.status = ControlStatus::CannotReach; break;
  }
  last_t_s_ = input.t_s;
  last_pose_ = input.pose;
  last_status_ = c.status;
  last_ = out;
  return c;
}

std::optional<ControlDiagnostics> PathFollowerController::diagnostics() const {
  ControlDiagnostics d;
  d.t_s = last_t_s_;
  d.pose = last_pose_;
  d.status = last_status_;
  d.command = last_.command;
  d.points = {{"look-ahead", last_.look_ahead}};
  d.terms = {{"cross_track_m", last_.cross_track_m},
             {"heading_error_deg", last_.heading_error_rad * 180.0 / kPi},
             {"distance_remaining_m", last_.distance_remaining_m}};
  return d;
}

LocalControllerDef path_follower_controller() {
  LocalControllerDef d;
  d.info.role = Role::LocalController;
  d.info.name = "path_follower";
  d.info.section = "follower";
  d.info.summary = "Li et al. 2019 path following: turn_then_drive, holonomic or pure_pursuit (docs/papers/li2019.md)";
  d.info.params = path_follower_params().specs();
  // Its pure_pursuit mode takes the keys of Nav2's pure pursuit (docs/ros2.md).
  d.info.nav2_counterpart = "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController";
  d.make = [](const LocalControllerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<LocalController> {
    const PathFollowerConfig c = configured(path_follower_params(), settings, ctx.file);
    try {
      return std::make_unique<PathFollowerController>(c, ctx.robot);  // validates, resolves the motion mode
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
