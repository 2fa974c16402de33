// starnav log info: the summary of a log in text and JSON, and one error line (file, line, field)
// with exit 2 for a malformed log, a directory and a device.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

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
  for (const char* f : {"map.yaml", "map.pgm", "pose_graph.json", "map.png", "summary.json"})
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

}  // namespace
}  // namespace starnav
