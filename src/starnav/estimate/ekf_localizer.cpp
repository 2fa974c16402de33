// The EKF as a localizer (and, in a localization chain, as the fused odometry another localizer
// reads): wheel odometry increments predict, IMU yaw readings update (estimate/odometry_imu_ekf).
#include <algorithm>
#include <memory>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/localizer.hpp"
#include "starnav/estimate/odometry_imu_ekf.hpp"

namespace starnav {

namespace {

struct EkfLocalizerConfig {
  EkfConfig filter;
  int ticks_per_rev = 1024;
  bool sample_initial_error = false;
};

const ParamTable<EkfLocalizerConfig>& ekf_localizer_params() {
  static const ParamTable<EkfLocalizerConfig> table = [] {
    using C = EkfLocalizerConfig;
    constexpr double deg = kPi / 180.0;
    ParamTable<C> t;
    t.boolean("bias_state", [](C& c) -> bool& { return c.filter.bias_state; },
              "five states (x, y, yaw, IMU yaw offset, gyro bias) instead of the paper's three");
    t.real("wheel_slip_sigma", [](C& c) -> double& { return c.filter.wheel_slip_sigma; }, closed(0.0, 1.0), "-",
           "slip of each wheel relative to its angle increment (the odometry's noise)");
    t.integer("ticks_per_rev", &C::ticks_per_rev, closed(0, 1e9), "-",
              "encoder resolution for the quantisation noise (0: none); the simulator's encoders.ticks_per_rev");
    t.real("imu_yaw_sigma_deg", [](C& c) -> double& { return c.filter.imu_yaw_sigma_rad; }, closed(0.0, 180.0), "deg",
           "standard deviation of the IMU yaw reading (the three-state filter has no drift model: this absorbs it)",
           deg);
    t.real("gyro_noise_sigma_radps", [](C& c) -> double& { return c.filter.gyro_noise_sigma_radps; },
           closed(0.0, 1.0), "rad/s", "white noise of each gyro sample (bias state: integrated into the yaw offset)");
    t.real("gyro_bias_walk", [](C& c) -> double& { return c.filter.gyro_bias_walk; }, closed(0.0, 1.0),
           "rad/s/sqrt(s)", "random walk of the gyro bias (bias state)");
    t.real("initial_sigma_xy_m", [](C& c) -> double& { return c.filter.initial_sigma_xy_m; }, closed(0.0, 100.0), "m",
           "standard deviation of the start's x and y");
    t.real("initial_sigma_yaw_deg", [](C& c) -> double& { return c.filter.initial_sigma_yaw_rad; }, closed(0.0, 180.0),
           "deg", "standard deviation of the start's yaw", deg);
    t.real("initial_bias_sigma_radps", [](C& c) -> double& { return c.filter.initial_bias_sigma_radps; },
           closed(0.0, 1.0), "rad/s", "prior standard deviation of the gyro bias (bias state)");
    t.real("initial_imu_offset_sigma_deg", [](C& c) -> double& { return c.filter.initial_imu_offset_sigma_rad; },
           closed(0.0, 180.0), "deg",
           "prior standard deviation of the IMU yaw minus the robot's at the start (0: aligned, as the simulator's)", deg);
    t.real("gate_chi2", [](C& c) -> double& { return c.filter.gate_chi2; }, closed(0.0, 1e6), "-",
           "Mahalanobis gate on the yaw innovation (squared, one degree of freedom); 0 turns it off");
    t.boolean("sample_initial_error", &C::sample_initial_error,
              "start from the start pose plus an error drawn from the initial covariance (consistency experiments)");
    return t;
  }();
  return table;
}

// Its own random stream of the scenario's seed (ground_truth has 101).
constexpr std::uint64_t kEkfStream = 103;

// An IMU heading at a time: the unit's own, or integrated here from its rates.
struct YawReading {
  double t_s = 0.0;
  double yaw_rad = 0.0;
};

class EkfLocalizer final : public Localizer {
 public:
  EkfLocalizer(const EkfLocalizerConfig& c, const LocalizerContext& ctx)
      : model_(make_robot_model(ctx.robot ? *ctx.robot : RobotConfig{})),
        ekf_(c.filter, *model_, ctx.start),
        last_odometry_(ctx.start),
        integrated_yaw_(ctx.start.yaw) {
    if (c.sample_initial_error) {
      Rng rng = Rng(ctx.seed).fork(kEkfStream);
      const double ex = c.filter.initial_sigma_xy_m * rng.normal();
      const double ey = c.filter.initial_sigma_xy_m * rng.normal();
      const double ea = c.filter.initial_sigma_yaw_rad * rng.normal();
      ekf_.set_pose({ctx.start.x + ex, ctx.start.y + ey, wrap_angle(ctx.start.yaw + ea)});
    }
  }
  std::string_view name() const override { return "ekf"; }
  // IMU readings wait for the odometry of their time: the filter predicts to each reading's time
  // (the period's increment split in proportion, as a constant twist over the period) before it
  // updates, so that a turning robot's yaw is never compared with a stale prediction.
  void on_odometry(const OdometryMessage& o) override {
    const Pose2 increment = last_odometry_.inverse().compose(o.pose);
    const Eigen::Matrix3d q = ekf_.period_covariance(increment);
    const double span = o.header.t_s - last_odometry_t_s_;
    Pose2 done;
    double f_done = 0.0;
    std::size_t used = 0;
    for (; used < pending_.size() && pending_[used].t_s <= o.header.t_s; ++used) {
      const double f = span > 0.0 ? std::clamp((pending_[used].t_s - last_odometry_t_s_) / span, f_done, 1.0) : 1.0;
      const Pose2 target(increment.x * f, increment.y * f, increment.yaw * f);
      ekf_.predict(done.inverse().compose(target), (f - f_done) * q);
      done = target;
      f_done = f;
      apply_imu(pending_[used]);
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(used));
    ekf_.predict(done.inverse().compose(increment), (1.0 - f_done) * q);
    last_odometry_ = o.pose;
    last_odometry_t_s_ = o.header.t_s;
    has_odometry_ = true;
    t_s_ = std::max(t_s_, o.header.t_s);
  }
  // A unit that integrates its own heading gives yaw_rad; for one that does not, the filter
  // integrates the yaw rate (the sensor's rates turned into the base frame by its mount) from the
  // start's yaw.
  void on_imu(const ImuMessage& m) override {
    YawReading r{m.header.t_s, 0.0};
    if (m.yaw_rad) {
      r.yaw_rad = *m.yaw_rad;
    } else {
      const double rate = (m.mount.rotation() * m.angular_velocity_radps).z();
      if (has_rate_) integrated_yaw_ += rate * std::max(0.0, r.t_s - last_rate_t_s_);
      has_rate_ = true;
      last_rate_t_s_ = r.t_s;
      r.yaw_rad = integrated_yaw_;
    }
    pending_.push_back(r);
    // Without odometry (none yet, or stalled for a while) the readings update at once.
    if (!has_odometry_ || r.t_s - last_odometry_t_s_ > kOdometryWait_s) {
      for (const YawReading& p : pending_) apply_imu(p);
      pending_.clear();
    }
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
  void apply_imu(const YawReading& r) {
    // The IMU's yaw integrates from the run's start (t = 0), where it read the start's yaw.
    const double dt = std::max(0.0, r.t_s - last_imu_t_s_);
    last_imu_t_s_ = r.t_s;
    ekf_.update_yaw(r.yaw_rad, dt);
    t_s_ = std::max(t_s_, r.t_s);
  }

  static constexpr double kOdometryWait_s = 0.5;
  std::unique_ptr<RobotModel> model_;
  OdometryImuEkf ekf_;
  Pose2 last_odometry_;
  double last_odometry_t_s_ = 0.0;
  bool has_odometry_ = false;
  double integrated_yaw_;
  bool has_rate_ = false;
  double last_rate_t_s_ = 0.0;
  std::vector<YawReading> pending_;
  double t_s_ = 0.0;
  double last_imu_t_s_ = 0.0;
};

}  // namespace

LocalizerDef ekf_localizer() {
  LocalizerDef d;
  d.info.role = Role::Localizer;
  d.info.name = "ekf";
  d.info.section = "ekf";
  d.info.summary = "EKF of wheel odometry and IMU yaw, optionally with the gyro bias in the state";
  d.info.capabilities = {Capability::FiltersOdometry};
  d.info.params = ekf_localizer_params().specs();
  d.make = [](const LocalizerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<Localizer> {
    EkfLocalizerConfig c = configured(ekf_localizer_params(), settings, ctx.file);
    c.filter.tick_rad = c.ticks_per_rev > 0 ? 2.0 * kPi / c.ticks_per_rev : 0.0;
    c.filter.validate();
    return std::make_unique<EkfLocalizer>(c, ctx);
  };
  return d;
}

}  // namespace starnav
