// The SLAM benchmark as a library call: a simulated ring drive written as a CARMEN log, with a
// relation file made from its ground truth (every 10th scan to the 5th after it and to one far
// along the ring), run through run_slam_benchmark: every relation evaluated, errors small, the
// report's tables and JSON carry them; the published figures come from the spec's table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "slam/room_fixture.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/experiment/slam_benchmark.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(SlamBenchmark, EvaluatesEveryRelationOfASimulatedLogAndReportsIt) {
  const test::ScratchDir dir;
  std::vector<Pose2> truth;
  const RobotLog log = test::ring_drive(truth);
  test::write_text(dir.file("ring.clf"), carmen_log_text(log));
  std::string relations;
  std::size_t count = 0;
  for (std::size_t i = 0; i + 200 < truth.size(); i += 10)
    for (std::size_t j : {i + 5, i + 200}) {
      const Pose2 d = truth[i].inverse().compose(truth[j]);
      relations += format_stamp_us(log.scans[i].stamp_us) + " " + format_stamp_us(log.scans[j].stamp_us) + " " + format_fixed(d.x, 6) +
                   " " + format_fixed(d.y, 6) + " 0 0 0 " + format_fixed(d.yaw, 6) + "\n";
      ++count;
    }
  test::write_text(dir.file("ring.relations"), relations);
  SlamBenchmarkConfig c;
  c.data_dir = dir.path().string();
  c.relations_dir = dir.path().string();
  c.logs = {{"ring", "ring.clf", "ring.relations", {}}};
  c.out_dir = dir.file("out");
  const SlamBenchmarkResult r = run_slam_benchmark(c);
  ASSERT_EQ(r.rows.size(), 1u);
  const RelativePoseError& e = r.rows[0].evaluated();
  EXPECT_EQ(e.translation_m.n, count);
  EXPECT_EQ(e.unmatched, 0u);
  EXPECT_LT(e.translation_m.mean, 0.05);
  EXPECT_LT(e.rotation_deg.mean, 0.5);
  EXPECT_FALSE(r.rows[0].laser_evaluated);  // the ring log has no mount
  EXPECT_GT(r.rows[0].run.real_time_factor(), 0.0);
  const auto j = nlohmann::json::parse(slam_benchmark_json(r));
  EXPECT_EQ(j["logs"][0]["rpe"]["count"], count);
  EXPECT_DOUBLE_EQ(j["logs"][0]["rpe"]["translation_m"]["mean"].get<double>(), e.translation_m.mean);
  EXPECT_FALSE(j["logs"][0].contains("published"));
  EXPECT_NE(slam_benchmark_markdown(r).find("| ring | " + std::to_string(count) + " | "), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.file("out/ring/pose_graph.json")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("out/ring/map.png")));
}

TEST(SlamBenchmark, PublishedFiguresAreTheSpecsTable) {
  const std::optional<SlamPublished> intel = slam_published("intel");
  ASSERT_TRUE(intel.has_value());
  EXPECT_DOUBLE_EQ(intel->graph_mapping.t_mean, 0.031);
  EXPECT_DOUBLE_EQ(intel->cartographer.t_mean, 0.0229);
  EXPECT_DOUBLE_EQ(intel->cartographer_runtime_s, 179);
  EXPECT_TRUE(std::isnan(intel->rbpf.r_mean));
  EXPECT_FALSE(slam_published("nowhere").has_value());
  EXPECT_EQ(slam_benchmark_logs().size(), 4u);
  EXPECT_TRUE(slam_benchmark_logs()[2].read.flaser_beam_angles);  // aces
}

TEST(CliBenchSlam, RefusesMissingFoldersAndUnknownLogs) {
  const test::ScratchDir dir;
  EXPECT_EQ(test::run_cli({"bench", "slam", "--data", dir.file("none"), "--relations", dir.path().string()}).exit_code, 2);
  const test::CliResult r = test::run_cli({"bench", "slam", "--data", dir.path().string(), "--relations", dir.path().string(), "--logs", "intel,atlantis"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("atlantis"), std::string::npos) << r.err;
  // A known log missing from the folder: one error line naming the file.
  const test::CliResult m = test::run_cli({"bench", "slam", "--data", dir.path().string(), "--relations", dir.path().string(), "--logs", "aces", "--quiet"});
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("aces.relations"), std::string::npos) << m.err;
}

}  // namespace
}  // namespace starnav
