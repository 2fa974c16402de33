// starnav export mcap: run records written as MCAP and read back by @mcap/core in
// tools/ros2-convert/check-mcap.mjs, every message decoded against its schema (Foxglove's JSON schemas
// with ajv; ROS 2 messages with @foxglove/rosmsg2-serialization); the ROS 2 export read back by
// starnav's own reader as a log; bad run folders refused in one line.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "support/ros2_convert.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(CliExportMcap, ARunReadsBackWithEveryMessageDecodingAgainstItsSchema) {
  const test::ScratchDir dir;
  // A simulated AMCL run: world, terrain-free indoor map, LiDAR, particles and estimates.
  const std::string run = dir.file("amcl");
  const test::CliResult sim = test::run_cli({"sim", test::scenario_path("amcl_indoor.yaml"), "--duration", "4", "--out", run, "--quiet"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string fox = dir.file("amcl.mcap"), ros2 = dir.file("amcl-ros2.mcap");
  const test::CliResult a = test::run_cli({"export", "mcap", run, fox, "--json"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto summary = nlohmann::json::parse(a.out);
  EXPECT_EQ(summary["topics"]["/particles"], summary["topics"]["/hits"]);
  const test::CliResult b = test::run_cli({"export", "mcap", run, ros2, "--ros2"});
  ASSERT_EQ(b.exit_code, 0) << b.err;

  // starnav's own reader: the ROS 2 export is a log whose scans are the run's steps (its /tf is
  // map -> base_link, the run's own pose, not an odometry).
  const test::CliResult info = test::run_cli({"log", "info", ros2, "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto log = nlohmann::json::parse(info.out);
  EXPECT_EQ(log["scans"], summary["topics"]["/scan"]);
  EXPECT_EQ(log["odometry"], 0);

  if (!test::have_ros2_tools()) GTEST_SKIP() << "needs Node.js and tools/ros2-convert's npm packages";
  const test::CliResult fox_check = test::run_ros2_tool("check-mcap.mjs", {fox});
  ASSERT_EQ(fox_check.exit_code, 0) << fox_check.err;
  const auto f = nlohmann::json::parse(fox_check.out);
  for (const char* topic : {"/world", "/tf", "/trajectory", "/hits", "/scan", "/particles", "/estimate"}) {
    ASSERT_TRUE(f["topics"].contains(topic)) << topic << " " << fox_check.out;
    EXPECT_GT(f["topics"][topic]["messages"].get<int>(), 0) << topic;
    EXPECT_EQ(f["topics"][topic]["encoding"], "jsonschema") << topic;
  }
  EXPECT_EQ(f["topics"]["/world"]["schema"], "foxglove.SceneUpdate");
  EXPECT_EQ(f["topics"]["/hits"]["schema"], "foxglove.PointCloud");
  EXPECT_EQ(f["messages"], summary["messages"]);
  const test::CliResult ros2_check = test::run_ros2_tool("check-mcap.mjs", {ros2});
  ASSERT_EQ(ros2_check.exit_code, 0) << ros2_check.err;
  const auto r = nlohmann::json::parse(ros2_check.out);
  EXPECT_EQ(r["topics"]["/scan"]["schema"], "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(r["topics"]["/tf"]["schema"], "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(r["topics"]["/trajectory"]["schema"], "nav_msgs/msg/Path");
}

TEST(CliExportMcap, ANavigationRunWithMovingObstaclesPlansAndMaps) {
  if (!test::have_ros2_tools()) GTEST_SKIP() << "needs Node.js and tools/ros2-convert's npm packages";
  const test::ScratchDir dir;
  // The small navigation world with a box that appears on the way (E4's kind of obstacle, in a run
  // of a second instead of a minute).
  test::write_text(dir.file("nav.yaml"),
                   test::small_nav_scenario(test::kSmallNavWall +
                                            "    - {name: late, kind: box, position_m: [4.5, 3.2], size_m: [0.3, 0.3, 0.5], appear_s: 3.0}\n"));
  const std::string run = dir.file("nav");
  const test::CliResult sim = test::run_cli({"sim", dir.file("nav.yaml"), "--out", run, "--quiet"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  for (const bool ros2 : {false, true}) {
    const std::string out = dir.file(ros2 ? "nav-ros2.mcap" : "nav.mcap");
    std::vector<std::string> args = {"export", "mcap", run, out};
    if (ros2) args.push_back("--ros2");
    const test::CliResult e = test::run_cli(args);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    const test::CliResult c = test::run_ros2_tool("check-mcap.mjs", {out});
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const auto j = nlohmann::json::parse(c.out);
    EXPECT_GT(j["topics"]["/plan"]["messages"].get<int>(), 0) << c.out;
    EXPECT_EQ(j["topics"]["/map"]["messages"], 2) << c.out;  // the navigation grid at the start and the end
    if (!ros2) {
      EXPECT_GT(j["topics"]["/world"]["messages"].get<int>(), 1) << c.out;  // moving obstacles: one update per step
    }
  }
}

TEST(CliExportMcap, BadRunFoldersAndOutputsAreRefusedInOneLine) {
  const test::ScratchDir dir;
  test::write_text(dir.file("exists.mcap"), "x");
  struct Row {
    std::vector<std::string> args;
    std::string expect;
  };
  for (const Row& r : {Row{{"export", "mcap", dir.path().string(), dir.file("o.mcap")}, "run.json"},
                       Row{{"export", "mcap", dir.file("none"), dir.file("o.mcap")}, "none"},
                       Row{{"export", "mcap", dir.path().string(), dir.file("exists.mcap")}, "exists already"}}) {
    const test::CliResult c = test::run_cli(r.args);
    EXPECT_EQ(c.exit_code, 2) << r.expect;
    EXPECT_NE(c.err.find(r.expect), std::string::npos) << c.err;
    EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
  }
}

}  // namespace
}  // namespace starnav
