// starnav log info: the summary of a log in text and JSON, and one error line (file, line, field)
// with exit 2 for a malformed log, a directory and a device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/io/ros_map.hpp"
#include "starnav/logs/log_file.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(CliLog, InfoSummarisesALogAndRefusesBadOnesInOneLine) {
  const test::ScratchDir dir;
  const std::string log = dir.file("run.clf");
  test::write_text(log,
                   "PARAM robot_frontlaser_offset 0.1 h 0\n"
                   "ODOM 0 0 0 0 0 0 1.000000 h 0\n"
                   "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1.500000 h 0\n"
                   "ODOM 1 0 0 0 0 0 2.000000 h 0\nSYNC x\n");
  const test::CliResult text = test::run_cli({"log", "info", log});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("scans:      1 of 3 beams"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("skipped:    1 x SYNC"), std::string::npos) << text.out;
  const test::CliResult js = test::run_cli({"log", "info", log, "--json"});
  ASSERT_EQ(js.exit_code, 0) << js.err;
  const auto j = nlohmann::json::parse(js.out);
  EXPECT_EQ(j["odometry"], 2);
  EXPECT_EQ(j["first_stamp"], "1.000000");
  EXPECT_DOUBLE_EQ(j["laser_in_base"]["x_m"].get<double>(), 0.1);

  test::write_text(dir.file("bad.clf"), "ODOM 0 0 0 0 0 0 1.0 h 0\nFLASER 2 1.0 oops 0 0 0 0 0 0 1.5 h 0\n");
  struct Row {
    std::vector<std::string> args;
    std::string expect;
  };
  for (const Row& r : {Row{{"log", "info", dir.file("bad.clf")}, "bad.clf:2: FLASER range: expected a finite number, got 'oops'"},
                       Row{{"log", "info", dir.path().string()}, "is a directory"},
                       Row{{"log", "info", "/dev/null"}, "not a regular file"},
                       Row{{"log", "info", log, "--range-max", "-1"}, "--range-max"}}) {
    const test::CliResult c = test::run_cli(r.args);
    EXPECT_EQ(c.exit_code, 2) << r.expect;
    EXPECT_NE(c.err.find(r.expect), std::string::npos) << c.err;
    EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
  }
}

TEST(CliMapBuild, MapsALogWithKnownPosesIntoAMapServerMap) {
  const test::ScratchDir dir;
  std::string log = "PARAM robot_frontlaser_offset 0.0 h 0\n";
  for (int i = 0; i < 4; ++i) {
    // A wall 2 m ahead of a robot standing at the origin, seen in 5 beams over the front half-plane.
    log += "FLASER 5 2.0 2.1 2.2 2.1 2.0 0 0 0 0 0 0 " + std::to_string(i) + ".000000 h 0\n";
  }
  test::write_text(dir.file("wall.clf"), log);
  const std::string out = dir.file("wall.yaml");
  const test::CliResult r = test::run_cli({"map", "build", dir.file("wall.clf"), "--out", out, "--json", "--resolution", "0.1",
                                           "--set", "hit_probability=0.8", "--trajectory-out", dir.file("traj.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["scans_mapped"], 4);
  EXPECT_GE(j["occupied"].get<int>(), 5);
  EXPECT_TRUE(test::fs::exists(dir.file("wall.pgm")));
  const test::CliResult info = test::run_cli({"map", "info", out, "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(test::read_text(dir.file("traj.csv")).substr(0, 29), "t_s,x_m,y_m,yaw_rad\n0.000000,");
  // The outputs exist now: without --force, refused before any work.
  const test::CliResult again = test::run_cli({"map", "build", dir.file("wall.clf"), "--out", out});
  EXPECT_EQ(again.exit_code, 2);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"map", "build", dir.file("wall.clf"), "--out", dir.file("b.yaml"), "--poses", dir.file("none.csv")},
        std::vector<std::string>{"map", "build", dir.file("wall.clf"), "--out", dir.file("b.yaml"), "--set", "hit_probability=2"},
        std::vector<std::string>{"map", "build", dir.file("wall.clf"), "--out", dir.file("b.yaml"), "--set", "bogus=1"},
        std::vector<std::string>{"map", "build", dir.file("wall.clf"), "--out", dir.file("b.yaml"), "--poses", "truth"}}) {
    const test::CliResult c = test::run_cli(args);
    EXPECT_EQ(c.exit_code, 2) << args.back();
    EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
  }
}

TEST(CliSlam, RunWritesATrajectoryPerScanAndEvalReadsIt) {
  const test::ScratchDir dir;
  std::string log;
  for (int i = 0; i < 6; ++i)
    log += "ODOM " + std::to_string(0.01 * i) + " 0 0 0 0 0 " + std::to_string(i) + ".000000 h 0\n" +
           "FLASER 5 2.0 2.1 2.2 2.1 2.0 0 0 0 0 0 0 " + std::to_string(i) + ".500000 h 0\n";
  test::write_text(dir.file("run.clf"), log);
  test::write_text(dir.file("r.relations"), "0.500000 5.500000 0.05 0 0 0 0 0\n");
  const test::CliResult r = test::run_cli({"slam", "run", dir.file("run.clf"), "--out", dir.file("out"), "--json", "--quiet",
                                           "--relations", dir.file("r.relations")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["poses"], 6);
  EXPECT_EQ(j["rpe_base"]["count"], 1);
  for (const char* f : {"map.yaml", "map.pgm", "pose_graph.json", "map.png", "summary.json", "steps.jsonl", "world.json", "run.json"})
    EXPECT_TRUE(std::filesystem::exists(dir.file(std::string("out/") + f))) << f;
  const auto graph = nlohmann::json::parse(test::read_text(dir.file("out/pose_graph.json")));
  EXPECT_EQ(graph["nodes"].size(), j["nodes"].get<std::size_t>());
  const std::string traj = test::read_text(dir.file("out/trajectory.csv"));
  EXPECT_EQ(std::count(traj.begin(), traj.end(), '\n'), 7);
  const test::CliResult e = test::run_cli({"slam", "eval", dir.file("out/trajectory.csv"), dir.file("r.relations"), "--json"});
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_EQ(nlohmann::json::parse(e.out)["base"]["translation_m"]["count"], 1);
  EXPECT_EQ(test::run_cli({"slam", "run", dir.file("run.clf"), "--out", dir.file("out")}).exit_code, 2);  // results there
  EXPECT_EQ(test::run_cli({"slam", "run", dir.file("run.clf"), "--out", dir.file("o2"), "--set", "local.window_nodes=0"}).exit_code, 2);
  EXPECT_EQ(test::run_cli({"slam", "eval", dir.file("run.clf"), dir.file("r.relations")}).exit_code, 2);
}

// The simulator records a CARMEN log of a run in a map world; SLAM maps it with its ground truth
// beside; the wall distances of the built map against the world's map come out small.
TEST(CliSimLog, SimWritesALogThatSlamMapsAgainstTheTruth) {
  const test::ScratchDir dir;
  OccupancyGrid g(GridGeometry{120, 80, 0.05, {}}, 0);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 120; ++x)
      if (x < 2 || y < 2 || x >= 118 || y >= 78 || (x >= 70 && x < 80 && y >= 30 && y < 40)) g(x, y) = 100;
  write_ros_map(g, dir.file("room.yaml"));
  test::write_text(dir.file("s.yaml"), R"(name: room
world:
  occupancy_map: room.yaml
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 20.0}
sensors:
  lidar: {preset: hokuyo_utm30lx, rate_hz: 10.0, mount: {x_m: 0.1, y_m: 0.0, z_m: 0.4}, noise_sigma_m: 0.005}
  encoders: {rate_hz: 50.0, ticks_per_rev: 1024, slip_sigma: 0.05}
sim: {dt_s: 0.01, seed: 1}
commands:
  - {duration_s: 6.0, vx_mps: 0.4, vy_mps: 0.0, wz_radps: 0.05}
)");
  const test::CliResult sim = test::run_cli({"sim", dir.file("s.yaml"), "--out", dir.file("run"), "--quiet"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_NE(sim.out.find("log.clf"), std::string::npos);
  const test::CliResult info = test::run_cli({"log", "info", dir.file("run/log.clf"), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto li = nlohmann::json::parse(info.out);
  EXPECT_EQ(li["scans"], 61);  // 6 s at 10 Hz and the scan at 0
  EXPECT_EQ(li["truth"], 61);
  const test::CliResult slam = test::run_cli({"slam", "run", dir.file("run/log.clf"), "--out", dir.file("slam"), "--json", "--quiet"});
  ASSERT_EQ(slam.exit_code, 0) << slam.err;
  const auto j = nlohmann::json::parse(slam.out);
  EXPECT_LT(j["ate"]["rmse_m"].get<double>(), 0.04);
  EXPECT_LT(j["ate"]["rotation_deg"]["mean"].get<double>(), 0.3);
  EXPECT_GT(j["ate_odometry"]["rotation_deg"]["mean"].get<double>(), j["ate"]["rotation_deg"]["mean"].get<double>());
  const test::CliResult walls = test::run_cli({"slam", "walls", dir.file("room.yaml"), dir.file("slam/map.yaml"), "--json"});
  ASSERT_EQ(walls.exit_code, 0) << walls.err;
  const auto w = nlohmann::json::parse(walls.out);
  EXPECT_GE(w["distances"].size(), 6u);
  EXPECT_LT(w["mean_abs_error_m"][0].get<double>(), 0.06);
}

// The benchmark of scale end to end on a short drive: make-benchmark writes a building and its
// scenario, `starnav sim` drives the start of the route (cut to 20 s) into log.clf, the log reader
// reads it back (scans of the LMS151 at 5 Hz, truth at each), `slam relations` makes a relation
// file from its truth that `slam eval` scores zero against that truth, and bench slam runs it by name.
TEST(CliSlamBenchmark, AShortRouteOfAGeneratedBuildingReadsBackAndIsBenchmarked) {
  const test::ScratchDir dir;
  const test::CliResult make = test::run_cli({"slam", "make-benchmark", "--kind", "ladder", "--seed", "3", "--length-km", "0.05",
                                              "--out", dir.file("b"), "--json"});
  ASSERT_EQ(make.exit_code, 0) << make.err;
  const auto m = nlohmann::json::parse(make.out);
  EXPECT_EQ(m["name"], "building_ladder_3");
  EXPECT_GE(m["size_m"][0].get<double>(), 150.0);
  EXPECT_GE(m["size_m"][1].get<double>(), 80.0);
  EXPECT_EQ(m["loops"], 6);
  EXPECT_EQ(test::run_cli({"slam", "make-benchmark", "--kind", "ladder", "--seed", "3", "--out", dir.file("b")}).exit_code, 2);  // exists
  EXPECT_EQ(test::run_cli({"slam", "make-benchmark", "--kind", "castle", "--out", dir.file("c")}).exit_code, 2);
  const test::CliResult shut = test::run_cli({"slam", "make-benchmark", "--shut-doors", "1.5", "--out", dir.file("c")});
  EXPECT_EQ(shut.exit_code, 2);
  EXPECT_NE(shut.err.find("--shut-doors"), std::string::npos) << shut.err;
  const std::string run = dir.file("b/building_ladder_3");
  const test::CliResult sim = test::run_cli({"sim", dir.file("b/building_ladder_3.yaml"), "--out", run, "--duration", "20", "--quiet"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const RobotLog log = read_robot_log(run + "/log.clf");
  EXPECT_EQ(log.scans.size(), 101u);  // 20 s at 5 Hz and the scan at 0
  EXPECT_EQ(log.truth.size(), log.scans.size());
  ASSERT_FALSE(log.scans.empty());
  EXPECT_EQ(log.scans[0].ranges_m.size(), 541u);
  ASSERT_TRUE(log.laser_in_base.has_value());
  EXPECT_DOUBLE_EQ(log.laser_in_base->x, 0.12);
  const Pose2 last = log.truth.back().pose;
  EXPECT_GT(std::hypot(last.x - log.truth.front().pose.x, last.y - log.truth.front().pose.y), 5.0);  // it drove
  const test::CliResult rel = test::run_cli({"slam", "relations", run + "/log.clf", "--out", run + "/log.relations"});
  ASSERT_EQ(rel.exit_code, 0) << rel.err;
  const test::CliResult truth = test::run_cli({"map", "build", run + "/log.clf", "--poses", "truth", "--out", dir.file("t.yaml"),
                                               "--trajectory-out", dir.file("truth.csv")});
  ASSERT_EQ(truth.exit_code, 0) << truth.err;
  const test::CliResult eval = test::run_cli({"slam", "eval", dir.file("truth.csv"), run + "/log.relations", "--log", run + "/log.clf", "--json"});
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  const auto e = nlohmann::json::parse(eval.out);
  EXPECT_GT(e["laser"]["translation_m"]["count"].get<int>(), 10);
  EXPECT_LT(e["laser"]["translation_m"]["max"].get<double>(), 1e-5);
  const test::CliResult bench = test::run_cli({"bench", "slam", "--data", dir.file("b"), "--relations", dir.file("b"), "--logs",
                                               "building_ladder_3", "--json", "--quiet"});
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  const auto bj = nlohmann::json::parse(bench.out);
  EXPECT_EQ(bj["logs"][0]["evaluated_pose"], "laser");
  EXPECT_GE(bj["logs"][0]["rpe"]["translation_m"]["p95"].get<double>(), 0.0);
  EXPECT_TRUE(bj["logs"][0].contains("worse_than_odometry"));
  EXPECT_EQ(test::run_cli({"bench", "slam", "--data", dir.file("b"), "--relations", dir.file("b"), "--logs", "nothing"}).exit_code, 2);
  // A rule out of range is refused by its flag's name before the log is read (the log named here
  // does not exist).
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--key-distance", "0"}, {"--key-angle", "-1"}, {"--loop-distance", "0"}, {"--loop-travel", "-5"}, {"--loop-every", "0"}}) {
    const test::CliResult bad = test::run_cli({"slam", "relations", dir.file("missing.clf"), "--out", dir.file("x.relations"), flag, value});
    EXPECT_EQ(bad.exit_code, 2) << flag;
    EXPECT_NE(bad.err.find(flag), std::string::npos) << bad.err;
    EXPECT_EQ(bad.err.find("missing.clf"), std::string::npos) << bad.err;
  }
}

}  // namespace
}  // namespace starnav
