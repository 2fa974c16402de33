// The odometry + IMU EKF: one step against numbers worked by hand, the bias variant against a
// textbook linear Kalman filter where the model is linear (no translation), dead reckoning
// without updates equal to the composed odometry, the slip covariance against Monte Carlo, the
// gate, angle wrapping, and the Fig. 5 experiment's claims on a few seeds.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>

#include "starnav/core/angle.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/odometry_imu_ekf.hpp"
#include "starnav/experiment/localization_experiment.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::read_text;
using test::scenario_path;

RobotConfig mecanum() { return RobotConfig{}; }

TEST(OdometryImuEkf, OnePredictAndUpdateMatchTheHandComputedStep) {
  const auto model = make_robot_model(mecanum());
  EkfConfig c;
  c.initial_sigma_xy_m = 0.1;
  c.initial_sigma_yaw_rad = 0.2;
  c.imu_yaw_sigma_rad = 0.1;
  c.gate_chi2 = 0.0;
  OdometryImuEkf ekf(c, *model, Pose2(1.0, 2.0, kPi / 2));
  // Increment 1 m forward, 0.5 m left, 0.1 rad, with Q = diag(0.01, 0.04, 0.0025).
  ekf.predict(Pose2(1.0, 0.5, 0.1), Eigen::Vector3d(0.01, 0.04, 0.0025).asDiagonal());
  // Heading pi/2: forward is +y, left is -x.
  EXPECT_NEAR(ekf.pose().x, 0.5, 1e-12);
  EXPECT_NEAR(ekf.pose().y, 3.0, 1e-12);
  EXPECT_NEAR(ekf.pose().yaw, kPi / 2 + 0.1, 1e-12);
  // F = [1 0 -(s dx + c dy); 0 1 c dx - s dy; 0 0 1] = [1 0 -1; 0 1 -0.5; 0 0 1] at yaw pi/2.
  // P = F diag(.01,.01,.04) F' + R Q R' with R the rotation by pi/2 (Q's x, y swap).
  Eigen::Matrix3d expected;
  expected << 0.01 + 0.04 + 0.04, 0.02, -0.04,  //
      0.02, 0.01 + 0.01 + 0.01, -0.02,          //
      -0.04, -0.02, 0.04 + 0.0025;
  EXPECT_TRUE(ekf.pose_covariance().isApprox(expected, 1e-12)) << ekf.pose_covariance();
  // Yaw reading 0.2 rad above the prediction: S = 0.0425 + 0.01, K = P(:,2) / S.
  ASSERT_TRUE(ekf.update_yaw(kPi / 2 + 0.3, 0.01));
  const double s = 0.0425 + 0.01;
  EXPECT_NEAR(ekf.pose().x, 0.5 + (-0.04 / s) * 0.2, 1e-12);
  EXPECT_NEAR(ekf.pose().y, 3.0 + (-0.02 / s) * 0.2, 1e-12);
  EXPECT_NEAR(ekf.pose().yaw, kPi / 2 + 0.1 + (0.0425 / s) * 0.2, 1e-12);
  EXPECT_NEAR(ekf.pose_covariance()(2, 2), 0.0425 * 0.01 / s, 1e-12);
  EXPECT_NEAR(ekf.pose_covariance()(0, 0), 0.09 - 0.04 * 0.04 / s, 1e-12);
}

TEST(OdometryImuEkf, BiasStateEqualsATextbookLinearKalmanFilterWithoutTranslation) {
  // With dx = dy = 0 every Jacobian is constant: the EKF is the linear KF of (theta, psi, b).
  const auto model = make_robot_model(mecanum());
  EkfConfig c;
  c.bias_state = true;
  c.initial_sigma_yaw_rad = 0.05;
  c.initial_imu_offset_sigma_rad = 0.02;
  c.initial_bias_sigma_radps = 0.01;
  c.gyro_noise_sigma_radps = 0.003;
  c.gyro_bias_walk = 0.001;
  c.imu_yaw_sigma_rad = 0.01;
  c.gate_chi2 = 0.0;
  OdometryImuEkf ekf(c, *model, Pose2(0.0, 0.0, 0.3));
  Eigen::Vector3d x(0.3, 0.0, 0.0);
  Eigen::Matrix3d p = Eigen::Vector3d(0.05 * 0.05, 0.02 * 0.02, 0.01 * 0.01).asDiagonal();
  Rng rng(4);
  for (int k = 0; k < 200; ++k) {
    const double dtheta = 0.02 * rng.normal(), q = 1e-4 * (1.0 + rng.uniform());
    Eigen::Matrix3d q3 = Eigen::Matrix3d::Zero();
    q3(2, 2) = q;
    ekf.predict(Pose2(0.0, 0.0, dtheta), q3);
    x(0) += dtheta;
    p(0, 0) += q;
    const double dt = 0.01 * (1 + k % 3), z = x(0) + 0.01 * rng.normal();
    Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
    a(1, 2) = dt;
    x = a * x;
    p = a * p * a.transpose();
    p(1, 1) += (0.003 * dt) * (0.003 * dt);
    p(2, 2) += 0.001 * 0.001 * dt;
    const Eigen::RowVector3d h(1.0, 1.0, 0.0);
    const double s = (h * p * h.transpose())(0, 0) + 1e-4;
    const Eigen::Vector3d gain = p * h.transpose() / s;
    x += gain * (z - h * x);
    p = (Eigen::Matrix3d::Identity() - gain * h) * p;
    ASSERT_TRUE(ekf.update_yaw(z, dt));
    ASSERT_NEAR(wrap_angle(ekf.state()(2) - x(0)), 0.0, 1e-10) << k;
    ASSERT_NEAR(ekf.state()(3), x(1), 1e-10) << k;
    ASSERT_NEAR(ekf.state()(4), x(2), 1e-10) << k;
    const std::array<int, 3> idx = {2, 3, 4};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ASSERT_NEAR(ekf.covariance()(idx[i], idx[j]), p(i, j), 1e-12) << k;
  }
}

TEST(OdometryImuEkf, WithoutUpdatesItIsTheComposedOdometry) {
  const auto model = make_robot_model(mecanum());
  OdometryImuEkf ekf({}, *model, Pose2(1.0, -1.0, 3.0));
  Pose2 truth(1.0, -1.0, 3.0);
  Rng rng(9);
  for (int k = 0; k < 1000; ++k) {
    const Pose2 inc(0.02 * rng.uniform(), 0.01 * rng.normal(), 0.05 * rng.normal());
    truth = truth.compose(inc);
    truth.yaw = wrap_angle(truth.yaw);
    ekf.predict(inc);
  }
  EXPECT_NEAR(ekf.pose().x, truth.x, 1e-9);
  EXPECT_NEAR(ekf.pose().y, truth.y, 1e-9);
  EXPECT_NEAR(wrap_angle(ekf.pose().yaw - truth.yaw), 0.0, 1e-9);
  // The covariance grew and stayed symmetric positive definite.
  const Eigen::Matrix3d p = ekf.pose_covariance();
  EXPECT_TRUE(p.isApprox(p.transpose(), 1e-12));
  EXPECT_GT(p.llt().matrixL().toDenseMatrix().diagonal().minCoeff(), 0.0);
}

TEST(OdometryImuEkf, SlipCovarianceMatchesMonteCarloOfTheWheels) {
  // Each wheel's increment off by slip * N(0,1) * increment, through the forward kinematics.
  const auto model = make_robot_model(mecanum());
  EkfConfig c;
  c.wheel_slip_sigma = 0.05;
  OdometryImuEkf ekf(c, *model, {});
  const Pose2 inc(0.02, 0.005, 0.01);
  std::array<double, 4> gamma{};
  model->inverse({inc.x, inc.y, inc.yaw}, gamma);
  Rng rng(1);
  const int n = 200000;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int k = 0; k < n; ++k) {
    std::array<double, 4> g = gamma;
    for (double& w : g) w *= 1.0 + 0.05 * rng.normal();
    const BodyTwist b = model->forward(g);
    const Eigen::Vector3d e(b.vx - inc.x, b.vy - inc.y, b.wz - inc.yaw);
    m += e * e.transpose() / n;
  }
  const Eigen::Matrix3d q = ekf.slip_covariance(inc);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(q(i, j), m(i, j), 0.02 * q.diagonal().maxCoeff()) << i << j;
}

// The paper's Mecanum base with 1024-tick encoders.
class QuantisedEkf : public ::testing::Test {
 protected:
  static EkfConfig ticked() {
    EkfConfig c;
    c.tick_rad = 2.0 * kPi / 1024.0;
    return c;
  }
  const RobotConfig robot = mecanum();
  const std::unique_ptr<RobotModel> model = make_robot_model(robot);
  const EkfConfig c = ticked();
  OdometryImuEkf ekf{c, *model, {}};
};

// A still period right after motion may hide up to a tick of each wheel: its covariance is
// the rounding of every wheel, tick^2 / 6 each, through the forward kinematics (for the yaw of
// a Mecanum base: 4 (tick^2 / 6) (r / (4 (L1 + L2)))^2); from the third still period on, and
// before the robot ever moved, nothing.
TEST_F(QuantisedEkf, StillPeriodsAfterMotionCarryTheRoundingThenNothing) {
  const Pose2 still;
  EXPECT_TRUE(ekf.period_covariance(still).isZero());  // at the start: settled
  const Pose2 moving(0.006, 0.0, 0.0);
  EXPECT_TRUE(ekf.period_covariance(moving).isApprox(ekf.slip_covariance(moving)));
  const double k = robot.wheel_radius_m / (4.0 * (robot.half_track_m + robot.half_wheelbase_m));
  const double yaw_variance = 4.0 * c.tick_rad * c.tick_rad / 6.0 * k * k;
  for (int period = 1; period <= OdometryImuEkf::kSettlePeriods; ++period) {
    const Eigen::Matrix3d q = ekf.period_covariance(still);
    EXPECT_NEAR(q(2, 2), yaw_variance, 1e-12 * yaw_variance) << period;
    EXPECT_GT(q(0, 0), 0.0);
    EXPECT_GT(q(1, 1), 0.0);
    EXPECT_TRUE(ekf.slip_covariance(still).isZero());  // the slip model alone: nothing
  }
  EXPECT_TRUE(ekf.period_covariance(still).isZero());
  EXPECT_TRUE(ekf.period_covariance(still).isZero());
  EXPECT_FALSE(ekf.period_covariance(moving).isZero());
  EXPECT_FALSE(ekf.period_covariance(still).isZero());  // settling again
}

TEST_F(QuantisedEkf, AtRestAwayFromTheOriginTheIncrementsRoundingIsStillStill) {
  // Between two equal odometry poses away from the origin the composed increment is not exactly
  // zero (1e-16 m): that is rest, and only whole ticks are motion.
  Pose2 residue;
  for (int k = 1; k < 100 && residue.x == 0.0 && residue.y == 0.0; ++k) {
    const Pose2 corner(0.37 * k, 0.21 * k, 0.1 * k);
    residue = corner.inverse().compose(corner);
  }
  ASSERT_FALSE(residue.x == 0.0 && residue.y == 0.0);  // the case itself
  EXPECT_LT(std::hypot(residue.x, residue.y), 1e-12);
  EXPECT_TRUE(ekf.period_covariance(residue).isZero());
  // One tick of one wheel, and one tick on each of two wheels the other way (whose projection on
  // the body's motions is half a tick per wheel): motion, then settling rest.
  for (const std::array<double, 4>& ticks : {std::array<double, 4>{1, 0, 0, 0}, std::array<double, 4>{1, -1, 0, 0}}) {
    std::array<double, 4> gamma{};
    for (std::size_t i = 0; i < 4; ++i) gamma[i] = ticks[i] * c.tick_rad;
    const BodyTwist b = model->forward(gamma);
    const Pose2 moved(b.vx, b.vy, b.wz);
    ASSERT_GT(std::hypot(moved.x, moved.y) + std::abs(moved.yaw), 0.0);
    EXPECT_TRUE(ekf.period_covariance(moved).isApprox(ekf.slip_covariance(moved)));
    EXPECT_FALSE(ekf.period_covariance(residue).isZero());  // settling
  }
  for (int period = 1; period < OdometryImuEkf::kSettlePeriods; ++period) EXPECT_FALSE(ekf.period_covariance(residue).isZero());
  EXPECT_TRUE(ekf.period_covariance(residue).isZero());
}

TEST(OdometryImuEkf, GateRejectsAnOutlierAndInnovationsWrapAtPi) {
  const auto model = make_robot_model(mecanum());
  EkfConfig c;
  c.initial_sigma_yaw_rad = 0.01;
  c.imu_yaw_sigma_rad = 0.01;
  c.gate_chi2 = 9.0;
  OdometryImuEkf ekf(c, *model, Pose2(0.0, 0.0, kPi - 0.01));
  // 10 sigma of the innovation (sqrt(2) * 0.01) away: rejected, nothing changes.
  EXPECT_FALSE(ekf.update_yaw(kPi - 0.01 + 0.15, 0.01));
  EXPECT_EQ(ekf.rejected(), 1);
  EXPECT_DOUBLE_EQ(ekf.pose().yaw, kPi - 0.01);
  // A reading just past pi (-pi + 0.01) is 0.02 rad ahead, not 2 pi - 0.02 behind.
  EXPECT_TRUE(ekf.update_yaw(-kPi + 0.01, 0.01));
  EXPECT_NEAR(std::abs(ekf.pose().yaw), kPi, 1e-12);  // halfway: exactly at +-pi
}

TEST(OdometryImuEkf, ImpossibleParametersNameTheirField) {
  const auto model = make_robot_model(mecanum());
  EkfConfig c;
  c.wheel_slip_sigma = -1.0;
  try {
    OdometryImuEkf(c, *model, {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "ekf.wheel_slip_sigma");
  }
  const std::vector<ParamSetting> bad = {{"gate_chi2", "nan", "s.yaml", 3, "localization.ekf.gate_chi2"}};
  EXPECT_THROW(find_localizer("ekf").make({}, bad), Error);
}

TEST(EkfLocalizer, AGyroWithoutAHeadingIsIntegratedFromItsRatesInTheBaseFrame) {
  // The same turn seen by three IMUs: one that gives its integrated heading, one that gives only
  // its rate, and one mounted upside down (its z axis down: the rate's sign flips in its frame).
  // The filter integrates the rates from the start's yaw and turns them by the mount, so all
  // three give the same estimates.
  const double w = 0.2, start_yaw = 0.3, dt = 0.01;
  LocalizerContext ctx(Pose2(1.0, 2.0, start_yaw), 7, "x.yaml");
  std::vector<std::unique_ptr<Localizer>> filters;
  for (int i = 0; i < 3; ++i) filters.push_back(find_localizer("ekf").make(ctx, {}));
  const Pose3 upside_down = Pose3::from_rpy(Vec3(0.1, 0.0, 0.2), kPi, 0.0, 0.0);
  for (int k = 0; k <= 200; ++k) {
    const double t = k * dt;
    OdometryMessage o;
    o.header = {t, "odom"};
    o.pose = Pose2(1.0 + 0.1 * t, 2.0, start_yaw + 0.9 * w * t);  // the wheels under-read the turn
    o.twist = {0.1, 0.0, 0.9 * w};
    ImuMessage with_heading;
    with_heading.header = {t, "imu"};
    with_heading.angular_velocity_radps = Vec3(0.0, 0.0, w);
    with_heading.yaw_rad = start_yaw + w * t;
    ImuMessage rate_only = with_heading;
    rate_only.yaw_rad.reset();
    ImuMessage flipped = rate_only;
    flipped.mount = upside_down;
    flipped.angular_velocity_radps = Vec3(0.0, 0.0, -w);
    for (auto& f : filters) f->on_odometry(o);
    filters[0]->on_imu(with_heading);
    filters[1]->on_imu(rate_only);
    filters[2]->on_imu(flipped);
  }
  const PoseEstimate a = filters[0]->estimate();
  // The IMU pulled the heading towards the true turn, away from the wheels' (a real test).
  EXPECT_GT(a.pose.yaw, start_yaw + 0.9 * w * 2.0 + 0.01);
  for (int i = 1; i < 3; ++i) {
    const PoseEstimate b = filters[static_cast<std::size_t>(i)]->estimate();
    EXPECT_NEAR(b.pose.x, a.pose.x, 1e-9);
    EXPECT_NEAR(b.pose.y, a.pose.y, 1e-9);
    EXPECT_NEAR(b.pose.yaw, a.pose.yaw, 1e-9);
    EXPECT_NEAR(b.covariance(2, 2), a.covariance(2, 2), 1e-12);
  }
}

TEST(LocalizationChain, RefusesTheEkfTwiceAndAnEkfWithoutImu) {
  const std::string base = read_text(scenario_path("ekf_square.yaml"));
  const auto config_of = [&](const std::string& text) { return localization_config(parse_scenario(text, scenario_path("x.yaml"))); };
  std::string twice = base;
  twice.replace(twice.find("odometry: wheel"), 15, "odometry: ekf");
  EXPECT_THROW(config_of(twice), Error);
  std::string no_imu = twice;
  no_imu.replace(no_imu.find("  imu: {}"), 9, "");
  no_imu.replace(no_imu.find("localizer: ekf"), 14, "localizer: odometry");
  const auto at = no_imu.find("  ekf:");
  no_imu.erase(at, no_imu.find("commands:") - at);
  try {
    config_of(no_imu);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "localization.odometry");
  }
}

TEST(EkfSquare, TheBiasStateHalvesTheErrorsAndItsNeesIsPlausible) {
  // Six seeds of the Fig. 5 experiment (make bench runs 20): the bias EKF far below dead
  // reckoning, the paper's three-state EKF misled by the gyro's drift.
  EkfSquareConfig c;
  c.scenario_file = scenario_path("ekf_square.yaml");
  c.seeds = 6;
  const EkfSquareResult r = run_ekf_square(c);
  // Means over the seeds (a single seed's dead reckoning can be lucky: docs/localization.md).
  double odo_rmse = 0.0, bias_rmse = 0.0, odo_heading = 0.0, bias_heading = 0.0;
  for (const auto& t : r.trials) {
    odo_rmse += t.record.localizers[0].rmse_m;
    bias_rmse += t.record.localizers[2].rmse_m;
    odo_heading += t.record.localizers[0].heading_rmse_deg;
    bias_heading += t.record.localizers[2].heading_rmse_deg;
    EXPECT_LT(t.record.localizers[2].final_heading_error_deg, 1.5) << t.key.seed;
    // b T = 0.0005 rad/s x 409 s = 11.7 deg: the three-state filter follows the drifting yaw.
    EXPECT_GT(t.record.localizers[1].final_heading_error_deg, 8.0) << t.key.seed;
  }
  EXPECT_LT(bias_rmse, 0.5 * odo_rmse);
  EXPECT_LT(bias_heading, 0.5 * odo_heading);
  double mean = 0.0;
  for (const double v : r.nees_mean) mean += v / static_cast<double>(r.nees_mean.size());
  // The mean over time of six seeds' mean NEES: each seed's error persists for minutes, so it
  // is about one draw of chi-square(18) / 6; inside its 99 % interval, [1.04, 6.20].
  EXPECT_GT(mean, chi_square_quantile_wilson_hilferty(0.005, 18.0) / 6.0);
  EXPECT_LT(mean, chi_square_quantile_wilson_hilferty(0.995, 18.0) / 6.0);
  EXPECT_NEAR(chi_square_quantile_wilson_hilferty(0.975, 60.0) / 20.0, 4.17, 0.01);
  EXPECT_NEAR(chi_square_quantile_wilson_hilferty(0.025, 60.0) / 20.0, 2.02, 0.01);
}

TEST(EkfSquare, WithANoiselessGyroTheBiasStateEndsWithinAFewHundredthsOfADegree) {
  // The heading floor of the square test is the gyro's (docs/localization.md): with no rate noise
  // the bias learnt at rest is exact, so whatever heading error is left is the filter's own. The
  // wheels still slip; the filter is told the gyro is nearly perfect.
  EkfSquareConfig c;
  c.scenario_file = scenario_path("ekf_square.yaml");
  c.overrides = {{"sensors.imu.yaw_rate_noise_sigma_radps", "0"}, {"localization.ekf.gyro_noise_sigma_radps", "1e-5"}};
  c.seeds = 3;
  const EkfSquareResult r = run_ekf_square(c);
  std::vector<int> under(kEkfSquareLocalizers, 0);
  for (const auto& t : r.trials) {
    EXPECT_LT(t.record.localizers[2].final_heading_error_deg, 0.05) << t.key.seed;
    for (int l = 0; l < kEkfSquareLocalizers; ++l)
      if (t.record.localizers[static_cast<std::size_t>(l)].final_heading_error_deg < 0.5) ++under[static_cast<std::size_t>(l)];
  }
  EXPECT_EQ(r.heading_under_half_degree, under);
  EXPECT_EQ(r.heading_under_half_degree[2], 3);
  EXPECT_EQ(r.heading_under_half_degree[1], 0);  // the three-state filter still follows the bias
}

}  // namespace
}  // namespace starnav
