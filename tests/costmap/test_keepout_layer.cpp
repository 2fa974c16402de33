// The keepout costmap layer, found by name in the registry: its cells against an independent
// rasterisation (each cell's square clipped by the polygon, Sutherland-Hodgman, area > 0), its
// obstacles equal to the same cells given as a prior map, its parameter errors; then a whole run
// in which the planner routes round the zone and the body never enters it, while the same run
// without the layer drives through it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/costmap/keepout_layer.hpp"
#include "starnav/costmap/layered_costmap.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"
#include "support/polygon_clip.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

GridGeometry grid(int w, int h, double res, double ox, double oy, double yaw = 0.0) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = Pose2(ox, oy, yaw);
  return g;
}

// Every cell's square (in world coordinates, rotated with the grid) clipped by the polygon.
std::vector<std::uint8_t> reference_cells(const GridGeometry& g, const std::vector<Vec2>& polygon) {
  std::vector<std::uint8_t> mask(g.cell_count(), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      std::vector<Vec2> square = {g.grid_to_world({x * g.resolution, y * g.resolution}),
                                  g.grid_to_world({(x + 1) * g.resolution, y * g.resolution}),
                                  g.grid_to_world({(x + 1) * g.resolution, (y + 1) * g.resolution}),
                                  g.grid_to_world({x * g.resolution, (y + 1) * g.resolution})};
      // The square is convex and counter-clockwise: clip the polygon by its four edges.
      const std::vector<Vec2> part = test::clip_by_convex(polygon, square);
      if (part.size() >= 3 && test::shoelace_area(part) > 1e-12) mask[g.index(x, y)] = 1;
    }
  return mask;
}

TEST(KeepoutLayer, CellsAreThoseTheZoneOverlapsByAnIndependentClip) {
  Rng rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    SCOPED_TRACE(trial);
    const double yaw = trial % 3 == 0 ? rng.uniform(-1.0, 1.0) : 0.0;
    const GridGeometry g = grid(31, 23, 0.1, rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), yaw);
    // Centres inside, near an edge and outside the grid (clipped).
    const Vec2 centre = g.grid_to_world({rng.uniform(-0.5, 3.6), rng.uniform(-0.5, 2.8)});
    const std::vector<Vec2> poly = test::random_star_polygon(rng, centre, trial % 5 == 0 ? 0.07 : 1.2);
    ASSERT_EQ(rasterize_polygon_cells(g, poly), reference_cells(g, poly));
  }
}

TEST(KeepoutLayer, AZoneOnCellLinesTakesOnlyTheCellsInside) {
  // Edges exactly on the cell lines, and a concave zone: touching cells are not taken.
  const GridGeometry g = grid(6, 5, 0.5, 0.0, 0.0);
  const std::vector<Vec2> square = {{0.5, 0.5}, {1.5, 0.5}, {1.5, 1.5}, {0.5, 1.5}};
  std::vector<std::uint8_t> want(g.cell_count(), 0);
  for (const Cell c : {Cell{1, 1}, Cell{2, 1}, Cell{1, 2}, Cell{2, 2}}) want[g.index(c.x, c.y)] = 1;
  EXPECT_EQ(rasterize_polygon_cells(g, square), want);
  const std::vector<Vec2> ell = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.5}, {0.5, 0.5}, {0.5, 1.5}, {0.0, 1.5}};
  EXPECT_EQ(rasterize_polygon_cells(g, ell), reference_cells(g, ell));
  std::vector<std::uint8_t> want_ell(g.cell_count(), 0);
  for (const Cell c : {Cell{0, 0}, Cell{1, 0}, Cell{0, 1}, Cell{0, 2}}) want_ell[g.index(c.x, c.y)] = 1;
  EXPECT_EQ(rasterize_polygon_cells(g, ell), want_ell);
}

TEST(KeepoutLayer, FromTheRegistryItsObstaclesEqualThoseOfAPriorMap) {
  const GridGeometry g = grid(80, 60, 0.05, -1.0, -0.5);
  CostmapLayerContext ctx;
  ctx.geometry = g;
  ctx.map.barrier_distance_m = 0.3;
  ctx.file = "k.yaml";
  const std::vector<ParamSetting> settings = {
      {"zones", "[[[0.2, 0.3], [1.4, 0.1], [1.1, 1.2]], [[2.0, 1.0], [2.6, 1.0], [2.6, 2.0], [2.3, 1.4], [2.0, 2.0]]]", "k.yaml", 3,
       "navigation.keepout.zones"}};
  std::vector<std::unique_ptr<CostmapLayer>> with_zones;
  with_zones.push_back(find_costmap_layer("keepout", "navigation.layers").make(ctx, settings));
  const LayeredCostmap a(g, ctx.map, std::move(with_zones));

  std::vector<std::uint8_t> mask(g.cell_count(), 0);
  for (const auto& zone : parse_param_polygons(settings[0])) {
    std::vector<Vec2> poly;
    for (const auto& p : zone) poly.emplace_back(p[0], p[1]);
    const std::vector<std::uint8_t> cells = reference_cells(g, poly);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] |= cells[i];
  }
  CostmapLayerContext prior = ctx;
  prior.prior_obstacles = mask;
  std::vector<std::unique_ptr<CostmapLayer>> as_prior;
  as_prior.push_back(find_costmap_layer("static_map", "navigation.layers").make(prior, {}));
  const LayeredCostmap b(g, ctx.map, std::move(as_prior));

  EXPECT_EQ(a.raw_blocked(), b.raw_blocked());
  EXPECT_EQ(a.blocked(), b.blocked());
  EXPECT_GT(std::count(a.raw_blocked().begin(), a.raw_blocked().end(), 1), 100);
  EXPECT_GT(std::count(a.blocked().begin(), a.blocked().end(), 1), std::count(a.raw_blocked().begin(), a.raw_blocked().end(), 1));
}

TEST(KeepoutLayer, ParameterErrorsNameTheSetting) {
  CostmapLayerContext ctx;
  ctx.geometry = grid(10, 10, 0.1, 0.0, 0.0);
  ctx.file = "k.yaml";
  const CostmapLayerDef& def = find_costmap_layer("keepout", "navigation.layers");
  for (const ParamSetting& bad : std::vector<ParamSetting>{{"zones", "[[[0, 0], [1, 0]]]", "k.yaml", 4, "navigation.keepout.zones"},
                                                           {"zone", "[]", "k.yaml", 5, "navigation.keepout.zone"}}) {
    try {
      def.make(ctx, std::vector<ParamSetting>{bad});
      ADD_FAILURE() << "accepted " << bad.key << "=" << bad.value;
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "k.yaml");
      EXPECT_EQ(e.line(), bad.line);
      EXPECT_EQ(e.field(), bad.field);
    }
  }
  // Many edges, each spanning a huge grid: refused before the work.
  ctx.geometry = grid(40000, 40000, 0.05, 0.0, 0.0);
  std::string zigzag = "[[";
  for (int i = 0; i < 6000; ++i) zigzag += (i ? ", [" : "[") + std::to_string(i * 0.1) + (i % 2 ? ", 0]" : ", 1999]");
  zigzag += "]]";
  try {
    def.make(ctx, std::vector<ParamSetting>{{"zones", zigzag, "k.yaml", 6, "navigation.keepout.zones"}});
    ADD_FAILURE() << "accepted a zone of 6000 edges across 40000 rows";
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 6);
    EXPECT_NE(std::string(e.what()).find("grid rows"), std::string::npos) << e.what();
  }
}

// The corners of the robot's body at a trajectory sample.
std::vector<Vec2> body_at(const TrajectorySample& s, double length, double width) {
  const double c = std::cos(s.rpy.z()), si = std::sin(s.rpy.z());
  std::vector<Vec2> corners;
  for (const auto& [dx, dy] : {std::pair{0.5, 0.5}, std::pair{-0.5, 0.5}, std::pair{-0.5, -0.5}, std::pair{0.5, -0.5}}) {
    const double bx = dx * length, by = dy * width;
    corners.emplace_back(s.position.x() + c * bx - si * by, s.position.y() + si * bx + c * by);
  }
  return corners;
}

// Separating axes of two convex polygons.
bool convex_overlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  for (const std::vector<Vec2>* poly : {&a, &b})
    for (std::size_t i = 0; i < poly->size(); ++i) {
      const Vec2 e = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      const Vec2 axis(-e.y(), e.x());
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const Vec2& p : a) amin = std::min(amin, axis.dot(p)), amax = std::max(amax, axis.dot(p));
      for (const Vec2& p : b) bmin = std::min(bmin, axis.dot(p)), bmax = std::max(bmax, axis.dot(p));
      if (amax < bmin || bmax < amin) return false;
    }
  return true;
}

TEST(KeepoutLayer, ThePlannerAndTheControllerKeepTheBodyOutOfTheZone) {
  const std::string file = test::scenario_path("keepout_two_doors.yaml");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::vector<Vec2> zone = {{3.4, 0.8}, {4.6, 0.8}, {4.6, 2.2}, {3.4, 2.2}};
  // The same world without the layer (and its section): the near door is the way.
  std::string without = text.str();
  without.replace(without.find("layers: [static_map, node_height, keepout]"), 42, "layers: [static_map, node_height]");
  without.erase(without.find("  keepout:"), without.find("\nsim:") - without.find("  keepout:"));

  int entered[2] = {0, 0};
  for (int with_layer = 0; with_layer < 2; ++with_layer) {
    SCOPED_TRACE(with_layer ? "with the keepout layer" : "without it");
    const ScenarioSpec spec = parse_scenario(with_layer ? text.str() : without, file);
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun run(spec, o);
    if (with_layer) {
      // The controllers read the same map: the zone's cells are obstacles at zero clearance.
      const LayeredCostmap& map = run.navigator().map();
      const std::optional<Cell> inside = map.geometry().world_to_cell({4.0, 1.5});
      ASSERT_TRUE(inside);
      EXPECT_TRUE(map.raw_blocked(inside->x, inside->y));
    }
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
    EXPECT_EQ(m.collisions, 0);
    for (const TrajectorySample& s : run.simulation().trajectory())
      if (convex_overlap(body_at(s, spec.vehicle.robot.body_length_m, spec.vehicle.robot.body_width_m), zone)) ++entered[with_layer];
  }
  EXPECT_GT(entered[0], 100) << "without the layer the robot takes the near door";
  EXPECT_EQ(entered[1], 0) << "with it the body never overlaps the zone";
}

}  // namespace
}  // namespace starnav
