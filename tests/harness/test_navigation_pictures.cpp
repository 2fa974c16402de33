// Navigation pictures (scene and planned-vs-executed overlay): what each picture holds, read back
// from the SVG text; determinism; file writing by extension and errors naming the file. Most
// tests fill NavigationPictureData by hand (a NodeHeightMap fed one synthetic scan, hand-made
// plans and trajectory), so they do not depend on a navigation run; the last one draws a real run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <numeric>
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

// A plan label as the scene draws it: its text and its box on the picture, from DejaVu Sans's
// advance widths (P 0.603 em, digits 0.636 em, '.', ',' and space 0.318 em; 0.76 em above the
// baseline, 0.24 em below), not from the drawing code's own estimate.
struct DrawnLabel {
  std::string text;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

double attribute(const std::string& element, const std::string& name) {
  const std::size_t at = element.find(" " + name + "=\"");
  return at == std::string::npos ? 0.0 : std::stod(element.substr(at + name.size() + 3));
}

std::vector<DrawnLabel> plan_labels(const std::string& svg) {
  std::vector<DrawnLabel> out;
  const std::string open = "<text class=\"layer-text\"";
  for (std::size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1)) {
    const std::size_t gt = svg.find('>', at), end = svg.find("</text>", gt);
    const std::string element = svg.substr(at, gt - at);
    DrawnLabel l;
    l.text = svg.substr(gt + 1, end - gt - 1);
    const double size = attribute(element, "font-size"), x = attribute(element, "x"), y = attribute(element, "y");
    double width = 0.0;
    for (const char c : l.text) width += (c == 'P' ? 0.603 : c >= '0' && c <= '9' ? 0.636 : 0.318) * size;
    l.x0 = x - width / 2, l.x1 = x + width / 2, l.y0 = y - 0.76 * size, l.y1 = y + 0.24 * size;
    out.push_back(l);
  }
  return out;
}

// The plan ids a label names ("P3", "P3, P4", "P3..P7, P12").
std::vector<int> ids_named(const std::string& text) {
  std::vector<int> ids;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(", ", at);
    if (end == std::string::npos) end = text.size();
    const std::string item = text.substr(at, end - at);
    const std::size_t dots = item.find("..");
    const int a = std::stoi(item.substr(1, dots == std::string::npos ? std::string::npos : dots - 1));
    const int b = dots == std::string::npos ? a : std::stoi(item.substr(dots + 3));
    for (int i = a; i <= b; ++i) ids.push_back(i);
    at = end + 2;
  }
  return ids;
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

// A car's trail by hand: 1 m forward along x, then 0.5 m back; its outline (0.6 x 0.4 m,
// centred 0.2 m ahead of the rear axle) every 0.25 m, at the change of direction and at the end.
TEST(NavigationPictures, TheFootprintTrailMarksEveryChangeOfDirection) {
  std::vector<TrajectorySample> trajectory;
  const auto sample = [&](double x, double vx) {
    TrajectorySample s;
    s.t_s = static_cast<double>(trajectory.size()) * 0.01;
    s.position = Vec3(x, 1.0, 0.0);
    s.rpy = Vec3(0.0, 0.0, 0.5);
    s.twist.vx = vx;
    trajectory.push_back(s);
  };
  // Steps of 1/16 m (exact in binary, so the 0.25 m spacing falls on samples).
  for (int i = 0; i <= 16; ++i) sample(0.0625 * i, i == 0 ? 0.0 : 0.2);
  sample(1.0, 0.0);  // at rest at the cusp: no direction
  for (int i = 1; i <= 8; ++i) sample(1.0 - 0.0625 * i, -0.2);
  FootprintModel body;
  body.circle = false;
  body.half_length_m = 0.3;
  body.half_width_m = 0.2;
  body.center_x_m = 0.2;
  const FootprintTrail t = footprint_trail(trajectory, body);
  ASSERT_EQ(t.reversals.size(), 1u);
  EXPECT_NEAR(t.reversals[0].x(), 0.9375, 1e-12);
  // The start; 0.25, 0.5, 0.75 and 1 m forward; the reversal (at 0.9375 m); 0.25 m after it;
  // the end (0.1875 m after that).
  EXPECT_EQ(t.outlines.size(), 8u);
  for (const std::vector<Vec2>& o : t.outlines) {
    ASSERT_EQ(o.size(), 5u);
    EXPECT_NEAR((o[0] - o[4]).norm(), 0.0, 1e-12);  // closed
    EXPECT_NEAR((o[1] - o[0]).norm(), 0.6, 1e-9);
    EXPECT_NEAR((o[2] - o[1]).norm(), 0.4, 1e-9);
    // The rectangle's centre 0.2 m ahead along the heading (0.5 rad) of a pose on y = 1.
    const Vec2 centre = 0.5 * (o[0] + o[2]);
    EXPECT_NEAR(centre.y() - 1.0, 0.2 * std::sin(0.5), 1e-9);
  }
  // Drawn as one outline layer each and a marker layer for the reversal.
  Fixture f;
  const std::size_t lines = count(navigation_scene_picture(f.data).svg_string(), "class=\"layer-polyline\"");
  f.data.footprints = t.outlines;
  f.data.reversals = t.reversals;
  const std::string svg = navigation_scene_picture(f.data).svg_string();
  EXPECT_EQ(count(svg, "class=\"layer-polyline\""), lines + t.outlines.size());
  EXPECT_NE(svg.find("change of driving direction"), std::string::npos);
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

// Many plans starting at one place, or a few centimetres apart (as E4's 36 replans do): every plan
// is named once, and no label overlaps another, the start or the goal, or leaves the plot.
TEST(NavigationPictures, PlanLabelsStayReadableWhenManyPlansStartTogether) {
  Fixture f;
  f.plans.clear();
  const auto route = [](const Vec2& from) { return std::vector<Vec2>{from, from + Vec2(0.3, 0.4), Vec2(3.5, 1.5)}; };
  f.plans.push_back(plan(1, "initial", route({0.5, 1.5})));
  for (int i = 2; i <= 11; ++i) f.plans.push_back(plan(i, "blocked", route({1.5, 1.5})));  // one place
  for (int i = 12; i <= 20; ++i) f.plans.push_back(plan(i, "blocked", route({2.0, 0.5 + 0.005 * i})));  // creeping
  for (int i = 21; i <= 36; ++i) {  // a 4 x 4 lattice 4 cm apart: near, not together
    const int j = i - 21;
    f.plans.push_back(plan(i, "missed", route({1.0 + 0.04 * (j % 4), 0.8 + 0.04 * (j / 4)})));
  }
  f.plans.push_back(plan(37, "blocked", route({1.5, 1.5})));  // back at the first place
  f.data.plans = f.plans;
  const viz::MapPicture pic = navigation_scene_picture(f.data);
  const viz::PictureLayout L = pic.svg_layout();
  const std::vector<DrawnLabel> labels = plan_labels(pic.svg_string());
  std::vector<int> named;
  for (const DrawnLabel& l : labels)
    for (const int id : ids_named(l.text)) named.push_back(id);
  std::sort(named.begin(), named.end());
  std::vector<int> all(37);
  std::iota(all.begin(), all.end(), 1);
  EXPECT_EQ(named, all);
  const Vec2 start = L.to_picture(f.data.start.translation()), goal = L.to_picture(f.data.goal);
  for (std::size_t a = 0; a < labels.size(); ++a) {
    const DrawnLabel& l = labels[a];
    EXPECT_TRUE(l.x0 >= L.plot_x && l.x1 <= L.plot_x + L.plot_w && l.y0 >= L.plot_y && l.y1 <= L.plot_y + L.plot_h) << l.text;
    for (const Vec2& m : {start, goal}) EXPECT_FALSE(m.x() > l.x0 && m.x() < l.x1 && m.y() > l.y0 && m.y() < l.y1) << l.text;
    for (std::size_t b = a + 1; b < labels.size(); ++b) {
      const DrawnLabel& o = labels[b];
      EXPECT_FALSE(l.x0 < o.x1 && o.x0 < l.x1 && l.y0 < o.y1 && o.y0 < l.y1) << l.text << " overlaps " << o.text;
    }
  }
  // Labels naming one plan keep its place and colour; the ten that started at one place share one.
  EXPECT_EQ(count(pic.svg_string(), ">P1</text>"), 1u);
  EXPECT_NE(pic.svg_string().find(">P2..P11, P37</text>"), std::string::npos);
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
  std::vector<int> named;
  for (const DrawnLabel& l : plan_labels(scene))
    for (const int id : ids_named(l.text)) named.push_back(id);
  std::sort(named.begin(), named.end());
  std::vector<int> drawn;
  for (const NavPlan& p : plans) {
    if (p.points.size() < 2) continue;
    drawn.push_back(p.id);
    const std::string label = ">P" + std::to_string(p.id) + "</text>";
    if (plans.size() <= 12) {
      EXPECT_EQ(count(overlay, label), 1u) << label;
    }
  }
  EXPECT_EQ(named, drawn);  // every plan drawn is named in the scene once
  EXPECT_NE(scene.find("executed trajectory"), std::string::npos);
  EXPECT_NE(scene.find("true obstacle"), std::string::npos);
  // Drawing again gives the same bytes.
  write_navigation_scene(run, dir.file("again.svg"));
  EXPECT_EQ(test::read_text(dir.file("again.svg")), scene);
}

}  // namespace
}  // namespace starnav
