// Teleport events (the kidnapped robot): the robot is where the event says from its time on, its
// wheels (hence encoders) do not turn, the jump is not driven distance, and a bad event is one
// error naming its field.
#include <gtest/gtest.h>

#include "starnav/core/error.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {
namespace {

const std::string kTeleport =
    "name: teleport\n"                                                      // 1
    "world:\n"                                                              // 2
    "  obstacles:\n"                                                        // 3
    "    - {name: crate, kind: box, position_m: [5, 5], size_m: [0.1, 2, 2]}\n"  // 4: a wall
    "robot:\n"                                                              // 5
    "  start: {x_m: 0, y_m: 0, yaw_deg: 0}\n"                               // 6
    "sensors: {encoders: {rate_hz: 50}}\n"                                  // 7
    "sim: {dt_s: 0.01, seed: 1}\n"                                          // 8
    "events:\n"                                                             // 9
    "  - {t_s: 1.0, teleport: {x_m: 2, y_m: -3, yaw_deg: 90}}\n"             // 10
    "commands:\n"                                                           // 11
    "  - {duration_s: 0.5}\n"                                               // 12
    "  - {duration_s: 1.5}\n";                                              // 13

TEST(Teleport, MovesTheRobotWithoutTurningItsWheelsOrCountingDistance) {
  Simulation sim(parse_scenario(kTeleport, "t.yaml"));
  sim.run();
  const VehicleState& s = sim.vehicle().state();
  EXPECT_NEAR(s.pose.position.x(), 2.0, 1e-12);
  EXPECT_NEAR(s.pose.position.y(), -3.0, 1e-12);
  EXPECT_NEAR(s.pose.to_pose2().yaw, kPi / 2, 1e-12);
  for (const double a : s.wheel_angle_rad) EXPECT_EQ(a, 0.0);
  EXPECT_EQ(sim.metrics().distance_m, 0.0);
  bool seen = false;
  for (const auto& e : sim.events())
    if (e.kind == "teleport") seen = e.t_s == 1.0;
  EXPECT_TRUE(seen);
}

TEST(Teleport, BadEventsNameTheirField) {
  // The body would straddle the wall (its wheels on the floor either side).
  std::string into_crate = kTeleport;
  into_crate.replace(into_crate.find("x_m: 2, y_m: -3"), 15, "x_m: 5, y_m: 5");
  try {
    Simulation sim(parse_scenario(into_crate, "t.yaml"));
    sim.run();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "events[0].teleport") << e.what();
    EXPECT_EQ(e.line(), 10);
  }
  std::string unknown = kTeleport;
  unknown.replace(unknown.find("yaw_deg: 90"), 11, "yaw: 90");
  EXPECT_THROW(parse_scenario(unknown, "t.yaml"), Error);
  std::string backwards = kTeleport;
  backwards.replace(backwards.find("events:\n"), 8, "events:\n  - {t_s: 2.0, teleport: {}}\n");
  EXPECT_THROW(parse_scenario(backwards, "t.yaml"), Error);
}

}  // namespace
}  // namespace starnav
