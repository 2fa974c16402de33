// --params NAV2_PARAMS.yaml on sim and localize, and `starnav params --nav2`: a run with a Nav2 file
// equals the same run with the equivalent --set values, byte for byte; Nav2's shipped file lists
// its mapping; a value out of range is one error line naming the file, line and both keys.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(CliNav2Params, AMappedRunEqualsTheRunWithTheEquivalentSets) {
  const test::ScratchDir dir;
  const std::string nav2 = dir.file("dwb.yaml");
  test::write_text(nav2,
                   "controller_server:\n  ros__parameters:\n    FollowPath:\n      plugin: dwb_core::DWBLocalPlanner\n"
                   "      max_vel_x: 0.35\n      max_vel_theta: 1.2\n      PathDist.scale: 40.0\n"
                   "local_costmap:\n  local_costmap:\n    ros__parameters:\n      inflation_layer:\n"
                   "        plugin: nav2_costmap_2d::InflationLayer\n        inflation_radius: 0.45\n");
  const std::string scenario = test::scenario_path("dwa_doorway.yaml");
  const auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"sim", scenario, "--duration", "6", "--out", dir.file(name), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const test::CliResult r = test::run_cli(args);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;  // 1: not arrived within 6 s
    return test::read_text(dir.file(name) + "/trajectory.csv");
  };
  const std::string mapped = run("mapped", {"--params", nav2});
  const std::string set = run("set", {"--set", "navigation.dwa.max_vx_mps=0.35", "--set", "navigation.dwa.max_yaw_rate_degps=68.75493541569878",
                                      "--set", "navigation.dwa.path_dist_weight=40", "--set", "navigation.dwa.inflation_radius_m=0.45"});
  const std::string plain = run("plain", {});
  ASSERT_FALSE(mapped.empty());
  EXPECT_EQ(mapped, set);
  EXPECT_NE(mapped, plain);  // the settings changed the run
  // --set after --params wins.
  EXPECT_EQ(run("both", {"--params", nav2, "--set", "navigation.dwa.max_vx_mps=0.5"}),
            run("set2", {"--set", "navigation.dwa.max_vx_mps=0.5", "--set", "navigation.dwa.max_yaw_rate_degps=68.75493541569878",
                         "--set", "navigation.dwa.path_dist_weight=40", "--set", "navigation.dwa.inflation_radius_m=0.45"}));
}

TEST(CliNav2Params, TheShippedFileAndErrors) {
  const std::string shipped = test::test_data("nav2/nav2_params.yaml");
  const test::CliResult list = test::run_cli({"params", "--nav2", shipped, "--json"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  const auto j = nlohmann::json::parse(list.out);
  EXPECT_GT(j["mapped"].size(), 20u);
  EXPECT_GT(j["ignored"].size(), 100u);
  const test::CliResult text = test::run_cli({"params", "--nav2", shipped, "--scenario", test::scenario_path("amcl_indoor.yaml")});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("mapped  amcl.update_min_a = 0.2  ->  localization.amcl.update_min_a_deg = 11.459155902616466  (rad -> deg)"),
            std::string::npos)
      << text.out;

  const test::ScratchDir dir;
  test::write_text(dir.file("bad.yaml"), "amcl:\n  ros__parameters:\n    update_min_a: 7.0\n");
  const test::CliResult bad = test::run_cli({"sim", test::scenario_path("amcl_indoor.yaml"), "--params", dir.file("bad.yaml"), "--out", dir.file("o")});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.yaml:3: amcl.update_min_a (localization.amcl.update_min_a_deg): 7.0"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

}  // namespace
}  // namespace starnav
