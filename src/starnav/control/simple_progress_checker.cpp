// Nav2's SimpleProgressChecker: the robot makes progress while it moves at least
// required_movement_m from a reference pose within movement_time_allowance_s; each time it does,
// the reference moves to where it is.
#include "starnav/control/progress_checker.hpp"

namespace starnav {

namespace {

struct SimpleProgressCheckerConfig {
  double required_movement_m = 0.1;
  double movement_time_allowance_s = 15.0;
};

const ParamTable<SimpleProgressCheckerConfig>& simple_progress_checker_params() {
  static const ParamTable<SimpleProgressCheckerConfig> table = [] {
    using C = SimpleProgressCheckerConfig;
    ParamTable<C> t;
    t.real("required_movement_m", &C::required_movement_m, positive(), "m", "moving this far counts as progress");
    t.real("movement_time_allowance_s", &C::movement_time_allowance_s, positive(), "s",
           "no progress in this long: the navigator starts its recoveries");
    return t;
  }();
  return table;
}

class SimpleProgressChecker final : public ProgressChecker {
 public:
  explicit SimpleProgressChecker(const SimpleProgressCheckerConfig& c) : c_(c) {}
  std::string_view name() const override { return "simple_progress"; }
  void reset() override { since_ = -1.0; }
  void restart_clock(double t) override { since_ = t; }
  bool check(const Pose2& pose, double t) override {
    if (since_ < 0.0 || (pose.translation() - reference_.translation()).norm() >= c_.required_movement_m) {
      reference_ = pose;
      since_ = t;
      return true;
    }
    if (t - since_ < c_.movement_time_allowance_s) return true;
    since_ = t;
    return false;
  }

 private:
  SimpleProgressCheckerConfig c_;
  Pose2 reference_;
  double since_ = -1.0;
};

}  // namespace

ProgressCheckerDef simple_progress_checker() {
  ProgressCheckerDef d;
  d.info.role = Role::ProgressChecker;
  d.info.name = "simple_progress";
  d.info.section = "progress_checker";
  d.info.summary = "Progress is moving required_movement_m within movement_time_allowance_s (Nav2's SimpleProgressChecker)";
  d.info.params = simple_progress_checker_params().specs();
  d.make = [](const ProgressCheckerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ProgressChecker> {
    return std::make_unique<SimpleProgressChecker>(configured(simple_progress_checker_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
