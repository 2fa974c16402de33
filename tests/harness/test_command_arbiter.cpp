// Who commands the robot (harness/command_arbiter): bumper stop > manual > autonomous, the wait
// after a contact, manual segments by time; and the whole priority chain in a simulated run: a
// box dropped in front of the robot stops it by the bumper within its stopping time, it waits,
// and it resumes within a second once the box is gone; a manual command overrides navigation.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "starnav/harness/command_arbiter.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {
namespace {

ScenarioManualCommand manual(double t, double d, double vx) {
  ScenarioManualCommand c;
  c.t_s = t;
  c.duration_s = d;
  c.twist.vx = vx;
  return c;
}

TEST(CommandArbiter, BumperOutranksManualOutranksAutonomous) {
  CommandArbiter a({true, 0.5}, {manual(1.0, 2.0, 0.3)});
  EXPECT_EQ(a.decide(0.0, false).source, CommandSource::Autonomous);
  const auto m = a.decide(1.0, false);
  EXPECT_EQ(m.source, CommandSource::Manual);
  EXPECT_EQ(m.twist.vx, 0.3);
  // A contact during the manual command stops the robot.
  const auto b = a.decide(1.5, true);
  EXPECT_EQ(b.source, CommandSource::BumperStop);
  EXPECT_EQ(b.twist.vx, 0.0);
  // Released at 2.0: it waits resume_delay_s, then the manual command is back.
  EXPECT_EQ(a.decide(2.0, false).source, CommandSource::BumperWait);
  EXPECT_EQ(a.decide(2.49, false).source, CommandSource::BumperWait);
  EXPECT_EQ(a.decide(2.5, false).source, CommandSource::Manual);
  // The manual segment ends at 3.0.
  EXPECT_EQ(a.decide(3.0, false).source, CommandSource::Autonomous);
  ASSERT_EQ(a.events().size(), 5u);
  EXPECT_EQ(a.events()[0].kind, "manual");
  EXPECT_EQ(a.events()[1].kind, "bumper_stop");
  EXPECT_EQ(a.events()[2].kind, "bumper_wait");
  EXPECT_EQ(a.events()[3].kind, "manual");
  EXPECT_EQ(a.events()[4].kind, "autonomous");
}

TEST(CommandArbiter, WithoutBumperStopContactsChangeNothing) {
  CommandArbiter a({false, 0.5}, {});
  EXPECT_EQ(a.decide(0.0, true).source, CommandSource::Autonomous);
  EXPECT_EQ(a.decide(0.1, false).source, CommandSource::Autonomous);
  EXPECT_TRUE(a.events().empty());
}

// scenarios/ren_bumper.yaml: a low box (only the bumper finds it) in the robot's way until 8 s; a
// manual command backing it away at 10 s.
TEST(CommandArbiter, BumperStopsTheRobotItWaitsAndResumesOnceTheObstacleIsGone) {
  const ScenarioSpec spec = load_scenario(std::string(STARNAV_SOURCE_DIR) + "/scenarios/ren_bumper.yaml");
  NavigationRun run(spec);
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
  EXPECT_EQ(m.bumper_stops, 1);
  const auto& ev = run.arbiter().events();
  ASSERT_GE(ev.size(), 3u);
  EXPECT_EQ(ev[0].kind, "bumper_stop");
  const double contact_t = ev[0].t_s;
  EXPECT_LT(contact_t, 8.0);
  // At rest within the stopping time: speed / deceleration + the actuator lag (and one step).
  const RobotConfig& r = spec.vehicle.robot;
  const double decel = r.max_wheel_accel_radps2 * r.wheel_radius_m;
  double speed_at_contact = 0.0, rest_t = -1.0;
  for (const TrajectorySample& s : run.simulation().trajectory()) {
    if (s.t_s <= contact_t) speed_at_contact = std::hypot(s.twist.vx, s.twist.vy);
    if (s.t_s > contact_t && rest_t < 0.0 && std::hypot(s.twist.vx, s.twist.vy) < 1e-3) rest_t = s.t_s;
  }
  ASSERT_GT(rest_t, 0.0);
  EXPECT_LE(rest_t - contact_t, speed_at_contact / decel + 3.0 * r.actuator_lag_s + 0.02);
  EXPECT_GT(speed_at_contact, 0.05);  // it was moving when it met the box
  // It waits while the box is there, then resumes within 1 s of its going.
  EXPECT_EQ(ev[1].kind, "bumper_wait");
  EXPECT_NEAR(ev[1].t_s, 8.0, 0.02);
  EXPECT_EQ(ev[2].kind, "autonomous");
  EXPECT_LE(ev[2].t_s - 8.0, 1.0);
  for (const TrajectorySample& s : run.simulation().trajectory()) {
    if (s.t_s > rest_t + 0.1 && s.t_s < 8.0) {
      EXPECT_LT(std::hypot(s.twist.vx, s.twist.vy), 1e-3) << s.t_s;
    }
  }
  // The manual command backed it away at 10 s (if it had not arrived before).
  bool manual = false;
  for (const ArbiterEvent& e : ev) manual = manual || (e.kind == "manual" && std::abs(e.t_s - 10.0) < 0.02);
  EXPECT_EQ(manual, run.arrivals().empty() || run.arrivals().front().t_s > 10.0);
}

}  // namespace
}  // namespace starnav
