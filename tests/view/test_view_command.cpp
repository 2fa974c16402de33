// starnav view and sim --live from the command line: an address it cannot listen on is one error
// line, with no warning before it; `view --export` of every kind of run folder the library writes
// (scripted and navigation simulations, SLAM, AMCL on a log, 3D SLAM) gives a page carrying the
// folder's record byte for byte, whose map and trajectory are those of the folder's own outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/config.hpp"
#include "starnav/io/ros_map.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

int lines_of(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// A stand-in for the bundled viewer (the command needs its files before it serves or exports).
void use_stand_in_viewer(const test::ScratchDir& dir) {
  fs::create_directories(dir.file("viewer"));
  test::write_text(dir.file("viewer/index.html"), "<html><!--starnav-run-->\n<script src=\"viewer.js\"></script></html>");
  test::write_text(dir.file("viewer/viewer.js"), "var viewer = 1;");
  ::setenv("STARNAV_VIEWER_DIR", dir.file("viewer").c_str(), 1);
}

TEST(ViewCommand, AnAddressItCannotListenOnIsOneErrorLineWithNoWarningBefore) {
#if !STARNAV_HAVE_HTTP
  GTEST_SKIP() << "built without the HTTP server";
#endif
  const test::ScratchDir dir;
  use_stand_in_viewer(dir);
  fs::create_directories(dir.file("run"));
  test::write_text(dir.file("run/world.json"), "{\"schema\":\"starnav-world\",\"version\":1}");
  test::write_text(dir.file("run/run.json"), R"({"schema":"starnav-run","version":1,"kind":"simulation","files":["world.json"]})");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"view", dir.file("run"), "--bind", "999.1.1.1"},
        {"view", dir.file("run"), "--bind", "192.0.2.1", "--port", "0"},
        {"sim", test::kE1, "--out", dir.file("live"), "--live", "--bind", "999.1.1.1", "--duration", "1", "--quiet"}}) {
    const test::CliResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << " " << r.err;
    EXPECT_EQ(lines_of(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error:", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("--bind"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  }
}

// The run's files as the exported page carries them (the data element's JSON).
nlohmann::json exported_files(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"starnav-run\">";
  const std::size_t a = page.find(open);
  if (a == std::string::npos) return nullptr;
  const std::size_t b = page.find("</script>", a + open.size());
  return nlohmann::json::parse(page.substr(a + open.size(), b - a - open.size()));
}

// The grid a viewer shows after the last step: nav_map's initial cells with every step's changes.
std::vector<int> replayed_map(const nlohmann::json& world, const std::string& steps) {
  const nlohmann::json& m = world["nav_map"];
  const int w = m["width"].get<int>();
  std::vector<int> cells;
  const nlohmann::json& rle = m["initial"];
  for (std::size_t i = 0; i + 1 < rle.size(); i += 2) cells.insert(cells.end(), rle[i + 1].get<std::size_t>(), rle[i].get<int>());
  std::istringstream lines(steps);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    const auto step = nlohmann::json::parse(line);
    for (const auto& c : step.value("changed", nlohmann::json::array()))
      cells.at(static_cast<std::size_t>(c[1].get<int>() * w + c[0].get<int>())) = c[2].get<int>();
  }
  return cells;
}

std::vector<int> cells_of(const OccupancyGrid& grid) { return {grid.data().begin(), grid.data().end()}; }

TEST(ViewCommand, ExportsEveryKindOfRunFolderWithItsMapAndTrajectory) {
  const test::ScratchDir dir;
  use_stand_in_viewer(dir);
  const auto run = [](const std::vector<std::string>& args) {
    const test::CliResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0;
  };
  // One folder of each kind.
  test::write_text(dir.file("nav.yaml"), test::small_nav_scenario(test::kSmallNavWall));
  ASSERT_TRUE(run({"sim", test::kE1, "--out", dir.file("scripted"), "--duration", "2", "--quiet"}));
  ASSERT_TRUE(run({"sim", dir.file("nav.yaml"), "--out", dir.file("navigation"), "--quiet"}));
  ASSERT_TRUE(run({"sim", test::scenario_path("indoor_slam.yaml"), "--out", dir.file("indoor"), "--duration", "15", "--quiet"}));
  ASSERT_TRUE(run({"slam", "run", dir.file("indoor/log.clf"), "--out", dir.file("slam"), "--quiet"}));
  ASSERT_TRUE(run({"localize", dir.file("indoor/log.clf"), "--map", dir.file("slam/map.yaml"), "--initial", "1.75,1.75,0", "--out",
                   dir.file("localization"), "--quiet"}));
  ASSERT_TRUE(run({"sim", test::scenario_path("ou2022_mapping3d.yaml"), "--out", dir.file("frames"), "--duration", "3", "--quiet"}));
  ASSERT_TRUE(run({"slam3d", dir.file("frames"), "--out", dir.file("slam3d"), "--plan-to", "2.5,0", "--quiet"}));

  const std::map<std::string, std::string> kinds = {{"scripted", "simulation"}, {"navigation", "navigation"}, {"slam", "slam"},
                                                    {"localization", "localization"}, {"slam3d", "slam3d"}};
  for (const auto& [folder, kind] : kinds) {
    SCOPED_TRACE(folder);
    ASSERT_TRUE(run({"view", dir.file(folder), "--export", dir.file(folder + ".html")}));
    const nlohmann::json files = exported_files(test::read_text(dir.file(folder + ".html")));
    ASSERT_TRUE(files.is_object());
    const auto manifest = nlohmann::json::parse(files["run.json"].get<std::string>());
    EXPECT_EQ(manifest["kind"], kind);
    // The record, byte for byte.
    for (const char* name : {"run.json", "world.json", "metrics.json", "trajectory.csv", "steps.jsonl"}) {
      const bool on_disk = fs::exists(dir.file(folder + "/" + name));
      EXPECT_EQ(files.contains(name), on_disk) << name;
      if (on_disk && files.contains(name)) {
        EXPECT_EQ(files[name].get<std::string>(), test::read_text(dir.file(folder + "/" + name))) << name;
      }
    }
    const auto world = nlohmann::json::parse(files["world.json"].get<std::string>());
    const std::string steps = files.value("steps.jsonl", std::string());
    std::size_t step_count = 0;
    for (const char c : steps) step_count += c == '\n' ? 1 : 0;
    // The map the viewer draws at the end is the folder's written map.
    if (kind == "slam" || kind == "localization" || kind == "slam3d") {
      const std::string map_yaml = kind == "localization" ? dir.file("slam/map.yaml") : dir.file(folder + "/map.yaml");
      ASSERT_TRUE(world.contains("nav_map"));
      EXPECT_EQ(replayed_map(world, steps), cells_of(read_ros_map(map_yaml)));
    }
    if (kind == "navigation") {
      ASSERT_TRUE(world.contains("nav_map"));
      EXPECT_GT(world["nav_map"]["width"].get<int>() * world["nav_map"]["height"].get<int>(), 0);
    }
    // A trajectory to draw: trajectory.csv's rows, or for 3D SLAM (whose trajectory.csv is the
    // sensor's) a step per frame with the base on the floor.
    const std::string trajectory = files.value("trajectory.csv", std::string());
    std::size_t rows = 0;
    for (const char c : trajectory) rows += c == '\n' ? 1 : 0;
    EXPECT_GT(rows, 10u);
    if (kind == "slam" || kind == "slam3d") {
      EXPECT_EQ(step_count, rows - 1);
    }
    if (kind == "slam3d") {
      std::istringstream lines(steps);
      std::string last;
      for (std::string line; std::getline(lines, line);) {
        const auto step = nlohmann::json::parse(line);
        EXPECT_LT(std::abs(step["pose"][2].get<double>()), 0.05) << line;
        last = line;
      }
      const auto end = nlohmann::json::parse(last);
      ASSERT_TRUE(end.contains("path")) << "the planned path, at the end";
      const std::string path_csv = test::read_text(dir.file("slam3d/path.csv"));  // x_m,y_m and a row per point
      EXPECT_EQ(end["path"].size(), static_cast<std::size_t>(std::count(path_csv.begin(), path_csv.end(), '\n')) - 1);
    }
  }
}

}  // namespace
}  // namespace starnav
