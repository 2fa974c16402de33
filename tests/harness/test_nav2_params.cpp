// Nav2 parameter files (harness/nav2_params.hpp): Nav2's shipped nav2_params.yaml (tests/data/nav2)
// leaves no amcl, inflation or controller key unaccounted for; each conversion on hand-written
// files; values out of range refused naming the file, the line and both keys.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <set>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/nav2_params.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// Every leaf key under NODE's ros__parameters, dotted, read here with yaml-cpp on its own.
void leaves(const YAML::Node& n, const std::string& prefix, std::set<std::string>& out) {
  for (const auto& kv : n) {
    const std::string key = prefix + "." + kv.first.Scalar();
    if (kv.second.IsMap()) leaves(kv.second, key, out);
    else out.insert(key);
  }
}

std::map<std::string, const Nav2Key*> by_name(const std::vector<Nav2Key>& keys) {
  std::map<std::string, const Nav2Key*> m;
  for (const Nav2Key& k : keys) m[k.nav2] = &k;
  return m;
}

Nav2Target scenario(const std::string& localizer, const std::string& controller) {
  Nav2Target t;
  t.navigation = true;
  t.localizer = localizer;
  t.controller = controller;
  return t;
}

TEST(Nav2Params, TheShippedFileLeavesNoAmclInflationOrControllerKeyUnaccountedFor) {
  const std::string file = test::test_data("nav2/nav2_params.yaml");
  const YAML::Node root = YAML::LoadFile(file);
  std::set<std::string> amcl, controller, inflation;
  leaves(root["amcl"]["ros__parameters"], "amcl", amcl);
  leaves(root["controller_server"]["ros__parameters"], "controller_server", controller);
  for (const char* c : {"local_costmap", "global_costmap"}) {
    std::set<std::string> all;
    leaves(root[c][c]["ros__parameters"], c, all);
    for (const std::string& k : all)
      if (k.find("inflation") != std::string::npos || k.find("robot_radius") != std::string::npos) inflation.insert(k);
  }
  ASSERT_GT(amcl.size(), 30u);
  ASSERT_GT(controller.size(), 50u);
  for (const Nav2Target& target : {scenario("amcl", "dwa"), scenario("amcl", "path_follower"), Nav2Target{Nav2Target::Kind::Localize, false, "", ""}}) {
    const Nav2Params p = read_nav2_params(file, target);
    const auto mapped = by_name(p.mapped), ignored = by_name(p.ignored);
    for (const auto* set : {&amcl, &controller, &inflation})
      for (const std::string& k : *set) {
        const bool m = mapped.count(k) > 0, i = ignored.count(k) > 0;
        EXPECT_TRUE(m != i) << k << " is " << (m ? "mapped and ignored" : "neither mapped nor ignored");
        if (i) {
          EXPECT_FALSE(ignored.at(k)->note.empty()) << k << " ignored without a reason";
        }
      }
    // Nothing mapped that the file does not hold, each at its line.
    for (const Nav2Key& k : p.mapped) {
      EXPECT_GT(k.line, 0) << k.nav2;
      EXPECT_FALSE(k.starnav.empty()) << k.nav2;
    }
    // AMCL: the same keys map whatever the target, to its section.
    const std::string root_key = target.kind == Nav2Target::Kind::Localize ? "amcl." : "localization.amcl.";
    ASSERT_TRUE(mapped.count("amcl.update_min_a"));
    EXPECT_EQ(mapped.at("amcl.update_min_a")->starnav, root_key + "update_min_a_deg");
    EXPECT_NEAR(std::stod(mapped.at("amcl.update_min_a")->converted), rad_to_deg(0.2), 1e-12);
    EXPECT_EQ(mapped.at("amcl.sigma_hit")->starnav, root_key + "sigma_hit_m");
    EXPECT_EQ(mapped.at("amcl.robot_model_type")->converted, "differential");
    EXPECT_EQ(mapped.at("amcl.max_particles")->converted, "2000");
    EXPECT_TRUE(ignored.count("amcl.laser_min_range"));  // -1: the laser's own
    EXPECT_TRUE(ignored.count("amcl.base_frame_id"));
    if (target.kind == Nav2Target::Kind::Scenario) {
      // The shipped controller is MPPI: starnav has none, so its keys are ignored and say so.
      EXPECT_NE(ignored.at("controller_server.FollowPath.vx_max")->note.find("MPPI"), std::string::npos);
      EXPECT_EQ(mapped.at("controller_server.general_goal_checker.xy_goal_tolerance")->starnav, "navigation.goal_tolerance_m");
      EXPECT_NEAR(std::stod(mapped.at("controller_server.general_goal_checker.yaw_goal_tolerance")->converted), rad_to_deg(0.25), 1e-12);
      EXPECT_EQ(mapped.at("global_costmap.robot_radius")->starnav, "navigation.map.barrier_distance_m");
      if (target.controller == "dwa") {
        EXPECT_EQ(mapped.at("local_costmap.inflation_layer.inflation_radius")->starnav, "navigation.dwa.inflation_radius_m");
        EXPECT_EQ(mapped.at("local_costmap.inflation_layer.cost_scaling_factor")->converted, "3");
        EXPECT_NEAR(std::stod(mapped.at("controller_server.controller_frequency")->converted), 0.05, 1e-15);
      } else {
        EXPECT_NE(ignored.at("local_costmap.inflation_layer.inflation_radius")->note.find("path_follower"), std::string::npos);
      }
    } else {
      EXPECT_EQ(ignored.at("controller_server.general_goal_checker.xy_goal_tolerance")->note, "localize runs AMCL only");
    }
  }
  // A scenario whose localizer is not AMCL: the amcl keys are ignored with that reason.
  const Nav2Params ekf = read_nav2_params(file, scenario("ekf", "dwa"));
  EXPECT_NE(by_name(ekf.ignored).at("amcl.alpha1")->note.find("ekf, not amcl"), std::string::npos);
}

// With the scenario's controller mppi, the shipped file's MPPI keys map onto it by its declared
// keys (critics' namespaces in snake_case, units' suffixes, radians to degrees), every key mapped
// or ignored with a reason.
TEST(Nav2Params, TheShippedMppiKeysMapOntoTheMppiController) {
  const std::string file = test::test_data("nav2/nav2_params.yaml");
  const YAML::Node root = YAML::LoadFile(file);
  std::set<std::string> controller;
  leaves(root["controller_server"]["ros__parameters"], "controller_server", controller);
  const Nav2Params p = read_nav2_params(file, scenario("amcl", "mppi"));
  const auto mapped = by_name(p.mapped), ignored = by_name(p.ignored);
  for (const std::string& k : controller) {
    EXPECT_TRUE((mapped.count(k) > 0) != (ignored.count(k) > 0)) << k;
    if (ignored.count(k)) {
      EXPECT_FALSE(ignored.at(k)->note.empty()) << k;
    }
  }
  const auto to = [&](const std::string& k) { return mapped.at("controller_server.FollowPath." + k)->starnav; };
  const auto value = [&](const std::string& k) { return std::stod(mapped.at("controller_server.FollowPath." + k)->converted); };
  EXPECT_EQ(to("vx_max"), "navigation.mppi.vx_max_mps");
  EXPECT_EQ(to("batch_size"), "navigation.mppi.batch_size");
  EXPECT_EQ(to("wz_std"), "navigation.mppi.wz_std_degps");
  EXPECT_NEAR(value("wz_std"), rad_to_deg(0.4), 1e-9);
  EXPECT_EQ(to("GoalCritic.threshold_to_consider"), "navigation.mppi.goal.threshold_to_consider_m");
  EXPECT_EQ(to("PathAngleCritic.max_angle_to_furthest"), "navigation.mppi.path_angle.max_angle_to_furthest_deg");
  EXPECT_NEAR(value("PathAngleCritic.max_angle_to_furthest"), rad_to_deg(1.0), 1e-9);
  EXPECT_EQ(to("PathAlignCritic.cost_weight"), "navigation.mppi.path_align.cost_weight");
  EXPECT_EQ(to("TrajectoryValidator.collision_lookahead_time"), "navigation.mppi.trajectory_validator.collision_lookahead_time_s");
  EXPECT_EQ(mapped.at("controller_server.FollowPath.motion_model")->converted, "diff_drive");
  EXPECT_EQ(mapped.at("controller_server.FollowPath.critics")->converted,
            "[constraint, obstacles, goal, goal_angle, path_align, path_follow, path_angle, prefer_forward]");
  EXPECT_NEAR(std::stod(mapped.at("controller_server.controller_frequency")->converted), 0.05, 1e-15);
  EXPECT_NE(ignored.at("controller_server.FollowPath.CostCritic.critical_cost")->note.find("obstacles"), std::string::npos);
  // Every mapped value is one the controller takes: the settings build it.
  EXPECT_FALSE(p.settings().empty());
}

TEST(Nav2Params, EachConversionOnAHandWrittenFile) {
  const test::ScratchDir dir;
  const std::string file = dir.file("dwb.yaml");
  test::write_text(file,
                   "controller_server:\n"
                   "  ros__parameters:\n"
                   "    controller_frequency: 10.0\n"
                   "    FollowPath:\n"
                   "      plugin: \"dwb_core::DWBLocalPlanner\"\n"
                   "      max_vel_x: 0.4\n"
                   "      min_vel_x: -0.1\n"
                   "      max_vel_theta: 1.0\n"
                   "      acc_lim_theta: 2.0\n"
                   "      vx_samples: 15\n"
                   "      vtheta_samples: 25\n"
                   "      sim_time: 1.5\n"
                   "      critics: [\"RotateToGoal\", \"PathAlign\"]\n"
                   "      PathAlign.scale: 32.0\n"
                   "      RotateToGoal.scale: 40.0\n"
                   "      Oscillation.oscillation_reset_angle: 0.5\n"
                   "    goal_checker:\n"
                   "      plugin: \"nav2_controller::SimpleGoalChecker\"\n"
                   "      xy_goal_tolerance: 0.3\n"
                   "amcl:\n"
                   "  ros__parameters:\n"
                   "    laser_model_type: beam\n"
                   "    update_min_d: 0.1\n");
  const Nav2Params p = read_nav2_params(file, scenario("amcl", "dwa"));
  std::map<std::string, std::pair<std::string, std::string>> got;
  for (const Nav2Key& k : p.mapped) got[k.nav2] = {k.starnav, k.converted};
  using V = std::pair<std::string, std::string>;
  EXPECT_EQ(got["controller_server.controller_frequency"], V("navigation.dwa.control_period_s", "0.1"));
  EXPECT_EQ(got["controller_server.FollowPath.max_vel_x"], V("navigation.dwa.max_vx_mps", "0.4"));
  EXPECT_EQ(got["controller_server.FollowPath.min_vel_x"], V("navigation.dwa.min_vx_mps", "-0.1"));
  EXPECT_EQ(got["controller_server.FollowPath.max_vel_theta"].first, "navigation.dwa.max_yaw_rate_degps");
  EXPECT_DOUBLE_EQ(std::stod(got["controller_server.FollowPath.max_vel_theta"].second), 180.0 / kPi);
  EXPECT_DOUBLE_EQ(std::stod(got["controller_server.FollowPath.acc_lim_theta"].second), 360.0 / kPi);
  EXPECT_EQ(got["controller_server.FollowPath.vx_samples"], V("navigation.dwa.vx_samples", "15"));
  EXPECT_EQ(got["controller_server.FollowPath.vtheta_samples"], V("navigation.dwa.wz_samples", "25"));
  EXPECT_EQ(got["controller_server.FollowPath.sim_time"], V("navigation.dwa.sim_time_s", "1.5"));
  EXPECT_EQ(got["controller_server.FollowPath.PathAlign.scale"], V("navigation.dwa.path_align_weight", "32"));
  EXPECT_EQ(got["controller_server.FollowPath.RotateToGoal.scale"], V("navigation.dwa.rotate_to_goal_weight", "40"));
  EXPECT_DOUBLE_EQ(std::stod(got["controller_server.FollowPath.Oscillation.oscillation_reset_angle"].second), rad_to_deg(0.5));
  EXPECT_EQ(got["controller_server.goal_checker.xy_goal_tolerance"], V("navigation.goal_tolerance_m", "0.3"));
  EXPECT_EQ(got["amcl.laser_model_type"], V("localization.amcl.laser_model_type", "beam"));
  EXPECT_EQ(got["amcl.update_min_d"], V("localization.amcl.update_min_d_m", "0.1"));
  // The settings carry the file and line for errors.
  for (const ParamSetting& s : p.settings()) {
    EXPECT_EQ(s.file, file);
    EXPECT_GT(s.line, 0);
  }

  // Regulated Pure Pursuit on the path follower.
  test::write_text(dir.file("rpp.yaml"),
                   "controller_server:\n  ros__parameters:\n    FollowPath:\n"
                   "      plugin: \"nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController\"\n"
                   "      desired_linear_vel: 0.5\n      lookahead_dist: 0.6\n      rotate_to_heading_angular_vel: 1.8\n"
                   "      use_collision_detection: true\n");
  const Nav2Params rpp = read_nav2_params(dir.file("rpp.yaml"), scenario("", "path_follower"));
  std::map<std::string, std::pair<std::string, std::string>> r;
  for (const Nav2Key& k : rpp.mapped) r[k.nav2] = {k.starnav, k.converted};
  EXPECT_EQ(r["controller_server.FollowPath.desired_linear_vel"], V("navigation.follower.cruise_speed_mps", "0.5"));
  EXPECT_EQ(r["controller_server.FollowPath.lookahead_dist"], V("navigation.follower.pursuit_look_ahead_m", "0.6"));
  EXPECT_EQ(rpp.ignored.size(), 2u);  // the plugin line and use_collision_detection

  // The same file on the regulated_pure_pursuit component: every key is its own (unit suffixes,
  // radians to degrees), use_collision_detection included.
  const Nav2Params regulated = read_nav2_params(dir.file("rpp.yaml"), scenario("", "regulated_pure_pursuit"));
  r.clear();
  for (const Nav2Key& k : regulated.mapped) r[k.nav2] = {k.starnav, k.converted};
  EXPECT_EQ(r["controller_server.FollowPath.desired_linear_vel"], V("navigation.rpp.desired_linear_vel_mps", "0.5"));
  EXPECT_EQ(r["controller_server.FollowPath.lookahead_dist"], V("navigation.rpp.lookahead_dist_m", "0.6"));
  EXPECT_EQ(r["controller_server.FollowPath.use_collision_detection"], V("navigation.rpp.use_collision_detection", "true"));
  const auto& [degps_key, degps] = r["controller_server.FollowPath.rotate_to_heading_angular_vel"];
  EXPECT_EQ(degps_key, "navigation.rpp.rotate_to_heading_angular_vel_degps");
  EXPECT_NEAR(std::stod(degps), 1.8 * 180.0 / 3.14159265358979323846, 1e-9);
  EXPECT_EQ(regulated.ignored.size(), 1u);  // the plugin line
  std::size_t rpp_settings = 0;
  for (const ParamSetting& s : regulated.settings()) rpp_settings += s.key.rfind("navigation.rpp.", 0) == 0 ? 1 : 0;
  EXPECT_EQ(rpp_settings, 4u);

  // A key the component does not declare is ignored with its reason; a controller that does not
  // stand for pure pursuit takes none.
  test::write_text(dir.file("rpp2.yaml"),
                   "controller_server:\n  ros__parameters:\n    FollowPath:\n"
                   "      plugin: \"nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController\"\n"
                   "      inflation_cost_scaling_factor: 3.0\n      max_angular_accel: 3.2\n");
  const Nav2Params second = read_nav2_params(dir.file("rpp2.yaml"), scenario("", "regulated_pure_pursuit"));
  ASSERT_EQ(second.mapped.size(), 1u);
  EXPECT_EQ(second.mapped[0].starnav, "navigation.rpp.max_angular_accel_degps2");
  EXPECT_NEAR(std::stod(second.mapped[0].converted), 3.2 * 180.0 / 3.14159265358979323846, 1e-9);
  const Nav2Params on_dwa = read_nav2_params(dir.file("rpp2.yaml"), scenario("", "dwa"));
  EXPECT_TRUE(on_dwa.mapped.empty());
}

// A goal checker's own keys map onto the scenario's goal checker when it stands for that plugin
// (latching for SimpleGoalChecker, stopped for StoppedGoalChecker), in starnav's units; with the
// other checker they are ignored and say why.
TEST(Nav2Params, GoalCheckerKeysMapOntoTheCheckerThatStandsForThePlugin) {
  const test::ScratchDir dir;
  const std::string file = dir.file("checkers.yaml");
  test::write_text(file,
                   "controller_server:\n"
                   "  ros__parameters:\n"
                   "    simple_checker:\n"
                   "      plugin: \"nav2_controller::SimpleGoalChecker\"\n"
                   "      stateful: False\n"
                   "      xy_goal_tolerance: 0.1\n"
                   "    stopped_checker:\n"
                   "      plugin: \"nav2_controller::StoppedGoalChecker\"\n"
                   "      trans_stopped_velocity: 0.1\n"
                   "      rot_stopped_velocity: 0.5\n");
  Nav2Target latching = scenario("", "mppi");
  const Nav2Params a = read_nav2_params(file, latching);
  auto mapped = by_name(a.mapped), ignored = by_name(a.ignored);
  ASSERT_TRUE(mapped.count("controller_server.simple_checker.stateful"));
  EXPECT_EQ(mapped.at("controller_server.simple_checker.stateful")->starnav, "navigation.latching_goal_checker.stateful");
  EXPECT_EQ(mapped.at("controller_server.simple_checker.stateful")->converted, "false");
  EXPECT_EQ(mapped.at("controller_server.simple_checker.xy_goal_tolerance")->starnav, "navigation.goal_tolerance_m");
  ASSERT_TRUE(ignored.count("controller_server.stopped_checker.trans_stopped_velocity"));
  EXPECT_NE(ignored.at("controller_server.stopped_checker.trans_stopped_velocity")->note.find("latching, not one that stands for Nav2's StoppedGoalChecker"),
            std::string::npos);

  Nav2Target stopped = latching;
  stopped.goal_checker = "stopped";
  const Nav2Params b = read_nav2_params(file, stopped);
  mapped = by_name(b.mapped), ignored = by_name(b.ignored);
  EXPECT_TRUE(ignored.count("controller_server.simple_checker.stateful"));
  ASSERT_TRUE(mapped.count("controller_server.stopped_checker.rot_stopped_velocity"));
  EXPECT_EQ(mapped.at("controller_server.stopped_checker.trans_stopped_velocity")->starnav,
            "navigation.stopped_goal_checker.trans_stopped_velocity_mps");
  EXPECT_EQ(mapped.at("controller_server.stopped_checker.rot_stopped_velocity")->starnav,
            "navigation.stopped_goal_checker.rot_stopped_velocity_degps");
  EXPECT_NEAR(std::stod(mapped.at("controller_server.stopped_checker.rot_stopped_velocity")->converted), rad_to_deg(0.5), 1e-9);

  // A bool that is not one names the file, line and both keys.
  test::write_text(file, "controller_server:\n  ros__parameters:\n    checker:\n      plugin: \"nav2_controller::SimpleGoalChecker\"\n"
                         "      stateful: maybe\n");
  const std::string what = test::error_of([&] { read_nav2_params(file, latching); });
  EXPECT_NE(what.find("checkers.yaml:5:"), std::string::npos) << what;
  EXPECT_NE(what.find("expected true or false"), std::string::npos) << what;
  EXPECT_NE(what.find("navigation.latching_goal_checker.stateful"), std::string::npos) << what;
}

TEST(Nav2Params, ValuesOutOfRangeNameTheFileLineAndBothKeys) {
  const test::ScratchDir dir;
  struct Row {
    std::string yaml, expect;
    int line;
  };
  for (const Row& r : {Row{"amcl:\n  ros__parameters:\n    alpha1: 0.2\n    update_min_a: 7.0\n", "amcl.update_min_a (localization.amcl.update_min_a_deg)", 4},
                       Row{"amcl:\n  ros__parameters:\n    z_hit: 1.5\n", "amcl.z_hit (localization.amcl.z_hit)", 3},
                       Row{"amcl:\n  ros__parameters:\n    max_particles: 10.5\n", "expected an integer", 3},
                       Row{"amcl:\n  ros__parameters:\n    sigma_hit: fast\n", "expected a number", 3},
                       Row{"amcl: [1, 2]\n", "not a Nav2 parameter file", 0},
                       Row{"amcl:\n  ros__parameters: {alpha1: [\n", "not YAML", 0}}) {
    const std::string file = dir.file("bad.yaml");
    test::write_text(file, r.yaml);
    const std::string what = test::error_of([&] { read_nav2_params(file, scenario("amcl", "dwa")); });
    EXPECT_NE(what.find(r.expect), std::string::npos) << what;
    if (r.line > 0) {
      EXPECT_NE(what.find("bad.yaml:" + std::to_string(r.line) + ":"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace starnav
