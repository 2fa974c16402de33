// Dead reckoning as a localizer: the odometry's pose, with the covariance the slip model
// propagates (the EKF's prediction without its updates). The baseline every localizer is
// compared against.
#include <memory>

#include "starnav/estimate/localizer.hpp"
#include "starnav/estimate/odometry_imu_ekf.hpp"

namespace starnav {

namespace {

struct DeadReckoningConfig {
  double wheel_slip_sigma = 0.05;
};

const ParamTable<DeadReckoningConfig>& dead_reckoning_params() {
  static const ParamTable<DeadReckoningConfig> table = [] {
    ParamTable<DeadReckoningConfig> t;
    t.real("wheel_slip_sigma", &DeadReckoningConfig::wheel_slip_sigma, closed(0.0, 1.0), "-",
           "slip of each wheel relative to its angle increment (for the covariance only)");
    return t;
  }();
  return table;
}

class DeadReckoningLocalizer final : public Localizer {
 public:
  DeadReckoningLocalizer(const DeadReckoningConfig& c, const LocalizerContext& ctx)
      : model_(make_robot_model(ctx.robot ? *ctx.robot : RobotConfig{})),
        ekf_(filter_config(c), *model_, ctx.start),
        last_(ctx.start) {}
  std::string_view name() const override { return "odometry"; }
  void on_odometry(const OdometryMessage& o) override {
    ekf_.predict(last_.inverse().compose(o.pose));
    // The odometry's own pose, not the re-composed one: dead reckoning is the odometry exactly.
    ekf_.set_pose(o.pose);
    last_ = o.pose;
    t_s_ = o.header.t_s;
  }
  PoseEstimate estimate() const override {
    PoseEstimate e;
    e.t_s = t_s_;
    e.pose = ekf_.pose();
    e.covariance = ekf_.pose_covariance();
    e.valid = true;
    return e;
  }

 private:
  static EkfConfig filter_config(const DeadReckoningConfig& c) {
    EkfConfig f;
    f.wheel_slip_sigma = c.wheel_slip_sigma;
    return f;
  }
  std::unique_ptr<RobotModel> model_;
  OdometryImuEkf ekf_;
  Pose2 last_;
  double t_s_ = 0.0;
};

}  // namespace

LocalizerDef odometry_localizer() {
  LocalizerDef d;
  d.info.role = Role::Localizer;
  d.info.name = "odometry";
  d.info.section = "dead_reckoning";
  d.info.summary = "Dead reckoning: the odometry's pose, its covariance from the slip model";
  d.info.params = dead_reckoning_params().specs();
  d.make = [](const LocalizerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Localizer> {
    return std::make_unique<DeadReckoningLocalizer>(configured(dead_reckoning_params(), settings, ctx.file), ctx);
  };
  return d;
}

}  // namespace starnav
