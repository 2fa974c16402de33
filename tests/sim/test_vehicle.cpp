// The vehicle in a world: arc integration against the closed-form circle, attitude on a tilted
// plane against the plane's normal, never through a thin wall, steps and collisions refused, the
// paper's test-platform obstacles drivable, slide on steep slopes only, bumper contact,
// determinism by seed, and the cost of a step.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {
namespace {

// A plane z = a x + b y + c sampled on a grid (the terrain surface is exact for planes).
ElevationMap plane_map(double size, double res, double a, double b, double c, double x0, double y0) {
  GridGeometry g;
  g.width = g.height = static_cast<int>(std::lround(size / res));
  g.resolution = res;
  g.origin = Pose2(x0, y0, 0.0);
  ElevationMap m(g);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Vec2 p = g.cell_center(ix, iy);
      m.set_height(ix, iy, a * p.x() + b * p.y() + c);
    }
  return m;
}

World world_with(std::vector<Obstacle> obstacles, std::optional<ElevationMap> terrain = std::nullopt) {
  WorldDescription d;
  d.obstacles = std::move(obstacles);
  d.terrain = std::move(terrain);
  return World(d);
}

Obstacle box_obstacle(const std::string& name, const Vec3& centre, const Vec3& size, double yaw = 0.0) {
  Obstacle o;
  o.name = name;
  Box b;
  b.center = centre;
  b.size = size;
  b.yaw = yaw;
  o.parts.emplace_back(b);
  return o;
}

VehicleConfig quick_config() {
  VehicleConfig c;
  c.robot.actuator_lag_s = 0.0;
  c.robot.max_wheel_accel_radps2 = 1e9;
  return c;
}

TEST(Vehicle, ConstantTwistDrivesTheClosedFormCircle) {
  const World world;  // no terrain: the floor z = 0
  for (const DriveKind kind : {DriveKind::Mecanum, DriveKind::Differential, DriveKind::Ackermann}) {
    VehicleConfig c = quick_config();
    c.robot.drive = kind;
    c.robot.max_steer_rate_radps = 1e3;
    Vehicle v(world, c, Pose2(1.0, 2.0, 0.3), Rng(1));
    std::vector<VehicleEvent> ev;
    const BodyTwist cmd{0.4, kind == DriveKind::Mecanum ? 0.1 : 0.0, 0.5};
    const double dt = 0.01;
    v.step(cmd, dt, ev);  // no lag, no acceleration limit: the command holds from the first step on
    EXPECT_NEAR(v.state().twist.vx, cmd.vx, 1e-12);
    EXPECT_NEAR(v.state().twist.wz, cmd.wz, 1e-12);
    EXPECT_NEAR(v.state().pose.position.x(), 1.0 + cmd.vx * std::cos(0.3) * dt - cmd.vy * std::sin(0.3) * dt, 1e-4);
    const Pose2 p0 = v.state().pose.to_pose2();
    for (int i = 1; i <= 1500; ++i) {
      v.step(cmd, dt, ev);
      const double t = i * dt, th = cmd.wz * t;
      // Closed form: body velocity (vx, vy) turning at wz from p0.
      const double bx = (cmd.vx * std::sin(th) - cmd.vy * (1.0 - std::cos(th))) / cmd.wz;
      const double by = (cmd.vx * (1.0 - std::cos(th)) + cmd.vy * std::sin(th)) / cmd.wz;
      const Vec2 expect = p0.transform(Vec2(bx, by));
      const Pose2 p = v.state().pose.to_pose2();
      ASSERT_NEAR(p.x, expect.x(), 1e-9) << i;
      ASSERT_NEAR(p.y, expect.y(), 1e-9) << i;
      ASSERT_NEAR(angle_diff(p.yaw, p0.yaw + th), 0.0, 1e-9) << i;
      ASSERT_NEAR(v.state().pose.position.z(), 0.0, 1e-15);
    }
    EXPECT_TRUE(ev.empty());
    EXPECT_NEAR(v.state().twist.vx, cmd.vx, 1e-12);
    EXPECT_NEAR(v.state().twist.wz, cmd.wz, 1e-12);
  }
}

TEST(Vehicle, AttitudeOnATiltedPlaneIsThePlane) {
  const double a = 0.15, b = -0.1, c0 = 0.7;
  const World world = world_with({}, plane_map(10.0, 0.1, a, b, c0, -5.0, -5.0));
  VehicleConfig c = quick_config();
  for (const auto& [kind, yaw] : {std::pair{DriveKind::Mecanum, 0.0}, std::pair{DriveKind::Mecanum, 0.7},
                                  std::pair{DriveKind::Mecanum, 2.0}, std::pair{DriveKind::Mecanum, -2.8},
                                  std::pair{DriveKind::Differential, 1.1}, std::pair{DriveKind::Ackermann, -0.4}}) {
    c.robot.drive = kind;
    Vehicle v(world, c, Pose2(0.5, -0.3, yaw), Rng(1));
    std::vector<VehicleEvent> ev;
    for (int i = 0; i < 50; ++i) {
      v.step({0.3, 0.1, 0.2}, 0.02, ev);
      const Pose3& p = v.state().pose;
      EXPECT_NEAR(p.position.z(), a * p.position.x() + b * p.position.y() + c0, 1e-9);
      const Eigen::Matrix3d r = p.rotation();
      // z axis along the plane's normal, x axis in the plane along the heading.
      const Vec3 n = Vec3(-a, -b, 1.0).normalized();
      EXPECT_NEAR((r.col(2) - n).norm(), 0.0, 1e-9);
      EXPECT_NEAR(r.col(0).dot(n), 0.0, 1e-9);
      const double heading = v.state().pose.to_pose2().yaw;
      EXPECT_NEAR(std::atan2(r(1, 0), r(0, 0)), heading, 1e-9);
    }
    EXPECT_TRUE(ev.empty());
  }
}

TEST(Vehicle, NeverPassesThroughAThinWall) {
  // A 0.05 m thick wall across the path and a 0.02 m pole; the robot drives at full speed with
  // small and very large time steps.
  for (const double dt : {0.01, 0.05, 0.5}) {
    for (const bool pole : {false, true}) {
      const World world = pole ? world_with({[] {
        Obstacle o;
        o.name = "pole";
        o.parts.emplace_back(Cylinder{Vec3(2.0, 0.05, 0.0), 0.01, 1.0});
        return o;
      }()})
                               : world_with({box_obstacle("wall", Vec3(2.0, 0.0, 0.5), Vec3(0.05, 3.0, 1.0))});
      VehicleConfig c;
      c.robot.max_wheel_accel_radps2 = 100.0;
      Vehicle v(world, c, Pose2(0.0, 0.0, 0.0), Rng(1));
      std::vector<VehicleEvent> ev;
      const double face = pole ? 2.0 - 0.01 : 2.0 - 0.025;
      for (int i = 0; i < static_cast<int>(6.0 / dt); ++i) {
        v.step({2.0, 0.0, 0.0}, dt, ev);
        ASSERT_LE(v.state().pose.position.x() + 0.5 * c.robot.body_length_m, face + 1e-9) << dt;
      }
      ASSERT_FALSE(ev.empty());
      EXPECT_EQ(ev.front().kind, "collision");
      EXPECT_EQ(ev.front().detail, pole ? "pole" : "wall");
      EXPECT_NEAR(ev.front().where.x(), face, 0.02);
      EXPECT_EQ(ev.size(), 1u);  // one contact, reported once while it lasts
      EXPECT_TRUE(v.blocked());
      EXPECT_TRUE(v.bumper_contact());
      // Stopped within a few millimetres of the obstacle.
      EXPECT_GT(v.state().pose.position.x() + 0.5 * c.robot.body_length_m, face - 0.005) << dt;
      // Backing away frees the bumper.
      for (int i = 0; i < 20; ++i) v.step({-0.3, 0.0, 0.0}, 0.05, ev);
      EXPECT_FALSE(v.bumper_contact());
      EXPECT_FALSE(v.blocked());
    }
  }
}

TEST(Vehicle, AckermannBodyIsBetweenItsAxlesAndItCannotTurnInPlace) {
  const World world = world_with({box_obstacle("wall", Vec3(2.0, 0.0, 0.5), Vec3(0.05, 3.0, 1.0))});
  VehicleConfig c;
  c.robot.drive = DriveKind::Ackermann;
  Vehicle v(world, c, Pose2(0.0, 0.0, 0.0), Rng(1));
  EXPECT_EQ(v.model().body_center(), Vec2(c.robot.half_wheelbase_m, 0.0));
  std::vector<VehicleEvent> ev;
  for (int i = 0; i < 100; ++i) v.step({0.0, 0.0, 1.0}, 0.01, ev);
  EXPECT_EQ(v.state().pose.position.x(), 0.0);
  EXPECT_EQ(v.state().pose.to_pose2().yaw, 0.0);
  EXPECT_GT(v.state().wheel_angle_rad[1], 0.0);  // steered toward the turn
  v = Vehicle(world, c, Pose2(0.0, 0.0, 0.0), Rng(1));  // wheels straight again
  for (int i = 0; i < 1000; ++i) v.step({0.5, 0.0, 0.0}, 0.01, ev);
  ASSERT_FALSE(ev.empty());
  EXPECT_EQ(ev.front().kind, "collision");
  // Front face = base_link + L2 + length / 2.
  const double front = v.state().pose.position.x() + c.robot.half_wheelbase_m + 0.5 * c.robot.body_length_m;
  EXPECT_LE(front, 2.0 - 0.025 + 1e-9);
  EXPECT_GT(front, 2.0 - 0.025 - 0.005);
  EXPECT_TRUE(v.bumper_contact());
}

TEST(Vehicle, TallBoxIsACollisionAndAHighStepIsAStep) {
  {
    const World world = world_with({box_obstacle("tall", Vec3(1.5, 0.0, 0.25), Vec3(0.4, 0.4, 0.5))});
    Vehicle v(world, VehicleConfig{}, Pose2(0.0, 0.0, 0.0), Rng(1));
    std::vector<VehicleEvent> ev;
    for (int i = 0; i < 500; ++i) v.step({0.3, 0.0, 0.0}, 0.01, ev);
    ASSERT_FALSE(ev.empty());
    EXPECT_EQ(ev.front().kind, "collision");
    EXPECT_LT(v.state().pose.position.x(), 1.3 - 0.275 + 1e-9);
  }
  {
    // High body: a 0.12 m ledge passes under it but is too tall for the wheels.
    const World world = world_with({box_obstacle("ledge", Vec3(2.0, 0.0, 0.06), Vec3(1.0, 2.0, 0.12))});
    VehicleConfig c;
    c.robot.ground_clearance_m = 0.3;
    Vehicle v(world, c, Pose2(0.0, 0.0, 0.0), Rng(1));
    std::vector<VehicleEvent> ev;
    for (int i = 0; i < 500; ++i) v.step({0.3, 0.0, 0.0}, 0.01, ev);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev.front().kind, "step");
    EXPECT_NEAR(ev.front().where.x(), 1.5, 0.011);  // the front wheels at the ledge
    EXPECT_LE(v.state().pose.position.x() + c.robot.half_wheelbase_m, 1.5 + 1e-9);
    EXPECT_FALSE(v.bumper_contact());  // the ledge is below the body
  }
}

TEST(Vehicle, TestPlatformObstaclesAreDrivable) {
  // Each of the paper's composites with its defaults, crossed along its own x axis at 0.2 m/s.
  SlopeStep ss;
  ss.position = Vec3(2.0, 0.0, 0.0);
  UndulatingGround ug;
  ug.position = Vec3(2.0, 0.0, 0.0);
  RoundConvex rc;
  rc.position = Vec3(2.0, 0.0, 0.0);
  Gravel gr;
  gr.position = Vec3(2.0, 0.0, 0.0);
  gr.seed = 3;
  const World flat = world_with({}, plane_map(8.0, 0.05, 0.0, 0.0, 0.0, -2.0, -4.0));
  gr.follow_terrain = false;
  const std::vector<Obstacle> composites{make_slope_step(ss), make_undulating_ground(ug), make_round_convex(rc),
                                         make_gravel(gr)};
  for (const Obstacle& o : composites) {
    const World world = world_with({o}, plane_map(8.0, 0.05, 0.0, 0.0, 0.0, -2.0, -4.0));
    // Straight across, off-centre, and slightly skewed (staying on the composite's width).
    for (const auto& [y0, yaw_off] : {std::pair{0.0, 0.0}, std::pair{0.3, 0.0}, std::pair{-0.2, 0.05}}) {
      Vehicle v(world, VehicleConfig{}, Pose2(-0.5, y0, yaw_off), Rng(1));
      std::vector<VehicleEvent> ev;
      double z_max = 0.0, tilt_max = 0.0;
      for (int i = 0; i < 4000 && v.state().pose.position.x() < 4.5; ++i) {
        // Hold the heading: a proportional yaw controller back to yaw_off keeps the track straight.
        const double yaw = v.state().pose.to_pose2().yaw;
        v.step({0.2, 0.0, -1.0 * angle_diff(yaw, yaw_off)}, 0.01, ev);
        z_max = std::max(z_max, v.state().pose.position.z());
        const Vec3 rpy = v.state().pose.rpy();
        tilt_max = std::max({tilt_max, std::abs(rpy.x()), std::abs(rpy.y())});
      }
      EXPECT_TRUE(ev.empty()) << o.name << " y " << y0 << " yaw " << yaw_off << ": "
                              << (ev.empty() ? "" : ev.front().kind + " " + ev.front().detail + " at " +
                                                        std::to_string(ev.front().where.x()) + ", " +
                                                        std::to_string(ev.front().where.y()) + " t " +
                                                        std::to_string(ev.front().t_s));
      EXPECT_GT(v.state().pose.position.x(), 4.4) << o.name;
      EXPECT_GT(z_max, o.name == "gravel" ? 0.004 : 0.03) << o.name;  // it really drove over something
      EXPECT_LT(tilt_max, 16.0 * kPi / 180.0) << o.name;
    }
  }
  (void)flat;
}

TEST(Vehicle, SlidesDownASteepSlopeOnlyAndAsCoulombSays) {
  const double dt = 0.01;
  for (const double slope : {0.3, 0.8}) {  // tan(slope); friction 0.6
    const World world = world_with({}, plane_map(30.0, 0.2, slope, 0.0, 0.0, -15.0, -15.0));
    VehicleConfig c;
    c.friction = 0.6;
    Vehicle v(world, c, Pose2(0.0, 0.0, 1.0), Rng(1));
    std::vector<VehicleEvent> ev;
    const int steps = 100;
    for (int i = 0; i < steps; ++i) v.step({}, dt, ev);
    const double x = v.state().pose.position.x(), y = v.state().pose.position.y();
    if (slope < c.friction) {
      EXPECT_EQ(x, 0.0);
      EXPECT_EQ(y, 0.0);
      EXPECT_TRUE(ev.empty());
    } else {
      // Horizontal acceleration g (sin th - mu cos th) cos th downhill (-x); after n steps of the
      // explicit update the drift is a n dt and the distance a dt^2 n (n + 1) / 2 (velocity
      // updated before the move).
      const double th = std::atan(slope);
      const double acc = 9.81 * (std::sin(th) - c.friction * std::cos(th)) * std::cos(th);
      EXPECT_NEAR(x, -acc * dt * dt * steps * (steps + 1) / 2.0, 1e-9);
      EXPECT_NEAR(y, 0.0, 1e-12);
      ASSERT_EQ(ev.size(), 1u);
      EXPECT_EQ(ev.front().kind, "slide");
      EXPECT_NEAR(v.slide_velocity().x(), -acc * dt * steps, 1e-9);
    }
  }
}

TEST(Vehicle, BumperSeesOnlyTheFront) {
  const World world = world_with({box_obstacle("behind", Vec3(-0.8, 0.0, 0.5), Vec3(0.5, 2.0, 1.0)),
                                  box_obstacle("ahead", Vec3(1.0, 0.0, 0.5), Vec3(0.5, 2.0, 1.0))});
  // Rear face 0.005 m from "behind" (face at x = -0.55), front face 0.745 m from "ahead" (0.75).
  Vehicle v(world, VehicleConfig{}, Pose2(-0.55 + 0.005 + 0.275, 0.0, 0.0), Rng(1));
  std::vector<VehicleEvent> ev;
  v.step({}, 0.01, ev);
  EXPECT_FALSE(v.bumper_contact());
  // Drive forward until touching: contact comes within the bumper range (0.01 m) of the front face.
  bool seen = false;
  for (int i = 0; i < 2000 && !seen; ++i) {
    v.step({0.1, 0.0, 0.0}, 0.01, ev);
    const double gap = 0.75 - (v.state().pose.position.x() + 0.275);
    if (v.bumper_contact()) {
      seen = true;
      EXPECT_LE(gap, 0.01 + 1e-9);
    } else {
      EXPECT_GT(gap, 0.01 - 1e-3);
    }
  }
  EXPECT_TRUE(seen);
}

TEST(Vehicle, SameSeedSameTrajectoryBitForBit) {
  Gravel gr;
  gr.position = Vec3(1.5, 0.0, 0.0);
  gr.follow_terrain = false;
  const World world = world_with({make_gravel(gr)}, plane_map(6.0, 0.05, 0.02, 0.01, 0.0, -1.0, -3.0));
  VehicleConfig c;
  c.rough_slip_sigma = 0.2;
  auto run = [&](std::uint64_t seed) {
    Vehicle v(world, c, Pose2(0.0, 0.0, 0.0), Rng(seed));
    std::vector<VehicleEvent> ev;
    std::vector<double> out;
    for (int i = 0; i < 1500; ++i) {
      v.step({0.25, 0.05, 0.1 * std::sin(0.01 * i)}, 0.01, ev);
      const auto& p = v.state().pose;
      out.insert(out.end(), {p.position.x(), p.position.y(), p.position.z(), p.orientation.w(), p.orientation.x()});
    }
    return out;
  };
  const auto a = run(4), b = run(4), d = run(5);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << i;  // bit for bit
  EXPECT_NE(a, d);  // the slip draws matter on gravel

  // On a plane the contacts fit it exactly (no roughness): slip on or off, the same path.
  const World plane = world_with({}, plane_map(6.0, 0.05, 0.02, 0.01, 0.0, -1.0, -3.0));
  auto run_plane = [&](double sigma) {
    VehicleConfig pc;
    pc.rough_slip_sigma = sigma;
    Vehicle v(plane, pc, Pose2(0.0, 0.0, 0.0), Rng(4));
    std::vector<VehicleEvent> ev;
    for (int i = 0; i < 300; ++i) v.step({0.25, 0.05, 0.1}, 0.01, ev);
    return v.state().pose.position;
  };
  EXPECT_LT((run_plane(0.2) - run_plane(0.0)).norm(), 1e-9);
}

TEST(Vehicle, OffTheTerrainEdgeStops) {
  const World world = world_with({}, plane_map(2.0, 0.1, 0.0, 0.0, 0.0, -1.0, -1.0));
  Vehicle v(world, VehicleConfig{}, Pose2(0.0, 0.0, 0.0), Rng(1));
  std::vector<VehicleEvent> ev;
  for (int i = 0; i < 500; ++i) v.step({0.3, 0.0, 0.0}, 0.01, ev);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev.front().kind, "off_terrain");
  EXPECT_LE(v.state().pose.position.x() + 0.2, 1.0 + 1e-9);
  EXPECT_GT(v.state().pose.position.x() + 0.2, 1.0 - 0.011);
  EXPECT_THROW(Vehicle(world, VehicleConfig{}, Pose2(5.0, 0.0, 0.0), Rng(1)), Error);
}

TEST(Vehicle, WheelAnglesIntegrateTheWheelSpeeds) {
  const World world;
  VehicleConfig c;
  Vehicle v(world, c, Pose2(), Rng(1));
  std::vector<VehicleEvent> ev;
  for (int i = 0; i < 300; ++i) v.step({0.2, 0.0, 0.0}, 0.01, ev);
  // Straight motion: every wheel turned by distance / r.
  const double dist = v.state().pose.position.x();
  for (const double a : v.state().wheel_angle_rad) EXPECT_NEAR(a, dist / c.robot.wheel_radius_m, 1e-9);
}

TEST(Vehicle, BadConfigurationNamesTheField) {
  const World world;
  VehicleConfig c;
  c.friction = -0.1;
  try {
    Vehicle v(world, c, Pose2(), Rng(1));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "vehicle.friction");
  }
  Vehicle v(world, VehicleConfig{}, Pose2(), Rng(1));
  std::vector<VehicleEvent> ev;
  EXPECT_THROW(v.step({}, 0.0, ev), Error);
}

// Driving over the test platform's slope and step and a gravel field: no collision, step or slide
// event, and the robot arrives (how long a step takes is bench_vehicle.cpp's, not a test's).
TEST(Vehicle, DrivesOverTheTestPlatformWithoutEvents) {
  SlopeStep ss;
  ss.position = Vec3(1.5, 0.0, 0.0);
  Gravel gr;
  gr.position = Vec3(4.0, 0.0, 0.0);
  gr.follow_terrain = false;
  const World world = world_with({make_slope_step(ss), make_gravel(gr)}, plane_map(10.0, 0.05, 0.0, 0.0, 0.0, -1.0, -5.0));
  Vehicle v(world, VehicleConfig{}, Pose2(0.0, 0.0, 0.0), Rng(1));
  std::vector<VehicleEvent> ev;
  for (int i = 0; i < 3000; ++i) v.step({0.2, 0.0, 0.0}, 0.01, ev);
  EXPECT_TRUE(ev.empty());
  EXPECT_NEAR(v.state().pose.position.x(), 6.0, 0.05);
}

}  // namespace
}  // namespace starnav
