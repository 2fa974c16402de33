// A toy local controller: it ignores the global path and drives straight at the goal, turning
// toward it first. Useful as a baseline (what planning buys) and as the worked example of adding a
// component: this file and one line in registry/components.cpp (docs/architecture.md).
#include <algorithm>
#include <cmath>

#include "starnav/control/local_controller.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

namespace {

struct StraightToGoalConfig {
  double speed_mps = 0.2;
  double yaw_gain = 2.0;                 // 1/s
  double turn_in_place_rad = kPi / 6.0;  // heading error above which it only turns
  double tolerance_m = 0.1;
};

const ParamTable<StraightToGoalConfig>& straight_to_goal_params() {
  static const ParamTable<StraightToGoalConfig> table = [] {
    using C = StraightToGoalConfig;
    ParamTable<C> t;
    t.real("speed_mps", &C::speed_mps, positive(), "m/s", "forward speed (capped by the robot's limit)");
    t.real("yaw_gain", &C::yaw_gain, positive(), "1/s", "yaw rate per radian of bearing to the goal");
    t.real("turn_in_place_deg", &C::turn_in_place_rad, open(0.0, 180.0), "deg",
           "bearing to the goal above which the robot turns without driving", kPi / 180.0);
    t.real("tolerance_m", &C::tolerance_m, positive(), "m", "arrived this close to the goal");
    return t;
  }();
  return table;
}

class StraightToGoal final : public LocalController {
 public:
  explicit StraightToGoal(const StraightToGoalConfig& c) : c_(c) {}
  std::string_view name() const override { return "straight_to_goal"; }
  void set_path(std::span<const Vec2> points) override {
    if (points.empty()) throw Error("empty path", {}, 0, "path");
    path_.assign(points.begin(), points.end());
  }
  void clear() override { path_.clear(); }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }

  ControlOutput compute(const ControlInput& in) override {
    if (path_.empty()) return {};
    const Vec2 to_goal = in.goal - in.pose.translation();
    if (to_goal.norm() <= c_.tolerance_m) return {{}, ControlStatus::Arrived};
    const double bearing = wrap_angle(std::atan2(to_goal.y(), to_goal.x()) - in.pose.yaw);
    ControlOutput out;
    out.status = ControlStatus::Tracking;
    out.twist.wz = std::clamp(c_.yaw_gain * bearing, -in.limits.max_yaw_rate_radps, in.limits.max_yaw_rate_radps);
    if (std::abs(bearing) < c_.turn_in_place_rad) out.twist.vx = std::min(c_.speed_mps, in.limits.max_vx_mps);
    return out;
  }

 private:
  StraightToGoalConfig c_;
  std::vector<Vec2> path_;
};

}  // namespace

LocalControllerDef straight_to_goal_controller() {
  LocalControllerDef d;
  d.info.role = Role::LocalController;
  d.info.name = "straight_to_goal";
  d.info.section = "straight_to_goal";
  d.info.summary = "Toy baseline: ignores the path, turns toward the goal and drives straight at it";
  d.info.params = straight_to_goal_params().specs();
  d.make = [](const LocalControllerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<LocalController> {
    return std::make_unique<StraightToGoal>(configured(straight_to_goal_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
