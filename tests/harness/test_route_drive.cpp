// The route driver: legs planned on the world's map at the route's clearance, driven on the true
// pose without touching a wall, the run ended after the last lap; the kidnap carries the robot at
// least the asked distance and turns it by the asked angle; bad waypoints name their field.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/route_drive.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::read_text;
using test::scenario_path;

// indoor_slam.yaml's world and robot with a route along the south corridor and back.
std::string route_scenario(const std::string& waypoints, int laps) {
  std::string text = read_text(scenario_path("indoor_slam.yaml"));
  text.erase(text.find("commands:"));
  text.replace(text.find("  seed: 0"), 9, "  seed: 0\n  duration_s: 300.0");
  return text + "route:\n  waypoints_m: " + waypoints + "\n  speed_mps: 0.5\n  laps: " + std::to_string(laps) + "\n";
}

TEST(RouteDrive, DrivesTheLoopWithoutCollisionAndStopsAfterTheLastLap) {
  const ScenarioSpec spec = parse_scenario(route_scenario("[[1.75, 1.75], [10.0, 1.75]]", 2), scenario_path("route.yaml"));
  Simulation sim(spec);
  const auto drive = make_route_drive(sim);
  EXPECT_NEAR(drive->lap_length_m(), 2 * 8.25, 0.2);  // there and back along the corridor
  sim.run();
  EXPECT_EQ(drive->laps_done(), 2);
  EXPECT_LT(sim.time(), 300.0);  // stopped by the driver, not the clock
  EXPECT_EQ(sim.metrics().collisions, 0);
  EXPECT_NEAR(sim.metrics().distance_m, 2 * 2 * 8.25, 1.5);
}

TEST(RouteDrive, KidnapCarriesTheRobotAheadAndTurnsIt) {
  const ScenarioSpec spec = parse_scenario(route_scenario("[[1.75, 1.75], [20.0, 1.75]]", 1), scenario_path("route.yaml"));
  Simulation sim(spec);
  const auto drive = make_route_drive(sim);
  drive->kidnap_at(4.0, 5.0, kPi / 2);
  Pose2 before;
  sim.encoder_feed.subscribe(SampleStage::Record, [&](const EncoderSample& e) {
    if (e.t_s < 4.0) before = sim.vehicle().state().pose.to_pose2();
  });
  sim.run();
  ASSERT_GE(drive->kidnap_time(), 4.0);
  EXPECT_GE((drive->kidnap_pose().translation() - before.translation()).norm(), 5.0);
  EXPECT_NEAR(std::abs(wrap_angle(drive->kidnap_pose().yaw - before.yaw)), kPi / 2, 0.05);
  EXPECT_EQ(sim.metrics().collisions, 0);
}

TEST(RouteDrive, BlockedOrUnreachableWaypointsNameTheirField) {
  // (12, 8) lies inside the rooms' walls block; outside the map is refused too.
  for (const std::string wp : {"[[1.75, 1.75], [-5.0, 1.75]]", "[[1.75, 1.75], [0.02, 0.02]]"}) {
    const ScenarioSpec spec = parse_scenario(route_scenario(wp, 1), scenario_path("route.yaml"));
    Simulation sim(spec);
    try {
      make_route_drive(sim);
      ADD_FAILURE() << wp;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "route.waypoints_m[1]") << e.what();
    }
  }
  EXPECT_THROW(parse_scenario(route_scenario("[[1.75, 1.75]]", 1), "r.yaml"), Error);
}

}  // namespace
}  // namespace starnav
