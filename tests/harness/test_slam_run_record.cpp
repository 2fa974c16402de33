// A SLAM run's record for the viewer (docs/run-records.md, kind "slam"): replaying every step's
// map changes over the all-unknown grid gives the written map's classes, each loop closure of the
// pose graph appears once, at its later node, and the folder reads back as a run record.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "slam/room_fixture.hpp"
#include "starnav/harness/slam_report.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "starnav/view/run_folder.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(SlamRunRecord, StepsReplayToTheWrittenMapAndCarryEveryLoopClosure) {
  const test::ScratchDir dir;
  std::vector<Pose2> truth;
  const RobotLog log = test::ring_drive(truth);
  test::write_text(dir.file("ring.clf"), carmen_log_text(log));
  SlamRunRequest q;
  q.log = dir.file("ring.clf");
  const SlamRunResult r = run_slam_on_file(q);
  ASSERT_EQ(r.steps.size(), r.trajectory.size());
  write_slam_outputs(r, dir.file("out"));

  const auto world = nlohmann::json::parse(test::read_text(dir.file("out/world.json")));
  const auto& m = world["nav_map"];
  const int width = m["width"], height = m["height"];
  ASSERT_EQ(width, r.map.width());
  ASSERT_EQ(height, r.map.height());
  std::vector<int> cells(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), -1);
  std::istringstream lines(test::read_text(dir.file("out/steps.jsonl")));
  std::string line;
  std::size_t steps = 0, closures = 0;
  double last_t = -1.0;
  while (std::getline(lines, line)) {
    const auto j = nlohmann::json::parse(line);
    EXPECT_GE(j["t_s"].get<double>(), last_t);
    last_t = j["t_s"].get<double>();
    for (const auto& c : j["changed"]) {
      const int x = c[0], y = c[1];
      ASSERT_TRUE(x >= 0 && y >= 0 && x < width && y < height) << x << ", " << y;
      cells[static_cast<std::size_t>(y * width + x)] = c[2];
    }
    if (j.contains("loop_closures")) closures += j["loop_closures"].size();
    ++steps;
  }
  EXPECT_EQ(steps, r.trajectory.size());
  EXPECT_EQ(closures, r.graph.closures());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int v = r.map(x, y);
      const int expected = v < 0 ? -1 : (v >= 65 ? 100 : (v <= 20 ? 0 : -1));  // as map_saver writes the percent
      ASSERT_EQ(cells[static_cast<std::size_t>(y * width + x)], expected) << x << ", " << y << " (" << v << "%)";
    }
  const RunFolder folder = read_run_folder(dir.file("out"));
  EXPECT_EQ(folder.kind, "slam");
  const auto manifest = nlohmann::json::parse(test::read_text(dir.file("out/run.json")));
  EXPECT_EQ(manifest["log"]["name"], "ring.clf");
  EXPECT_NEAR(manifest["start_s"].get<double>(), static_cast<double>(r.steps.front().stamp_us) * 1e-6, 5e-4);
}

TEST(SlamRunRecord, WithoutStepsNoRecordIsWritten) {
  const test::ScratchDir dir;
  std::string log;  // six scans down a short corridor
  for (int i = 0; i < 6; ++i)
    log += "ODOM " + std::to_string(0.01 * i) + " 0 0 0 0 0 " + std::to_string(i) + ".000000 h 0\n" +
           "FLASER 5 2.0 2.1 2.2 2.1 2.0 0 0 0 0 0 0 " + std::to_string(i) + ".500000 h 0\n";
  test::write_text(dir.file("run.clf"), log);
  SlamRunRequest q;
  q.log = dir.file("run.clf");
  q.record_steps = false;
  const SlamRunResult r = run_slam_on_file(q);
  EXPECT_TRUE(r.steps.empty());
  write_slam_outputs(r, dir.file("out"));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/run.json")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("out/map.yaml")));
}

}  // namespace
}  // namespace starnav
