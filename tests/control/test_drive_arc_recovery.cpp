// The drive_arc recovery, found by its name in the registry: a car's way out, an arc of its own
// minimum radius (wz = vx / R), backwards first, to the first side whose whole arc the motion
// check calls clear, else forwards; nothing when no arc is clear; it ends after distance / speed.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/control/recovery.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "support/ideal_robots.hpp"

namespace starnav {
namespace {

// A motion check that calls clear the twists `allow` accepts.
class TwistCheck final : public MotionCheck {
 public:
  explicit TwistCheck(std::function<bool(const BodyTwist&)> allow) : allow_(std::move(allow)) {}
  bool clear(const Pose2& /*pose*/, const BodyTwist& twist, double /*duration_s*/) const override { return allow_(twist); }

 private:
  std::function<bool(const BodyTwist&)> allow_;
};

RobotConfig car() {
  RobotConfig r = test::mecanum();
  r.drive = DriveKind::Ackermann;
  r.half_wheelbase_m = 0.2;
  r.max_steer_rad = 30.0 * kPi / 180.0;
  return r;
}

// The first twist of the recovery started at t = 0, and the time it stops (or nullopt/-1).
struct ArcRun {
  std::optional<BodyTwist> first;
  double stopped_t = -1.0;
};

ArcRun run_arc(const RobotConfig& robot, const MotionCheck& check, std::vector<ParamSetting> settings = {}) {
  auto r = find_recovery("drive_arc").make({robot, "test.yaml"}, settings);
  RecoveryInput in;
  in.motion = &check;
  r->start(in);
  ArcRun out;
  for (int k = 0; k <= 1000; ++k) {
    in.t_s = 0.01 * k;
    const std::optional<BodyTwist> t = r->step(in);
    if (k == 0) out.first = t;
    if (!t) {
      out.stopped_t = in.t_s;
      break;
    }
  }
  return out;
}

TEST(DriveArcRecovery, BacksUpAlongTheCarsOwnRadiusToTheClearSide) {
  const RobotConfig c = car();
  const double radius = min_turning_radius_of(c);  // 0.4 / tan(30 deg) = 0.69 m
  ASSERT_NEAR(radius, 0.4 / std::tan(kPi / 6.0), 1e-12);
  // Everything clear: backwards, turning left (wz > 0), wz = speed / R; 0.3 m at 0.1 m/s: 3 s.
  const TwistCheck all([](const BodyTwist&) { return true; });
  const ArcRun a = run_arc(c, all);
  ASSERT_TRUE(a.first);
  EXPECT_DOUBLE_EQ(a.first->vx, -0.1);
  EXPECT_DOUBLE_EQ(a.first->vy, 0.0);
  EXPECT_NEAR(a.first->wz, 0.1 / radius, 1e-12);
  EXPECT_NEAR(a.stopped_t, 3.0, 0.011);
  // Backwards-left blocked: backwards-right.
  const TwistCheck no_back_left([](const BodyTwist& t) { return !(t.vx < 0.0 && t.wz > 0.0); });
  const ArcRun b = run_arc(c, no_back_left);
  ASSERT_TRUE(b.first);
  EXPECT_LT(b.first->vx, 0.0);
  EXPECT_NEAR(b.first->wz, -0.1 / radius, 1e-12);
  // Both backwards arcs blocked: forwards.
  const TwistCheck no_back([](const BodyTwist& t) { return t.vx > 0.0; });
  const ArcRun f = run_arc(c, no_back);
  ASSERT_TRUE(f.first);
  EXPECT_DOUBLE_EQ(f.first->vx, 0.1);
  // Nothing clear: done at once.
  const TwistCheck none([](const BodyTwist&) { return false; });
  const ArcRun n = run_arc(c, none);
  EXPECT_FALSE(n.first);
  EXPECT_EQ(n.stopped_t, 0.0);
}

TEST(DriveArcRecovery, ItsParametersAndARobotThatTurnsInPlace) {
  const TwistCheck all([](const BodyTwist&) { return true; });
  const ArcRun a = run_arc(car(), all,
                           {{"radius_m", "2", "test.yaml", 3, "navigation.drive_arc.radius_m"},
                            {"speed_mps", "0.2", "test.yaml", 4, "navigation.drive_arc.speed_mps"},
                            {"distance_m", "0.5", "test.yaml", 5, "navigation.drive_arc.distance_m"}});
  ASSERT_TRUE(a.first);
  EXPECT_NEAR(a.first->wz, 0.2 / 2.0, 1e-12);
  EXPECT_NEAR(a.stopped_t, 2.5, 0.011);
  const ArcRun d = run_arc(test::differential(), all);  // turns in place: 0.5 m
  ASSERT_TRUE(d.first);
  EXPECT_NEAR(d.first->wz, 0.1 / 0.5, 1e-12);
  EXPECT_THROW(run_arc(car(), all, {{"speed_mps", "0", "test.yaml", 3, "navigation.drive_arc.speed_mps"}}), Error);
}

}  // namespace
}  // namespace starnav
