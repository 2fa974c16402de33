// Path following (spec li2019 section 9). Closed forms: pure pursuit's curvature 2 y / L^2 for a
// point L away, progress along a straight path. Closed loop: the follower drives sim::Vehicle on
// the flat floor over an L-shaped and a zigzag polyline in every motion mode; each run must arrive
// within goal tolerance and stay within a stated distance of the polyline, measured by brute force
// over its segments (not with the follower's own bookkeeping). Holonomic runs keep their heading,
// turn_then_drive runs stand still while they turn, Ackermann runs never exceed 1 / R_min.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "starnav/control/path_follower.hpp"
#include "starnav/core/error.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {
namespace {

constexpr double kDt = 0.01;  // the simulator's default step (scenario sim.dt_s)

// Distance from p to the polyline: minimum over its segments of the point-segment distance.
double distance_to_polyline(const std::vector<Vec2>& poly, const Vec2& p) {
  double best = (p - poly.front()).norm();
  for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
    const Vec2 a = poly[i], ab = poly[i + 1] - poly[i];
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (a + t * ab)).norm());
  }
  return best;
}

const std::vector<Vec2> kLShape = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 1.5}};
const std::vector<Vec2> kZigzag = {{0.0, 0.0}, {1.0, 0.8}, {2.0, 0.0}, {3.0, 0.8}, {4.0, 0.0}};
// Bends of atan(1/2) = 26.6 deg, as a line-of-sight smoothed grid path has.
const std::vector<Vec2> kGentle = {{0.0, 0.0}, {2.0, 0.0}, {4.0, 1.0}, {6.0, 1.0}, {8.0, 0.0}};
// Bends of 63 deg over short legs: pure pursuit asks for more than 1 / R_min here.
const std::vector<Vec2> kTight = {{0.0, 0.0}, {2.0, 0.0}, {2.5, 1.0}, {4.5, 1.0}};

VehicleConfig vehicle_config(DriveKind drive, bool lag) {
  VehicleConfig c;
  c.robot.drive = drive;
  if (!lag) {
    c.robot.actuator_lag_s = 0.0;
    c.robot.max_wheel_accel_radps2 = 1e9;
    c.robot.max_steer_rate_radps = 1e3;
  }
  return c;
}

struct FollowRun {
  std::vector<Pose2> poses;        // after each step
  std::vector<FollowOutput> outs;  // command of each step
  std::vector<BodyTwist> achieved;
  FollowStatus status = FollowStatus::NoPath;
  double arrival_s = 0.0;
  double max_deviation_m = 0.0;   // from the polyline as given
  double goal_distance_m = 0.0;   // at rest, 2 s after arrival
  double max_yaw_drift_rad = 0.0; // from the start heading
};

FollowRun follow(const PathFollowerConfig& fc, const VehicleConfig& vc, const std::vector<Vec2>& path, const Pose2& start,
           double t_max = 120.0) {
  const World world;  // the floor z = 0, no obstacles
  Vehicle vehicle(world, vc, start, Rng(7));
  PathFollower follower(fc, vc.robot);
  follower.set_path(path);
  FollowRun run;
  std::vector<VehicleEvent> events;
  double t = 0.0;
  for (; t < t_max; t += kDt) {
    const Pose2 pose = vehicle.state().pose.to_pose2();
    const FollowOutput out = follower.compute(pose);
    run.status = out.status;
    if (out.status == FollowStatus::Arrived || out.status == FollowStatus::Missed) break;
    vehicle.step(out.command, kDt, events);
    run.outs.push_back(out);
    run.poses.push_back(vehicle.state().pose.to_pose2());
    run.achieved.push_back(vehicle.state().twist);
  }
  run.arrival_s = t;
  // Let the drive come to rest under a zero command (the lag coasts a little).
  for (int i = 0; i < 200; ++i) {
    vehicle.step(BodyTwist{}, kDt, events);
    run.poses.push_back(vehicle.state().pose.to_pose2());
  }
  EXPECT_TRUE(events.empty()) << "the flat floor has nothing to hit";
  for (const Pose2& p : run.poses) {
    run.max_deviation_m = std::max(run.max_deviation_m, distance_to_polyline(path, p.translation()));
    run.max_yaw_drift_rad = std::max(run.max_yaw_drift_rad, std::abs(angle_diff(p.yaw, start.yaw)));
  }
  run.goal_distance_m = (run.poses.back().translation() - path.back()).norm();
  return run;
}

PathFollowerConfig mode_config(MotionMode mode) {
  PathFollowerConfig c;
  c.mode = mode;
  return c;
}

void report(const char* what, const FollowRun& r) {
  std::printf("%-44s arrived %5.1f s, max deviation %.4f m, goal %.4f m, yaw drift %.4f rad\n", what, r.arrival_s,
              r.max_deviation_m, r.goal_distance_m, r.max_yaw_drift_rad);
}

// ---------------------------------------------------------------------------------------------
// Configuration and modes.

TEST(PathFollower, ParsesAndNamesMotionModes) {
  for (const MotionMode m : {MotionMode::Auto, MotionMode::TurnThenDrive, MotionMode::Holonomic, MotionMode::PurePursuit})
    EXPECT_EQ(parse_motion_mode(motion_mode_name(m), "motion_mode"), m);
  try {
    parse_motion_mode("sideways", "motion_mode");
    FAIL() << "unknown mode accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "motion_mode");
    EXPECT_NE(e.message().find("sideways"), std::string::npos);
  }
}

TEST(PathFollower, ResolvesModesPerDrive) {
  EXPECT_EQ(resolve_motion_mode(MotionMode::Auto, DriveKind::Mecanum), MotionMode::TurnThenDrive);
  EXPECT_EQ(resolve_motion_mode(MotionMode::Auto, DriveKind::Differential), MotionMode::TurnThenDrive);
  EXPECT_EQ(resolve_motion_mode(MotionMode::Auto, DriveKind::Ackermann), MotionMode::PurePursuit);
  EXPECT_EQ(resolve_motion_mode(MotionMode::Holonomic, DriveKind::Mecanum), MotionMode::Holonomic);
  EXPECT_EQ(resolve_motion_mode(MotionMode::PurePursuit, DriveKind::Differential), MotionMode::PurePursuit);
  const auto refused = [](MotionMode m, DriveKind d) {
    try {
      resolve_motion_mode(m, d);
    } catch (const Error& e) {
      return e.field() == "motion_mode";
    }
    return false;
  };
  EXPECT_TRUE(refused(MotionMode::Holonomic, DriveKind::Differential));
  EXPECT_TRUE(refused(MotionMode::Holonomic, DriveKind::Ackermann));
  EXPECT_TRUE(refused(MotionMode::TurnThenDrive, DriveKind::Ackermann));
  // The constructor resolves too.
  RobotConfig diff;
  diff.drive = DriveKind::Differential;
  EXPECT_THROW(PathFollower(mode_config(MotionMode::Holonomic), diff), Error);
  RobotConfig ackermann;
  ackermann.drive = DriveKind::Ackermann;
  const PathFollower pp(PathFollowerConfig{}, ackermann);
  EXPECT_EQ(pp.mode(), MotionMode::PurePursuit);
  EXPECT_NEAR(pp.min_turning_radius_m(), 0.4 / std::tan(0.5), 1e-12);
  EXPECT_EQ(PathFollower(PathFollowerConfig{}, diff).min_turning_radius_m(), 0.0);
}

TEST(PathFollower, BadConfigurationNamesTheField) {
  struct Case {
    const char* field;
    void (*spoil)(PathFollowerConfig&);
  };
  const Case cases[] = {
      {"follower.cruise_speed_mps", [](PathFollowerConfig& c) { c.cruise_speed_mps = 0.0; }},
      {"follower.cruise_speed_mps", [](PathFollowerConfig& c) { c.cruise_speed_mps = std::nan(""); }},
      {"follower.min_speed_mps", [](PathFollowerConfig& c) { c.min_speed_mps = -0.1; }},
      {"follower.min_speed_mps", [](PathFollowerConfig& c) { c.min_speed_mps = 0.5; }},
      {"follower.look_ahead_m", [](PathFollowerConfig& c) { c.look_ahead_m = 0.0; }},
      {"follower.pursuit_look_ahead_m", [](PathFollowerConfig& c) { c.pursuit_look_ahead_m = -1.0; }},
      {"follower.heading_gain", [](PathFollowerConfig& c) { c.heading_gain = 0.0; }},
      {"follower.max_yaw_rate_radps", [](PathFollowerConfig& c) { c.max_yaw_rate_radps = INFINITY; }},
      {"follower.turn_tolerance_rad", [](PathFollowerConfig& c) { c.turn_tolerance_rad = 4.0; }},
      {"follower.vertex_tolerance_m", [](PathFollowerConfig& c) { c.vertex_tolerance_m = 0.0; }},
      {"follower.vertex_tolerance_m", [](PathFollowerConfig& c) { c.vertex_tolerance_m = 0.06; }},
      {"follower.goal_tolerance_m", [](PathFollowerConfig& c) { c.goal_tolerance_m = 0.0; }},
      {"follower.slow_down_distance_m", [](PathFollowerConfig& c) { c.slow_down_distance_m = 0.0; }},
      {"follower.mode", [](PathFollowerConfig& c) { c.mode = static_cast<MotionMode>(9); }},
  };
  EXPECT_NO_THROW(PathFollowerConfig{}.validate());
  for (const Case& k : cases) {
    PathFollowerConfig c;
    k.spoil(c);
    try {
      PathFollower f(c, RobotConfig{});
      ADD_FAILURE() << k.field << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), k.field);
    }
  }
  RobotConfig bad_robot;
  bad_robot.max_steer_rad = 0.0;
  EXPECT_THROW(PathFollower(PathFollowerConfig{}, bad_robot), Error);
}

TEST(PathFollower, BadPathNamesTheField) {
  PathFollower f(PathFollowerConfig{}, RobotConfig{});
  const auto field_of = [&](std::vector<Vec2> path) -> std::string {
    try {
      f.set_path(path);
    } catch (const Error& e) {
      return e.field();
    }
    return "";
  };
  EXPECT_EQ(field_of({}), "path");
  EXPECT_EQ(field_of({{0.0, 0.0}, {std::nan(""), 1.0}}), "path");
  EXPECT_EQ(field_of({{0.0, 0.0}, {1.0, 0.0}}), "");
  // No path: no motion.
  f.clear();
  const FollowOutput out = f.compute(Pose2());
  EXPECT_EQ(out.status, FollowStatus::NoPath);
  EXPECT_EQ(out.command.vx, 0.0);
  EXPECT_EQ(out.command.wz, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Open loop: one compute() against closed forms.

TEST(PathFollower, PurePursuitCurvatureIsTwoYOverLSquaredClampedToTheTurningRadius) {
  // Straight path along +x; the robot at (0, -y) heading +x. The look-ahead point is L = 0.6 along
  // the path from the projection (0, 0), i.e. (0.6, 0): at distance d = sqrt(0.36 + y^2) and
  // lateral offset y in the robot's frame, so kappa = 2 sin(alpha) / d = 2 y / d^2.
  const std::vector<Vec2> path = {{0.0, 0.0}, {5.0, 0.0}};
  RobotConfig ackermann;
  ackermann.drive = DriveKind::Ackermann;
  const double kappa_max = std::tan(ackermann.max_steer_rad) / (2.0 * ackermann.half_wheelbase_m);
  for (const double y : {0.0, 0.1, 0.2, 0.3, 0.4, -0.25, -0.5}) {
    const double expect = 2.0 * y / (0.36 + y * y);
    RobotConfig diff;
    diff.drive = DriveKind::Differential;
    PathFollower free_turning(mode_config(MotionMode::PurePursuit), diff);
    free_turning.set_path(path);
    const FollowOutput a = free_turning.compute(Pose2(0.0, -y, 0.0));
    ASSERT_EQ(a.status, FollowStatus::Driving);
    EXPECT_NEAR(a.command.wz / a.command.vx, expect, 1e-12) << y;
    EXPECT_NEAR(a.cross_track_m, -y, 1e-12);
    EXPECT_NEAR(a.distance_remaining_m, 5.0, 1e-12);
    EXPECT_LE(std::abs(a.command.wz), PathFollowerConfig{}.max_yaw_rate_radps + 1e-12);

    PathFollower car(PathFollowerConfig{}, ackermann);
    car.set_path(path);
    const FollowOutput b = car.compute(Pose2(0.0, -y, 0.0));
    EXPECT_NEAR(b.command.wz / b.command.vx, std::clamp(expect, -kappa_max, kappa_max), 1e-12) << y;
    EXPECT_GT(b.command.vx, 0.0);
  }
}

TEST(PathFollower, ProgressAndLookAheadOnAStraightSegment) {
  const std::vector<Vec2> path = {{1.0, 1.0}, {1.0, 4.0}, {3.0, 4.0}};  // north 3 m, then east 2 m
  for (const MotionMode mode : {MotionMode::TurnThenDrive, MotionMode::Holonomic}) {
    PathFollower f(mode_config(mode), RobotConfig{});
    f.set_path(path);
    // 1.2 m up the first segment, 0.05 m to its right, already facing north.
    const FollowOutput out = f.compute(Pose2(1.05, 2.2, 0.5 * kPi));
    EXPECT_EQ(out.status, FollowStatus::Driving);
    EXPECT_EQ(out.segment, 0u);
    EXPECT_NEAR(out.distance_remaining_m, 1.8 + 2.0, 1e-12);
    EXPECT_NEAR(out.cross_track_m, -0.05, 1e-12);
    EXPECT_NEAR(out.look_ahead.x(), 1.0, 1e-12);
    EXPECT_NEAR(out.look_ahead.y(), 2.2 + f.config().look_ahead_m, 1e-12);
    // Far from the corner: cruise speed toward the look-ahead point (0.3 ahead, 0.05 to the left).
    const double bearing = std::atan2(0.05, 0.3);
    if (mode == MotionMode::TurnThenDrive) {
      EXPECT_NEAR(out.command.vx, 0.2 * std::cos(bearing), 1e-12);
      EXPECT_NEAR(out.command.wz, 2.0 * bearing, 1e-12);
    } else {
      EXPECT_NEAR(std::hypot(out.command.vx, out.command.vy), 0.2, 1e-12);
      EXPECT_NEAR(std::atan2(out.command.vy, out.command.vx), bearing, 1e-12);
      EXPECT_EQ(out.command.wz, 0.0);  // heading captured here, nothing to correct
    }
  }
}

TEST(PathFollower, TurnThenDriveTurnsInPlaceFirst) {
  PathFollower f(mode_config(MotionMode::TurnThenDrive), RobotConfig{});
  f.set_path(std::vector<Vec2>{{0.0, 0.0}, {0.0, 2.0}});
  const FollowOutput out = f.compute(Pose2(0.0, 0.0, 0.0));  // facing east, path goes north
  EXPECT_EQ(out.status, FollowStatus::Turning);
  EXPECT_EQ(out.command.vx, 0.0);
  EXPECT_EQ(out.command.vy, 0.0);
  EXPECT_NEAR(out.command.wz, 1.0, 1e-12);  // 2 * pi/2 clamped to max_yaw_rate
  // Within the tolerance it drives.
  EXPECT_EQ(f.compute(Pose2(0.0, 0.0, 0.5 * kPi - 0.04)).status, FollowStatus::Driving);
}

// ---------------------------------------------------------------------------------------------
// Closed loop on the flat floor.

struct ModeCase {
  const char* name;
  DriveKind drive;
  MotionMode mode;
};
const ModeCase kModeCases[] = {
    {"mecanum turn_then_drive", DriveKind::Mecanum, MotionMode::TurnThenDrive},
    {"differential turn_then_drive", DriveKind::Differential, MotionMode::TurnThenDrive},
    {"mecanum holonomic", DriveKind::Mecanum, MotionMode::Holonomic},
};

TEST(PathFollower, FollowsPolylinesInBothModes) {
  for (const ModeCase& mc : kModeCases)
    for (const bool lag : {false, true})
      for (const auto* path : {&kLShape, &kZigzag}) {
        const std::string what = std::string(mc.name) + (lag ? " lag" : " no lag") +
                                 (path == &kLShape ? " L" : " zigzag");
        // Starting 0.3 rad off the first leg: turn_then_drive turns first, holonomic keeps 0.3 (so
        // its base_link velocities are not the world's).
        const FollowRun r = follow(mode_config(mc.mode), vehicle_config(mc.drive, lag), *path, Pose2(0.0, 0.0, 0.3));
        report(what.c_str(), r);
        EXPECT_EQ(r.status, FollowStatus::Arrived) << what;
        EXPECT_LE(r.goal_distance_m, 0.05) << what;
        EXPECT_LE(r.max_deviation_m, 0.015) << what;
        if (mc.mode == MotionMode::Holonomic) {
          EXPECT_LE(r.max_yaw_drift_rad, 0.01) << what;
        }
      }
}

TEST(PathFollower, HolonomicOffsetDecaysExponentiallyWithDistance) {
  // Holonomic toward a look-ahead point L ahead on the line: the velocity is parallel to
  // (L, -e), so de/dx = -e / L exactly and e(x) = e0 exp(-x / L), whatever the speed profile.
  // Without lag, and with the heading 1 rad off the path to exercise the base_link conversion.
  const std::vector<Vec2> path = {{0.0, 0.0}, {4.0, 0.0}};
  const VehicleConfig vc = vehicle_config(DriveKind::Mecanum, false);
  const World world;
  const double e0 = 0.1;
  Vehicle vehicle(world, vc, Pose2(0.0, e0, 1.0), Rng(1));
  PathFollower f(mode_config(MotionMode::Holonomic), vc.robot);
  f.set_path(path);
  std::vector<VehicleEvent> events;
  double worst = 0.0;
  while (vehicle.state().pose.position.x() < 2.0) {
    vehicle.step(f.compute(vehicle.state().pose.to_pose2()).command, kDt, events);
    const Pose2 p = vehicle.state().pose.to_pose2();
    const double expect = e0 * std::exp(-p.x / f.config().look_ahead_m);
    worst = std::max(worst, std::abs(p.y - expect) / e0);
    ASSERT_NEAR(p.yaw, 1.0, 1e-9);
  }
  std::printf("holonomic offset vs e0 exp(-x/L): worst error %.2e of e0\n", worst);
  EXPECT_LE(worst, 0.005);
}

TEST(PathFollower, TurnThenDriveOffsetSettlesLikeTheLinearModel) {
  // Linearised, without lag: e' = v psi, psi' = -k (psi + e / L): a second-order system with
  // w_n = sqrt(k v / L) = 1.15 rad/s and damping k / (2 w_n) = 0.87, whose overshoot is
  // exp(-pi z / sqrt(1 - z^2)) = 0.4 % of the initial offset; after 10 s it is below 1e-4 of it.
  const std::vector<Vec2> path = {{0.0, 0.0}, {4.0, 0.0}};
  const VehicleConfig vc = vehicle_config(DriveKind::Differential, false);
  const World world;
  const double e0 = 0.1;
  Vehicle vehicle(world, vc, Pose2(0.0, e0, 0.0), Rng(1));
  PathFollower f(mode_config(MotionMode::TurnThenDrive), vc.robot);
  f.set_path(path);
  std::vector<VehicleEvent> events;
  double undershoot = 0.0;
  for (int i = 0; i < 1000; ++i) {  // 10 s, 2 m at cruise speed
    vehicle.step(f.compute(vehicle.state().pose.to_pose2()).command, kDt, events);
    undershoot = std::min(undershoot, vehicle.state().pose.position.y());
  }
  std::printf("turn_then_drive offset: undershoot %.2e of e0, after 10 s %.2e of e0\n", -undershoot / e0,
              vehicle.state().pose.position.y() / e0);
  EXPECT_LE(-undershoot, 0.01 * e0);
  EXPECT_LE(std::abs(vehicle.state().pose.position.y()), 1e-3 * e0);
}

TEST(PathFollower, TurnThenDriveStandsStillWhileTurning) {
  // Zigzag from heading 0: a turn at the start (the first leg heads 38.7 deg) and at each of the
  // three inner vertices.
  for (const DriveKind drive : {DriveKind::Mecanum, DriveKind::Differential})
    for (const bool lag : {false, true}) {
      const FollowRun r = follow(mode_config(MotionMode::TurnThenDrive), vehicle_config(drive, lag), kZigzag,
                                 Pose2(0.0, 0.0, 0.0));
      ASSERT_EQ(r.status, FollowStatus::Arrived);
      int phases = 0;
      double max_speed = 0.0, max_speed_settled = 0.0, max_shift = 0.0;
      std::size_t phase_start = 0;
      for (std::size_t i = 0; i < r.outs.size(); ++i) {
        if (r.outs[i].status != FollowStatus::Turning) continue;
        EXPECT_EQ(r.outs[i].command.vx, 0.0);
        EXPECT_EQ(r.outs[i].command.vy, 0.0);
        if (i == 0 || r.outs[i - 1].status != FollowStatus::Turning) phase_start = i;
        const double speed = std::hypot(r.achieved[i].vx, r.achieved[i].vy);
        max_speed = std::max(max_speed, speed);
        if ((i - phase_start) * kDt >= 0.5) max_speed_settled = std::max(max_speed_settled, speed);
        if (i == phase_start) {
          ++phases;
          // Where the turn began (the pose before this step) to where it ends.
          const Vec2 from = i == 0 ? Vec2(0.0, 0.0) : r.poses[i - 1].translation();
          std::size_t end = i;
          while (end + 1 < r.outs.size() && r.outs[end + 1].status == FollowStatus::Turning) ++end;
          max_shift = std::max(max_shift, (r.poses[end].translation() - from).norm());
          // The turn ends facing the segment it turned to (the next step drives).
          const std::size_t seg = r.outs[end].segment;
          const Vec2 dir = kZigzag[seg + 1] - kZigzag[seg];
          const double err = std::abs(angle_diff(std::atan2(dir.y(), dir.x()), r.poses[end].yaw));
          EXPECT_LE(err, 0.06);
        }
      }
      EXPECT_EQ(phases, 4);
      // No lag: the wheels stop the instant the command does. With the default lag (0.1 s) the
      // drive still carries the slow approach speed into the turn, and it decays within 0.5 s.
      EXPECT_LE(max_speed, lag ? 0.03 : 1e-12) << drive_kind_name(drive);
      EXPECT_LE(max_speed_settled, lag ? 1e-3 : 1e-12) << drive_kind_name(drive);
      EXPECT_LE(max_shift, lag ? 0.005 : 1e-12) << drive_kind_name(drive);
      std::printf("%s %s: %d turns, max speed while turning %.4f m/s (%.2g after 0.5 s), max shift %.5f m\n",
                  drive_kind_name(drive), lag ? "lag" : "no lag", phases, max_speed, max_speed_settled, max_shift);
    }
}

TEST(PathFollower, AckermannPursuesPolylinesWithinItsTurningRadius) {
  for (const bool lag : {false, true})
    for (const auto* path : {&kGentle, &kTight}) {
      const VehicleConfig vc = vehicle_config(DriveKind::Ackermann, lag);
      const double kappa_max = std::tan(vc.robot.max_steer_rad) / (2.0 * vc.robot.half_wheelbase_m);
      const FollowRun r = follow(PathFollowerConfig{}, vc, *path, Pose2(0.0, 0.0, 0.0));
      const std::string what = std::string("ackermann pure_pursuit") + (lag ? " lag" : " no lag") +
                               (path == &kGentle ? " gentle" : " tight");
      report(what.c_str(), r);
      EXPECT_EQ(r.status, FollowStatus::Arrived) << what;
      EXPECT_LE(r.goal_distance_m, 0.05) << what;
      // The gentle path is followed closely; the tight one's corners are cut by about R_min.
      EXPECT_LE(r.max_deviation_m, path == &kGentle ? 0.08 : 0.20) << what;
      double max_cmd = 0.0, max_driven = 0.0;
      for (std::size_t i = 0; i < r.outs.size(); ++i) {
        const BodyTwist& c = r.outs[i].command;
        ASSERT_GT(c.vx, 0.0) << "an ackermann robot never turns in place";
        max_cmd = std::max(max_cmd, std::abs(c.wz / c.vx));
        // Curvature of the driven track: heading change over distance between poses.
        if (i > 0) {
          const double ds = (r.poses[i].translation() - r.poses[i - 1].translation()).norm();
          if (ds > 1e-4)
            max_driven = std::max(max_driven, std::abs(angle_diff(r.poses[i].yaw, r.poses[i - 1].yaw)) / ds);
        }
      }
      std::printf("  max commanded curvature %.4f, driven %.4f, 1/R_min %.4f\n", max_cmd, max_driven, kappa_max);
      EXPECT_LE(max_cmd, kappa_max + 1e-12) << what;
      EXPECT_LE(max_driven, kappa_max * (1.0 + 1e-6)) << what;
      // On the tight path the limit is what binds.
      if (path == &kTight) {
        EXPECT_NEAR(max_cmd, kappa_max, 1e-12) << what;
      }
    }
}

TEST(PathFollower, PurePursuitReportsAMissedGoalInsteadOfCircling) {
  RobotConfig ackermann;
  ackermann.drive = DriveKind::Ackermann;
  PathFollower f(PathFollowerConfig{}, ackermann);
  f.set_path(std::vector<Vec2>{{0.0, 0.0}, {1.0, 0.0}});
  EXPECT_EQ(f.compute(Pose2(1.0, 0.2, 0.0)).status, FollowStatus::Missed);  // past the end, 0.2 m off
  EXPECT_EQ(f.compute(Pose2(0.0, 0.0, 0.0)).status, FollowStatus::Missed);  // sticky until a new path
  f.set_path(std::vector<Vec2>{{0.0, 0.0}, {1.0, 0.0}});
  const FollowOutput near = f.compute(Pose2(1.0, 0.03, 0.0));
  EXPECT_EQ(near.status, FollowStatus::Arrived);
  EXPECT_EQ(near.command.vx, 0.0);
}

TEST(PathFollower, ReachesTheGoalWhenTheEndIsReachedOffToTheSide) {
  // Starting 0.3 m beside a 0.5 m path: the look-ahead cannot pull the robot onto the line before
  // the end, so the follower inserts a final approach from where it stands.
  for (const MotionMode mode : {MotionMode::TurnThenDrive, MotionMode::Holonomic}) {
    const std::vector<Vec2> path = {{0.0, 0.0}, {0.5, 0.0}};
    const VehicleConfig vc = vehicle_config(DriveKind::Mecanum, true);
    const World world;
    Vehicle vehicle(world, vc, Pose2(0.0, 0.3, 0.0), Rng(1));
    PathFollower f(mode_config(mode), vc.robot);
    f.set_path(path);
    std::vector<VehicleEvent> events;
    FollowStatus status = FollowStatus::NoPath;
    for (int i = 0; i < 6000 && status != FollowStatus::Arrived; ++i) {
      const FollowOutput out = f.compute(vehicle.state().pose.to_pose2());
      status = out.status;
      vehicle.step(out.command, kDt, events);
    }
    EXPECT_EQ(status, FollowStatus::Arrived) << motion_mode_name(mode);
    EXPECT_EQ(f.path().size(), 3u) << "a final-approach vertex was inserted";
    EXPECT_LE((vehicle.state().pose.to_pose2().translation() - path.back()).norm(), 0.05);
  }
}

TEST(PathFollower, SinglePointPathIsReachedFromWhereTheRobotIs) {
  for (const DriveKind drive : {DriveKind::Mecanum, DriveKind::Differential, DriveKind::Ackermann}) {
    const std::vector<Vec2> goal = {{1.5, 1.0}};
    const FollowRun r = follow(PathFollowerConfig{}, vehicle_config(drive, true), goal, Pose2(0.0, 0.0, 0.0));
    EXPECT_EQ(r.status, FollowStatus::Arrived) << drive_kind_name(drive);
    EXPECT_LE(r.goal_distance_m, 0.05) << drive_kind_name(drive);
  }
  // Already there: arrived at once.
  PathFollower f(PathFollowerConfig{}, RobotConfig{});
  f.set_path(std::vector<Vec2>{{1.0, 1.0}});
  EXPECT_EQ(f.compute(Pose2(1.01, 1.0, 2.0)).status, FollowStatus::Arrived);
}

TEST(PathFollower, RunsAreDeterministic) {
  for (const ModeCase& mc : kModeCases) {
    const FollowRun a = follow(mode_config(mc.mode), vehicle_config(mc.drive, true), kZigzag, Pose2(0.0, 0.0, 0.3));
    const FollowRun b = follow(mode_config(mc.mode), vehicle_config(mc.drive, true), kZigzag, Pose2(0.0, 0.0, 0.3));
    ASSERT_EQ(a.poses.size(), b.poses.size());
    for (std::size_t i = 0; i < a.poses.size(); ++i) {
      ASSERT_EQ(a.poses[i].x, b.poses[i].x);
      ASSERT_EQ(a.poses[i].y, b.poses[i].y);
      ASSERT_EQ(a.poses[i].yaw, b.poses[i].yaw);
    }
  }
}

}  // namespace
}  // namespace starnav
