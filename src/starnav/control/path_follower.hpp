#pragma once
// Path following (docs/papers/li2019.md): turns a polyline of world points and the robot's pose
// into a body twist, in one of three motion modes.
//
//   turn_then_drive  (Mecanum, differential) at each vertex stop, rotate in place to face the next
//                    segment, then drive forward, steering at a look-ahead point on the current
//                    segment's line so drift is corrected.
//   holonomic        (Mecanum only) keep the heading the robot had when the path was set and
//                    translate toward a look-ahead point on the current segment's line (the
//                    velocity is expressed in base_link).
//   pure_pursuit     (any drive; the only mode of an Ackermann robot) curvature 2 sin(alpha) / L
//                    to a look-ahead point L ahead along the path, clamped to 1 / R_min with
//                    R_min = wheelbase / tan(max_steer); never turns in place.
//
// Knows the robot only through RobotConfig (drive kind and geometry); nothing of the simulator.
// See docs/navigation.md, "Path following".
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

// Auto: pure_pursuit for an Ackermann robot, turn_then_drive (the paper's choice) otherwise.
enum class MotionMode : std::uint8_t { Auto, TurnThenDrive, Holonomic, PurePursuit };

// "auto", "turn_then_drive", "holonomic", "pure_pursuit".
const char* motion_mode_name(MotionMode mode);
// Throws Error naming `field` for any other name.
MotionMode parse_motion_mode(const std::string& s, const std::string& field);
// The mode a robot with `drive` uses when `requested` is asked for. Throws Error naming `field`
// when the drive cannot do it: holonomic needs a Mecanum robot; an Ackermann robot cannot turn in
// place, so it refuses turn_then_drive (and holonomic) and takes pure_pursuit.
MotionMode resolve_motion_mode(MotionMode requested, DriveKind drive, const std::string& field = "motion_mode");

struct PathFollowerConfig {
  MotionMode mode = MotionMode::Auto;
  double cruise_speed_mps = 0.2;        // the paper's nominal speed
  double min_speed_mps = 0.02;          // floor of the slow-down, so a vertex is reached in finite time
  double look_ahead_m = 0.3;            // turn_then_drive, holonomic: look-ahead on the segment's line
  double pursuit_look_ahead_m = 0.6;    // pure_pursuit: look-ahead along the path
  double heading_gain = 2.0;            // 1/s: yaw rate per radian of heading error
  double max_yaw_rate_radps = 1.0;
  double turn_tolerance_rad = 0.05;     // turn_then_drive: heading error below which driving starts
  double vertex_tolerance_m = 0.01;     // a vertex is reached when at most this far ahead along the segment
  double goal_tolerance_m = 0.05;       // arrived when the last vertex is reached this close to the goal
  double slow_down_distance_m = 0.3;    // speed ramps down linearly over this distance before a stop
  // Throws Error naming the field (prefix "follower.").
  void validate() const;
};

// The follower's declared parameters (section navigation.follower; motion_mode is also the
// scenario's top-level motion_mode and the CLI's --motion-mode).
const ParamTable<PathFollowerConfig>& path_follower_params();

enum class FollowStatus : std::uint8_t {
  NoPath,   // no path set: zero twist
  Turning,  // turn_then_drive: rotating in place toward the current segment
  Driving,  // moving along the current segment
  Arrived,  // within goal tolerance of the last point: zero twist until a new path is set
  Missed,   // pure_pursuit passed the end farther than goal tolerance from it (cannot turn in place): stopped
};
// "no_path", "turning", "driving", "arrived", "missed".
const char* follow_status_name(FollowStatus status);

struct FollowOutput {
  BodyTwist command;  // base_link
  FollowStatus status = FollowStatus::NoPath;
  std::size_t segment = 0;            // current segment: path()[segment] -> path()[segment + 1]
  double distance_remaining_m = 0.0;  // along the path from the robot's projection to its end (< 0 once past it)
  double cross_track_m = 0.0;         // signed distance from the current segment's line, + = robot to its left
  double heading_error_rad = 0.0;     // turn_then_drive, pure_pursuit: bearing of the look-ahead point
                                      // (turning: of the segment); holonomic: held heading minus current
  Vec2 look_ahead = Vec2::Zero();     // world
};

class PathFollower {
 public:
  // Validates both configurations and resolves the mode (see resolve_motion_mode, field
  // "motion_mode"); throws Error naming the field.
  PathFollower(const PathFollowerConfig& config, const RobotConfig& robot);

  MotionMode mode() const { return mode_; }
  const PathFollowerConfig& config() const { return config_; }
  // Minimum turning radius wheelbase / tan(max_steer) of an Ackermann robot; 0 for the others.
  double min_turning_radius_m() const { return min_turning_radius_m_; }

  // A new path (world x, y); consecutive duplicate points are merged. The robot should start near
  // the first point (a caller elsewhere prepends its own position). A single point is reached by
  // a segment from wherever the robot is at the next compute(). Throws Error (field "path") for an
  // empty path or a non-finite point.
  void set_path(std::span<const Vec2> points);
  void clear();
  bool has_path() const { return !points_.empty(); }
  // The path being followed: set_path's points, plus a vertex inserted where the robot stood when
  // it reached the end outside goal tolerance (turn_then_drive, holonomic make a final approach).
  const std::vector<Vec2>& path() const { return points_; }

  // One control step at `pose` (ground truth or estimate). Deterministic: a function of the path,
  // the configuration and the sequence of poses.
  FollowOutput compute(const Pose2& pose);

 private:
  void rebuild_lengths();
  // Speed cap from the stops ahead: min over upcoming vertices j of
  // v_end(j) + (cruise - v_end(j)) * min(1, d_j / slow_down), d_j the distance along the path.
  double speed_cap(std::size_t segment, double along_segment) const;
  // Angle (>= 0) the path turns through at inner vertex `v`.
  double vertex_turn(std::size_t v) const;
  // Speed the robot may pass vertex `v` with (min_speed where it must stop).
  double vertex_speed(std::size_t v) const;
  FollowOutput segment_tracking(const Pose2& pose);
  FollowOutput pure_pursuit(const Pose2& pose);

  PathFollowerConfig config_;
  MotionMode mode_ = MotionMode::TurnThenDrive;
  DriveKind drive_ = DriveKind::Mecanum;
  double min_turning_radius_m_ = 0.0;
  std::vector<Vec2> points_;
  std::vector<double> arc_;  // arc length at each point
  std::size_t segment_ = 0;
  bool turning_ = true;            // turn_then_drive phase
  bool hold_set_ = false;          // holonomic: heading captured at the first compute()
  double hold_yaw_ = 0.0;
  FollowStatus final_ = FollowStatus::NoPath;  // Arrived / Missed once reached (sticky)
};

// The follower as a LocalController (registry name "path_follower").
class PathFollowerController final : public LocalController {
 public:
  PathFollowerController(const PathFollowerConfig& config, const RobotConfig& robot) : follower_(config, robot) {}
  std::string_view name() const override { return "path_follower"; }
  void set_path(std::span<const Vec2> points) override { follower_.set_path(points); }
  void clear() override { follower_.clear(); }
  bool has_path() const override { return follower_.has_path(); }
  const std::vector<Vec2>& path() const override { return follower_.path(); }
  ControlOutput compute(const ControlInput& input) override;
  bool wants_smoothed_path() const override { return follower_.mode() == MotionMode::PurePursuit; }
  std::string motion_mode() const override { return motion_mode_name(follower_.mode()); }
  // The look-ahead point and the tracking errors of the last step (cheap: always kept).
  std::optional<ControlDiagnostics> diagnostics() const override;
  const PathFollower& follower() const { return follower_; }

 private:
  PathFollower follower_;
  // The last step, for diagnostics() (built only when asked).
  double last_t_s_ = 0.0;
  Pose2 last_pose_;
  ControlStatus last_status_ = ControlStatus::Idle;
  FollowOutput last_;
};

}  // namespace starnav
