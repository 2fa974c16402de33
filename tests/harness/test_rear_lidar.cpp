// A second 2D LiDAR declared in a scenario (sensors.lidars.rear): its scans reach the navigation
// map's obstacle layer and AMCL. Without it the same robot sees only its front half-circle: the
// cells behind it stay unobserved and AMCL makes half the updates.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

std::string scenario_text() {
  std::ifstream in(test::scenario_path("rear_lidar_indoor.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The scenario without its rear LiDAR.
std::string without_rear(std::string text) {
  const std::size_t a = text.find("  lidars:\n");
  const std::size_t b = text.find("  imu:");
  text.erase(a, b - a);
  return text;
}

TEST(RearLidar, FeedsTheObstacleLayerAndAmcl) {
  const std::string file = test::scenario_path("rear_lidar_indoor.yaml");
  int updates[2] = {0, 0};
  int behind_observed[2] = {0, 0};
  for (int with_rear = 0; with_rear < 2; ++with_rear) {
    SCOPED_TRACE(with_rear ? "with the rear LiDAR" : "front only");
    const ScenarioSpec spec = parse_scenario(with_rear ? scenario_text() : without_rear(scenario_text()), file);
    ASSERT_EQ(spec.other_lidars.size(), static_cast<std::size_t>(with_rear));
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun run(spec, o);
    // After the first scans, the cells more than 0.3 m behind the start (facing +x) are seen
    // only from the rear.
    run.simulation().step();
    const LayeredCostmap& map = run.navigator().map();
    int behind = 0;
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x)
        if (map.observed(x, y) && map.geometry().cell_center(x, y).x() < spec.start.x - 0.3) ++behind;
    behind_observed[with_rear] = behind;
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
    EXPECT_EQ(m.collisions, 0);
    const PoseEstimate e = run.localizer().estimate();
    const Pose2 truth = run.simulation().vehicle().state().pose.to_pose2();
    EXPECT_LT(std::hypot(e.pose.x - truth.x, e.pose.y - truth.y), 0.1);
    updates[with_rear] = e.updates;
  }
  EXPECT_EQ(behind_observed[0], 0);
  EXPECT_GT(behind_observed[1], 20);
  // Each motion step weighed by both scanners.
  EXPECT_GT(updates[1], 1.7 * updates[0]);
}

TEST(RearLidar, DeclarationErrorsNameTheField) {
  const std::string text = scenario_text();
  const auto refused = [&](const std::string& from, const std::string& to, const std::string& field) {
    std::string bad = text;
    bad.replace(bad.find(from), from.size(), to);
    try {
      parse_scenario(bad, "bad.yaml");
      ADD_FAILURE() << "accepted " << to;
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "bad.yaml");
      EXPECT_GT(e.line(), 0) << e.what();
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  refused("    rear:", "    Rear:", "sensors.lidars.Rear");
  refused("      rate_hz: 10.0\n      mount: {x_m: -0.2", "      rate_hz: 1000.0\n      mount: {x_m: -0.2", "sensors.lidars.rear.rate_hz");
  refused("    rear:", "    lidar:", "sensors.lidars.lidar");
}

}  // namespace
}  // namespace starnav
