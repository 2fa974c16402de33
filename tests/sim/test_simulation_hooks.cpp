// Simulation's hooks for a driver outside the simulator (navigation): command_source replaces the
// command script and sees the vehicle at t_k; stop() ends the run at once and records the state.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {
namespace {

const char* kFlat = R"(
name: hooks
world:
  terrain:
    generate: {kind: flat, size_m: [10.0, 4.0], resolution_m: 0.1}
robot:
  actuator_lag_s: 0.0
  max_wheel_accel_radps2: 1000.0
  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 0.0}
sim: {dt_s: 0.01, duration_s: 10.0}
commands:
  - {duration_s: 10.0, vx_mps: -0.3}
)";

TEST(SimulationHooks, CommandSourceReplacesTheScriptAndSeesTheStateAtTk) {
  Simulation sim(parse_scenario(kFlat, "hooks.yaml"));
  int calls = 0;
  sim.command_source = [&](double t) {
    EXPECT_NEAR(t, calls * 0.01, 1e-12);
    EXPECT_NEAR(sim.vehicle().state().pose.position.x(), 1.0 + 0.2 * calls * 0.01, 1e-9);
    ++calls;
    return BodyTwist{0.2, 0.0, 0.0};  // forward, whereas the script says backward
  };
  sim.run();
  EXPECT_EQ(calls, 1000);
  EXPECT_NEAR(sim.vehicle().state().pose.position.x(), 3.0, 1e-9);
  EXPECT_FALSE(sim.stopped());
}

TEST(SimulationHooks, StopEndsTheRunAndRecordsTheLastState) {
  Simulation sim(parse_scenario(kFlat, "hooks.yaml"));
  sim.command_source = [&](double t) {
    if (t >= 2.0 - 1e-9) sim.stop();
    return BodyTwist{0.2, 0.0, 0.0};
  };
  sim.run();
  EXPECT_TRUE(sim.stopped());
  EXPECT_TRUE(sim.finished());
  EXPECT_NEAR(sim.time(), 2.0, 1e-9);
  ASSERT_FALSE(sim.trajectory().empty());
  EXPECT_NEAR(sim.trajectory().back().t_s, 2.0, 1e-9);
  EXPECT_NEAR(sim.trajectory().back().position.x(), 1.4, 1e-9);
  // A stopped simulation takes no more steps.
  const auto steps = sim.step_count();
  sim.step();
  EXPECT_EQ(sim.step_count(), steps);
}

}  // namespace
}  // namespace starnav
