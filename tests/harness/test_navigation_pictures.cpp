// Navigation pictures (scene and planned-vs-executed overlay): what each picture holds, read back
// from the SVG text; determinism; file writing by extension and errors naming the file. Most
// tests fill NavigationPictureData by hand (a NodeHeightMap fed one synthetic scan, hand-made
// plans and trajectory), so they do not depend on a navigation run; the last one draws a real run.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_pictures.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/costmap/node_height_map.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/sim/scenario.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

GridGeometry grid_4x3() {
  GridGeometry g;
  g.width = 40;
  g.height = 30;
  g.resolution = 0.1;
  return g;
}

// A 4 m x 3 m map seen once: ground (z = 0) for x < 3 m, a wall 0.4 m high at x 2.0..2.2 m,
// y 0.9..2.1 m; x >= 3 m stays unobserved.
NodeHeightMap scanned_map(NodeMapMode mode) {
  NodeMapParams params;
  params.mode = mode;
  params.clear = false;
  params.barrier_distance_m = 0.3;
  NodeHeightMap map(grid_4x3(), params);
  std::vector<Vec3> points;
  for (double x = 0.05; x < 3.0; x += 0.1)
    for (double y = 0.05; y < 3.0; y += 0.1) {
      const bool wall = x > 2.0 && x < 2.2 && y > 0.9 && y < 2.1;
      if (mode == NodeMapMode::Nodes3D && !wall) points.emplace_back(x, y, 0.0);
      if (wall)
        for (const double z : {0.0, 0.2, 0.4}) points.emplace_back(x, y, z);
    }
  map.integrate(Vec3(0.5, 1.5, 0.6), points);
  return map;
}

NavPlan plan(int id, const std::string& cause, std::vector<Vec2> points) {
  NavPlan p;
  p.id = id;
  p.cause = cause;
  p.status = points.empty() ? "no_path" : "found";
  p.points = std::move(points);
  return p;
}

struct Fixture {
  NodeHeightMap map;
  std::vector<NavPlan> plans;
  std::vector<Obstacle> obstacles;
  NavigationPictureData data;

  explicit Fixture(NodeMapMode mode = NodeMapMode::Nodes3D) : map(scanned_map(mode)) {
    plans.push_back(plan(1, "initial", {{0.5, 1.5}, {3.5, 1.5}}));
    plans.push_back(plan(2, "blocked", {{1.5, 1.5}, {1.5, 0.5}, {3.5, 0.5}, {3.5, 1.5}}));
    plans.push_back(plan(3, "missed", {}));  // a failed search: nothing to draw
    data.name = "pictures";
    data.status = "arrived";
    data.end_time_s = 4.0;
    data.map = &map;
    data.plans = plans;
    data.trajectory = {{0.5, 1.5}, {1.5, 1.5}, {1.5, 0.55}, {3.4, 0.55}, {3.5, 1.45}};
    data.start = Pose2(0.5, 1.5, 0.0);
    data.goal = Vec2(3.5, 1.5);
    data.goal_tolerance_m = 0.15;
  }
  void add_obstacles() {
    Obstacle wall;
    wall.name = "wall";
    wall.parts = {Box{Vec3(2.1, 1.5, 0.2), Vec3(0.2, 1.2, 0.4)}};
    Obstacle late;
    late.name = "late";
    late.appear = 1.0;
    late.parts = {Cylinder{Vec3(1.0, 2.5, 0.0), 0.2, 0.5}};
    Obstacle never;  // appears after the run: not drawn
    never.name = "never";
    never.appear = 10.0;
    never.parts = {Cylinder{Vec3(1.0, 0.5, 0.0), 0.2, 0.5}};
    obstacles = {wall, late, never};
    data.obstacles = obstacles;
  }
};

TEST(NavigationPictures, SceneDrawsEveryPlanLabelledTheTrajectoryAndTheBlockedCells) {
  Fixture f;
  std::size_t raw = 0, band = 0;
  for (std::size_t i = 0; i < f.map.geometry().cell_count(); ++i) {
    raw += f.map.raw_blocked()[i] != 0;
    band += f.map.blocked()[i] != 0 && f.map.raw_blocked()[i] == 0;
  }
  ASSERT_GT(raw, 0u);
  ASSERT_GT(band, 0u);

  const std::string svg = navigation_scene_picture(f.data).svg_string();
  // One polyline per plan with a path, one for the trajectory; no obstacles given.
  EXPECT_EQ(count(svg, "class=\"layer-polyline\""), 3u);
  EXPECT_EQ(count(svg, ">P1</text>"), 1u);
  EXPECT_EQ(count(svg, ">P2</text>"), 1u);
  EXPECT_EQ(count(svg, ">P3</text>"), 0u);
  EXPECT_NE(svg.find("P1 (initial)"), std::string::npos);
  EXPECT_NE(svg.find("P2 (blocked)"), std::string::npos);
  EXPECT_NE(svg.find("executed trajectory"), std::string::npos);
  // The band and the raw blocked cells are two cell layers, the goal tolerance a circle.
  EXPECT_EQ(count(svg, "class=\"layer-cells\""), 2u);
  EXPECT_EQ(count(svg, "class=\"layer-circle\""), 1u);
  EXPECT_NE(svg.find("expansion band"), std::string::npos);
  EXPECT_NE(svg.find("raw blocked"), std::string::npos);
  // Observed cells grey by mid height (ground 0, the wall's cells 0 .. 0.4 m: mid 0.2 m).
  EXPECT_NE(svg.find("observed, lowest (0.00 m)"), std::string::npos);
  EXPECT_NE(svg.find("observed, highest (0.20 m)"), std::string::npos);
  EXPECT_NE(svg.find("<title>pictures: navigation scene (arrived, t = 4.0 s)</title>"), std::string::npos);
}

TEST(NavigationPictures, SceneOutlinesTheTrueObstaclesThatAppearedDuringTheRun) {
  Fixture f;
  const std::string without = navigation_scene_picture(f.data).svg_string();
  f.add_obstacles();
  const std::string with = navigation_scene_picture(f.data).svg_string();
  // The box's outline is a polyline, the cylinder that appeared a circle; the late one is left out.
  EXPECT_EQ(count(with, "class=\"layer-polyline\""), count(without, "class=\"layer-polyline\"") + 1);
  EXPECT_EQ(count(with, "class=\"layer-circle\""), count(without, "class=\"layer-circle\"") + 1);
  EXPECT_NE(with.find("true obstacle, dynamic"), std::string::npos);
}

TEST(NavigationPictures, Lidar2DMapsAreOneGrey) {
  Fixture f(NodeMapMode::Lidar2D);
  const std::string svg = navigation_scene_picture(f.data).svg_string();
  EXPECT_EQ(svg.find("lowest"), std::string::npos);
  EXPECT_NE(svg.find(">observed</text>"), std::string::npos);
  EXPECT_EQ(count(svg, ">P1</text>"), 1u);
  EXPECT_EQ(count(svg, ">P2</text>"), 1u);
}

TEST(NavigationPictures, OverlayHasOneSeriesPerPlanAndTheExecutedPath) {
  Fixture f;
  const std::string svg = navigation_overlay_plot(f.data).svg_string();
  // Lines: P1, P2, executed, goal tolerance (start and goal are markers only).
  EXPECT_EQ(count(svg, "<path d=\""), 4u);
  EXPECT_EQ(count(svg, ">P1</text>"), 1u);
  EXPECT_EQ(count(svg, ">P2</text>"), 1u);
  EXPECT_EQ(count(svg, ">P3</text>"), 0u);
  EXPECT_EQ(count(svg, ">executed</text>"), 1u);
  EXPECT_EQ(count(svg, ">start</text>"), 1u);
  EXPECT_EQ(count(svg, ">goal</text>"), 1u);
}

TEST(NavigationPictures, ManyPlansShareOneLegendEntry) {
  Fixture f;
  f.plans.clear();
  for (int i = 1; i <= 20; ++i) f.plans.push_back(plan(i, "blocked", {{0.5, 0.1 * i}, {3.5, 0.1 * i}}));
  f.data.plans = f.plans;
  const std::string scene = navigation_scene_picture(f.data).svg_string();
  const std::string overlay = navigation_overlay_plot(f.data).svg_string();
  for (int i = 1; i <= 20; ++i) EXPECT_EQ(count(scene, ">P" + std::to_string(i) + "</text>"), 1u) << i;
  EXPECT_NE(scene.find("planned paths P1..P20"), std::string::npos);
  EXPECT_NE(overlay.find("planned paths P1..P20"), std::string::npos);
  EXPECT_EQ(count(overlay, ">P7</text>"), 0u);
}

TEST(NavigationPictures, SameDataSameBytes) {
  Fixture a, b;
  a.add_obstacles();
  b.add_obstacles();
  EXPECT_EQ(navigation_scene_picture(a.data).svg_string(), navigation_scene_picture(b.data).svg_string());
  EXPECT_EQ(navigation_overlay_plot(a.data).svg_string(), navigation_overlay_plot(b.data).svg_string());
}

TEST(NavigationPictures, WritersChooseTheFormatByExtensionAndNameTheFile) {
  Fixture f;
  test::ScratchDir dir;
  write_navigation_scene(f.data, dir.file("scene.svg"));
  write_navigation_scene(f.data, dir.file("scene.PNG"));
  write_navigation_overlay(f.data, dir.file("overlay.svg"));
  EXPECT_EQ(test::read_text(dir.file("scene.svg")), navigation_scene_picture(f.data).svg_string());
  EXPECT_EQ(test::read_text(dir.file("scene.PNG")).substr(0, 4), "\x89PNG");
  EXPECT_EQ(test::read_text(dir.file("overlay.svg")), navigation_overlay_plot(f.data).svg_string());

  const auto file_of = [](auto&& write) -> std::string {
    try {
      write();
    } catch (const Error& e) {
      return e.file();
    }
    return "(no error)";
  };
  write_navigation_overlay(f.data, dir.file("overlay.png"));
  EXPECT_EQ(test::read_text(dir.file("overlay.png")).substr(0, 4), "\x89PNG");
  const std::string jpg = dir.file("scene.jpg"), pdf = dir.file("overlay.pdf");
  const std::string missing = (dir.path() / "no" / "such" / "scene.svg").string();
  EXPECT_EQ(file_of([&] { write_navigation_scene(f.data, jpg); }), jpg);
  EXPECT_EQ(file_of([&] { write_navigation_overlay(f.data, pdf); }), pdf);
  EXPECT_EQ(file_of([&] { write_navigation_scene(f.data, missing); }), missing);

  NavigationPictureData no_map = f.data;
  no_map.map = nullptr;
  EXPECT_THROW(navigation_scene_picture(no_map), Error);
  EXPECT_EQ(file_of([&] { write_navigation_scene(no_map, dir.file("x.svg")); }), dir.file("x.svg"));
}

// A short run end to end: a wall with a gap, a 2D LiDAR; every plan the run made is drawn and
// labelled in both pictures.
TEST(NavigationPictures, DrawsARealRun) {
  const std::string yaml = R"(
name: pictures_run
world:
  terrain:
    generate: {kind: flat, size_m: [6.0, 4.0], resolution_m: 0.05}
  obstacles:
    - {name: wall, kind: box, position_m: [3.0, 1.0], size_m: [0.2, 2.0, 0.5]}
robot:
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 60.0, seed: 1}
navigation:
  goal: {x_m: 5.0, y_m: 1.0}
  map: {resolution_m: 0.1}
)";
  const ScenarioSpec spec = parse_scenario(yaml, "pictures_run.yaml");
  NavigationRun run(spec);
  run.run();
  const std::vector<NavPlan>& plans = run.navigator().plans();
  ASSERT_FALSE(plans.empty());

  test::ScratchDir dir;
  write_navigation_scene(run, dir.file("scene.svg"));
  write_navigation_overlay(run, dir.file("overlay.svg"));
  const std::string scene = test::read_text(dir.file("scene.svg"));
  const std::string overlay = test::read_text(dir.file("overlay.svg"));
  for (const NavPlan& p : plans) {
    if (p.points.size() < 2) continue;
    const std::string label = ">P" + std::to_string(p.id) + "</text>";
    EXPECT_EQ(count(scene, label), 1u) << label;
    if (plans.size() <= 12) {
      EXPECT_EQ(count(overlay, label), 1u) << label;
    }
  }
  EXPECT_NE(scene.find("executed trajectory"), std::string::npos);
  EXPECT_NE(scene.find("true obstacle"), std::string::npos);
  // Drawing again gives the same bytes.
  write_navigation_scene(run, dir.file("again.svg"));
  EXPECT_EQ(test::read_text(dir.file("again.svg")), scene);
}

}  // namespace
}  // namespace starnav
