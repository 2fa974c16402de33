// Simulation's hooks for a driver outside the simulator (navigation): command_source replaces the
// command script and sees the vehicle at t_k; stop() ends the run at once and records the state;
// the sensor feeds hand each sample to estimators, then navigation, then recorders, whatever the
// order of subscription.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"

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

const char* kTwoLidars = R"(
name: feeds
world:
  terrain:
    generate: {kind: flat, size_m: [10.0, 4.0], resolution_m: 0.1}
robot:
  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 0.0}
sensors:
  lidar: {preset: hokuyo_utm30lx, rate_hz: 10.0}
  lidars:
    rear: {preset: hokuyo_utm30lx, rate_hz: 5.0, mount: {x_m: -0.2, yaw_deg: 180.0}}
  encoders: {}
sim: {dt_s: 0.01, duration_s: 1.0}
commands:
  - {duration_s: 1.0, vx_mps: 0.2}
)";

TEST(SimulationFeeds, StagesDecideTheOrderNotSubscription) {
  Simulation sim(parse_scenario(kTwoLidars, "feeds.yaml"));
  EXPECT_EQ(sim.lidar_streams(), (std::vector<std::string>{"lidar", "lidar/rear"}));
  std::vector<std::string> calls;
  // Subscribed backwards: a recorder, then the navigation, then two estimators.
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [&](const LidarScan&) { calls.push_back("record"); });
  sim.lidar_feed("lidar").subscribe(SampleStage::Navigate, [&](const LidarScan&) { calls.push_back("navigate"); });
  sim.lidar_feed("lidar").subscribe(SampleStage::Estimate, [&](const LidarScan&) { calls.push_back("estimate1"); });
  sim.lidar_feed("lidar").subscribe(SampleStage::Estimate, [&](const LidarScan&) { calls.push_back("estimate2"); });
  int rear = 0, ticks = 0;
  double last_rear_t = -1.0;
  sim.lidar_feed("lidar/rear").subscribe(SampleStage::Record, [&](const LidarScan& s) {
    ++rear;
    last_rear_t = s.time;
  });
  sim.encoder_feed.subscribe(SampleStage::Record, [&](const EncoderSample&) { ++ticks; });
  sim.run();
  // Scans at t = 0, 0.1, ..., 1.0: 11 of the front LiDAR, 6 of the rear one at 5 Hz.
  ASSERT_EQ(calls.size(), 4U * 11U);
  for (std::size_t i = 0; i < calls.size(); i += 4) {
    EXPECT_EQ(calls[i], "estimate1");
    EXPECT_EQ(calls[i + 1], "estimate2");
    EXPECT_EQ(calls[i + 2], "navigate");
    EXPECT_EQ(calls[i + 3], "record");
  }
  EXPECT_EQ(rear, 6);
  EXPECT_NEAR(last_rear_t, 1.0, 1e-9);
  EXPECT_GT(ticks, 0);
  EXPECT_THROW(sim.lidar_feed("lidar/front"), Error);
}

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
