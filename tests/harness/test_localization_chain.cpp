// The localization chain in the simulator: AMCL tracks the robot on the map its world was made
// from (error against the simulator's truth), odometry: ekf feeds the EKF's fused pose to the
// localizer, and a map-based localizer without a map is one error naming the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <variant>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/harness/route_drive.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::scenario_path;

double position_rmse(const std::vector<EstimateRecord>& records, bool scans_only) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const EstimateRecord& r : records) {
    if (scans_only && !r.scan) continue;
    sum += (r.estimate.pose.translation() - r.truth.translation()).squaredNorm();
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : NAN;
}

TEST(LocalizationChain, AmclTracksTheRobotOnTheMapOfItsWorld) {
  ScenarioSpec spec = load_scenario(scenario_path("amcl_indoor.yaml"));
  spec.duration_s = 25.0;  // the first corridor (the full loop runs in make bench)
  Simulation sim(spec);
  LocalizationChain chain(sim, localization_config(spec));
  const auto route = make_route_drive(sim);
  // Dead reckoning beside it, on the same encoders.
  chain.add_localizer("odometry", {});
  sim.run();
  const double amcl = position_rmse(chain.records(0), true);
  EXPECT_LT(amcl, 0.05);
  EXPECT_TRUE(chain.records(0).back().estimate.converged);
  EXPECT_GT(chain.records(0).back().estimate.updates, 50);
  EXPECT_LE(chain.records(0).back().estimate.particles, 2000);
  // A viewer's sample of the belief: as many as asked (up to the set), around the estimate.
  const PoseEstimate e = chain.localizer().estimate();
  const std::vector<Pose2> samples = chain.localizer().belief_samples(100);
  ASSERT_EQ(samples.size(), std::min<std::size_t>(100, static_cast<std::size_t>(e.particles)));
  Vec2 mean = Vec2::Zero();
  for (const Pose2& p : samples) mean += p.translation() / static_cast<double>(samples.size());
  EXPECT_LT((mean - e.pose.translation()).norm(), 0.1);
  EXPECT_TRUE(chain.localizer().belief_samples(0).empty());
  // Same inputs, same bytes: the run is a function of its seed.
  Simulation again(spec);
  LocalizationChain chain2(again, localization_config(spec));
  const auto route2 = make_route_drive(again);
  again.run();
  EXPECT_EQ(estimate_csv(chain.records(0)), estimate_csv(chain2.records(0)));
}

TEST(LocalizationChain, ItsMessagesRecordedAndPlayedBackDriveALocalizerToTheSameEstimates) {
  // A simulation and a recording are two sources of the same streams: what the chain's bus
  // delivered, kept and played onto a recording's bus (receipt order), drives a second AMCL built
  // the same way to the very estimates the chain's own gave at every scan.
  ScenarioSpec spec = load_scenario(scenario_path("amcl_indoor.yaml"));
  spec.duration_s = 8.0;
  Simulation sim(spec);
  LocalizationChain chain(sim, localization_config(spec));
  const auto route = make_route_drive(sim);
  std::vector<SensorMessage> recorded;
  chain.bus().subscribe<OdometryMessage>("", [&](const OdometryMessage& m) { recorded.emplace_back(m); });
  chain.bus().subscribe<ImuMessage>("", [&](const ImuMessage& m) { recorded.emplace_back(m); });
  chain.bus().subscribe<ScanMessage>("", [&](const ScanMessage& m) { recorded.emplace_back(m); });
  sim.run();
  std::size_t odometry = 0, scans = 0;
  for (const SensorMessage& m : recorded) {
    odometry += std::holds_alternative<OdometryMessage>(m) ? 1 : 0;
    scans += std::holds_alternative<ScanMessage>(m) ? 1 : 0;
  }
  ASSERT_GT(odometry, 100u);
  ASSERT_GT(scans, 10u);

  const std::unique_ptr<Localizer> replayed = find_localizer("amcl").make(chain.context(), chain.config().localizer.settings);
  SensorBus bus(SensorBus::Order::Receipt);
  std::vector<PoseEstimate> at_scans;
  bus.subscribe<OdometryMessage>(kOdometryStream, [&](const OdometryMessage& m) { replayed->on_odometry(m); });
  bus.subscribe<ImuMessage>(kImuStream, [&](const ImuMessage& m) { replayed->on_imu(m); });
  bus.subscribe<ScanMessage>("lidar", [&](const ScanMessage& m) {
    replayed->on_scan(m);
    at_scans.push_back(replayed->estimate());
  });
  for (const SensorMessage& m : recorded) bus.publish(m);
  bus.deliver_all();
  std::vector<PoseEstimate> chain_scans;
  for (const EstimateRecord& r : chain.records(0))
    if (r.scan) chain_scans.push_back(r.estimate);
  ASSERT_EQ(at_scans.size(), chain_scans.size());
  for (std::size_t i = 0; i < at_scans.size(); ++i) {
    EXPECT_EQ(at_scans[i].pose.x, chain_scans[i].pose.x) << i;
    EXPECT_EQ(at_scans[i].pose.y, chain_scans[i].pose.y) << i;
    EXPECT_EQ(at_scans[i].pose.yaw, chain_scans[i].pose.yaw) << i;
    EXPECT_EQ(at_scans[i].updates, chain_scans[i].updates) << i;
  }
  EXPECT_GT(at_scans.back().updates, 3);
}

TEST(LocalizationChain, FusedOdometryFeedsTheLocalizer) {
  ScenarioSpec spec = load_scenario(scenario_path("ekf_square.yaml"), std::vector<ScenarioOverride>{
      {"localization.odometry", "ekf"}, {"localization.localizer", "odometry"}, {"sim.duration_s", "120"}});
  Simulation sim(spec);
  LocalizationChain chain(sim, localization_config(spec));
  chain.add_localizer("ekf", {});  // unused here; proves extra localizers coexist with a filter
  sim.run();
  // The localizer (dead reckoning) reads the EKF's pose: its heading has the IMU's accuracy, not
  // the wheels' (about 0.5 deg after 120 s against about 1.5 deg).
  const EstimateRecord& last = chain.records(0).back();
  EXPECT_LT(std::abs(wrap_angle(last.estimate.pose.yaw - last.truth.yaw)), deg_to_rad(0.3));
}

TEST(LocalizationChain, AmclWithoutAMapIsOneErrorNamingTheField) {
  std::string text = test::read_text(scenario_path("ekf_square.yaml"));
  text.replace(text.find("localizer: ekf"), 14, "localizer: amcl");
  text.erase(text.find("  ekf:"), text.find("commands:") - text.find("  ekf:"));
  const ScenarioSpec spec = parse_scenario(text, scenario_path("no_map.yaml"));
  Simulation sim(spec);
  try {
    LocalizationChain chain(sim, localization_config(spec));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "localization.localizer") << e.what();
    EXPECT_NE(std::string(e.what()).find("needs a map"), std::string::npos) << e.what();
  }
}

// `odometry:` takes wheel, none, or a localizer that filters odometry (by capability, not by name);
// the errors list what it takes and name the field.
TEST(LocalizationChainConfig, OdometryTakesTheLocalizersThatFilterOdometry) {
  const auto error_of = [](std::vector<ScenarioOverride> overrides) {
    try {
      localization_config(load_scenario(scenario_path("ekf_square.yaml"), overrides));
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "localization.odometry (--set)") << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({{"localization.odometry", "amcl"}}).find("unknown odometry 'amcl' (wheel, none, ekf)"), std::string::npos);
  EXPECT_NE(error_of({{"localization.odometry", "ekf"}}).find("the ekf would run twice"), std::string::npos);
  const LocalizationConfig c =
      localization_config(load_scenario(scenario_path("ekf_square.yaml"), std::vector<ScenarioOverride>{
          {"localization.odometry", "ekf"}, {"localization.localizer", "odometry"}}));
  EXPECT_EQ(c.odometry, "wheel");
  ASSERT_TRUE(c.odometry_filter.has_value());
  EXPECT_EQ(c.odometry_filter->name, "ekf");
  EXPECT_EQ(localization_config(load_scenario(scenario_path("ekf_square.yaml"))).odometry_filter, std::nullopt);
}

}  // namespace
}  // namespace starnav
