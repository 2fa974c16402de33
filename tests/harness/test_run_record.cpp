// The run record (docs/run-records.md) against the run it describes: world.json holds the
// scenario's obstacles with their times and motions, the terrain subsampled as stated, and the
// navigator's initial grid; replaying every step's changes over that grid gives the navigator's
// final map exactly; each step line carries the estimate (and AMCL's particles) when the run
// localizes; the live feed is the same lines; run.json lists the folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/view/run_folder.hpp"

namespace starnav {
namespace {

const std::string kScene = R"(
name: record
world:
  terrain:
    generate: {kind: flat, size_m: [12.0, 8.0], resolution_m: 0.05, z_m: 0.25}
  obstacles:
    - {name: wall, kind: box, position_m: [6.0, 4.3], size_m: [1.0, 1.5, 0.5], yaw_deg: 30}
    - {name: post, kind: cylinder, position_m: [3.0, 6.5], radius_m: 0.2, height_m: 1.0, appear_s: 2.0, disappear_s: 9.0}
    - name: walker
      kind: sphere
      position_m: [9.0, 1.0]
      radius_m: 0.3
      waypoints:
        - {t_s: 0, position_m: [9.0, 1.0]}
        - {t_s: 10, position_m: [9.0, 2.0]}
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 4.0, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 200.0, seed: 3}
navigation:
  goal: {x_m: 11.0, y_m: 4.0}
)";

TEST(RunRecord, WorldJsonDescribesTheScenariosWorld) {
  const ScenarioSpec spec = parse_scenario(kScene, "record.yaml");
  NavigationRun run(spec);
  const auto w = nlohmann::json::parse(world_json(run.simulation(), &run));
  EXPECT_EQ(w["schema"], "starnav-world");
  EXPECT_EQ(w["version"], kRunRecordVersion);
  ASSERT_EQ(w["obstacles"].size(), 3u);
  const auto& wall = w["obstacles"][0];
  EXPECT_EQ(wall["name"], "wall");
  EXPECT_TRUE(wall["disappear_s"].is_null());
  ASSERT_EQ(wall["parts"].size(), 1u);
  EXPECT_EQ(wall["parts"][0][0], "box");
  EXPECT_DOUBLE_EQ(wall["parts"][0][1].get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(wall["parts"][0][3].get<double>(), 0.5);  // centre 0.25 above the 0.25 m ground
  EXPECT_NEAR(wall["parts"][0][9].get<double>(), 0.524, 1e-9);  // 30 degrees, to the millimetre
  const auto& post = w["obstacles"][1];
  EXPECT_DOUBLE_EQ(post["appear_s"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(post["disappear_s"].get<double>(), 9.0);
  EXPECT_EQ(post["parts"][0][0], "cylinder");
  const auto& walker = w["obstacles"][2];
  ASSERT_EQ(walker["waypoints"].size(), 2u);
  EXPECT_DOUBLE_EQ(walker["waypoints"][1][2].get<double>(), 2.0);
  // Flat terrain: 240 x 160 cells, every one kept (no side above 512), all at 0.25 m.
  const auto& t = w["terrain"];
  EXPECT_EQ(t["stride"], 1);
  EXPECT_EQ(t["samples_x"], 240);
  EXPECT_EQ(t["samples_y"], 160);
  ASSERT_EQ(t["heights"].size(), 240u * 160u);
  for (const auto& h : t["heights"]) ASSERT_DOUBLE_EQ(h.get<double>(), 0.25);
  EXPECT_EQ(w["robot"]["drive"], "differential");
  EXPECT_DOUBLE_EQ(w["goals"][0][0].get<double>(), 11.0);
  EXPECT_TRUE(w["goals"][0][2].is_null());
}

TEST(RunRecord, ALargeTerrainIsSubsampledToAtMost512PerSide) {
  std::string yaml = kScene;
  const std::string small = "size_m: [12.0, 8.0]";
  yaml.replace(yaml.find(small), small.size(), "size_m: [60.0, 8.0]");
  const ScenarioSpec spec = parse_scenario(yaml, "record.yaml");
  NavigationRun run(spec);
  const auto t = nlohmann::json::parse(world_json(run.simulation(), &run))["terrain"];
  // 1200 x 160 cells: stride ceil(1200 / 512) = 3, 400 x 54 samples.
  EXPECT_EQ(t["stride"], 3);
  EXPECT_EQ(t["samples_x"], 400);
  EXPECT_EQ(t["samples_y"], 54);
  EXPECT_EQ(t["heights"].size(), 400u * 54u);
}

TEST(RunRecord, ReplayingEveryStepsChangesOverTheInitialGridGivesTheFinalMap) {
  const ScenarioSpec spec = parse_scenario(kScene, "record.yaml");
  NavigationRun run(spec);
  run.run();
  ASSERT_TRUE(run.metrics().success);
  const auto w = nlohmann::json::parse(world_json(run.simulation(), &run));
  const auto& m = w["nav_map"];
  const int width = m["width"];
  std::vector<int> cells;
  for (std::size_t i = 0; i + 1 < m["initial"].size(); i += 2)
    cells.insert(cells.end(), m["initial"][i + 1].get<std::size_t>(), m["initial"][i].get<int>());
  const OccupancyGrid& final_map = run.navigator().map().occupancy();
  ASSERT_EQ(cells.size(), final_map.cell_count());
  std::size_t changes = 0, paths = 0;
  for (const NavStepRecord& r : run.steps()) {
    const auto j = nlohmann::json::parse(step_json_line(run, r));
    for (const auto& c : j["changed"]) {
      cells[static_cast<std::size_t>(c[1].get<int>() * width + c[0].get<int>())] = c[2].get<int>();
      ++changes;
    }
    if (j.contains("path")) ++paths;
    EXPECT_FALSE(j.contains("estimate"));  // no localization section
  }
  EXPECT_GT(changes, 0u);
  EXPECT_EQ(paths, static_cast<std::size_t>(run.metrics().plans));
  for (std::size_t i = 0; i < cells.size(); ++i) ASSERT_EQ(cells[i], final_map[i]) << "cell " << i;
}

TEST(RunRecord, StepsCarryTheEstimateWhenTheRunLocalizes) {
  std::string yaml = kScene;
  const std::string lidar = "  lidar: {}";
  yaml.replace(yaml.find(lidar), lidar.size(), lidar + "\n  encoders: {}");
  yaml += "localization: {odometry: wheel, localizer: ground_truth}\n";
  {
    NavigationRun run(parse_scenario(yaml, "record.yaml"));
    std::size_t lines = 0;
    run.run();
    for (const NavStepRecord& r : run.steps()) {
      const auto j = nlohmann::json::parse(step_json_line(run, r));
      ASSERT_TRUE(j.contains("estimate"));
      EXPECT_NEAR(j["estimate"][0].get<double>(), r.estimate->x, 5e-4);
      EXPECT_FALSE(j.contains("particles"));  // ground truth has no particle set
      ++lines;
    }
    EXPECT_GT(lines, 0u);
  }
}

TEST(RunRecord, TheLiveFeedSendsTheSameLinesAsStepsJsonl) {
  const ScenarioSpec spec = parse_scenario(kScene, "record.yaml");
  NavigationOptions o;
  std::vector<std::string> fed;
  o.on_step_line = [&fed](const std::string& line) { fed.push_back(line); };
  NavigationRun run(spec, o);
  run.run();
  ASSERT_EQ(fed.size(), run.steps().size());
  for (std::size_t i = 0; i < fed.size(); ++i) EXPECT_EQ(fed[i], step_json_line(run, run.steps()[i]));
}

TEST(RunRecord, RunJsonListsTheFolderAndReadsBack) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("starnav_run_record_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const ScenarioSpec spec = parse_scenario(kScene, "record.yaml");
  NavigationRun run(spec);
  run.run();
  write_navigation_records(run, dir.string());
  write_run_record(run.simulation(), &run, dir.string());
  const auto j = nlohmann::json::parse(std::ifstream(dir / "run.json"));
  EXPECT_EQ(j["schema"], "starnav-run");
  EXPECT_EQ(j["kind"], "navigation");
  EXPECT_EQ(j["scenario"]["file"], "record.yaml");
  std::vector<std::string> listed = j["files"];
  std::vector<std::string> present;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != "run.json" && e.path().filename().string()[0] != '.') present.push_back(e.path().filename().string());
  std::sort(present.begin(), present.end());
  EXPECT_EQ(listed, present);
  const RunFolder folder = read_run_folder(dir.string());
  EXPECT_EQ(folder.kind, "navigation");
  EXPECT_EQ(folder.files, listed);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace starnav
