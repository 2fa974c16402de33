// One rough-terrain query as a library call (plan_on_terrain) and its reports, on a ramp whose
// answers are closed forms; the generated terrain's metadata against the map it describes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "starnav/experiment/terrain_report.hpp"
#include "starnav/terrain/terrain_metadata.hpp"

namespace starnav {
namespace {

// 30 x 10 cells of 0.1 m rising 0.01 m per cell along x: slope atan(0.1), steps of 0.01 m.
ElevationMap ramp() {
  GridGeometry g;
  g.width = 30;
  g.height = 10;
  g.resolution = 0.1;
  ElevationMap m(g);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) m.set_height(x, y, 0.01 * x);
  return m;
}

TEST(TerrainPlanReport, AStraightRunUpARampHasTheClosedFormMetrics) {
  const ElevationMap m = ramp();
  RoughTerrainPlannerOptions options;
  options.record_trace = true;
  const TerrainPlanOutcome o = plan_on_terrain(m, {2, 5}, {22, 5}, RoughTerrainPlannerKind::OA, options);
  ASSERT_TRUE(o.result.found());
  EXPECT_NEAR(o.result.length, 2.0, 1e-9);                             // 20 moves of 0.1 m
  EXPECT_NEAR(o.metrics.lv_m, 20 * std::hypot(0.1, 0.01), 1e-9);       // each climbs 0.01 m
  EXPECT_NEAR(o.metrics.av_rad, std::atan(0.1), 1e-9);
  EXPECT_NEAR(o.metrics.hv_m, 0.01, 1e-9);
  ASSERT_EQ(o.path_z.size(), 21u);
  EXPECT_NEAR(o.path_z.back(), 0.22, 1e-9);
  EXPECT_FALSE(o.trace.empty());

  const auto j = nlohmann::json::parse(terrain_plan_json(o));
  EXPECT_EQ(j["planner"], "oa");
  EXPECT_EQ(j["path_cells"].size(), 21u);
  EXPECT_EQ(j["expanded_cells"].size(), o.trace.size());
  EXPECT_NEAR(j["lv_m"].get<double>(), o.metrics.lv_m, 1e-12);
  const std::string csv = terrain_plan_path_csv(o);
  EXPECT_EQ(csv.rfind("x_m,y_m,z_m,ix,iy\n", 0), 0u);
  EXPECT_NE(csv.find(",0.22,22,5\n"), std::string::npos) << csv;
  EXPECT_NE(terrain_plan_text(o).find("found:      yes, 21 points"), std::string::npos);

  // Outside the map: a result, not an error.
  const TerrainPlanOutcome out = plan_on_terrain(m, {2, 5}, {40, 5}, RoughTerrainPlannerKind::IA, {});
  EXPECT_FALSE(out.result.found());
  EXPECT_EQ(nlohmann::json::parse(terrain_plan_json(out))["lv_m"], nullptr);
}

TEST(TerrainMetadata, DescribesTheMapItCameWith) {
  HillsOptions h;
  h.width_m = 3.0;
  h.height_m = 2.0;
  h.seed = 9;
  const ElevationMap m = generate_hills(h);
  const auto j = nlohmann::json::parse(hills_metadata(h, m, "hills.asc", "asc"));
  EXPECT_EQ(j["kind"], "hills");
  EXPECT_EQ(j["seed"], 9u);
  EXPECT_EQ(j["width"], 30);
  EXPECT_EQ(j["height"], 20);
  EXPECT_DOUBLE_EQ(j["z_min_m"].get<double>(), m.height_range()->min);
  EXPECT_DOUBLE_EQ(j["z_max_m"].get<double>(), m.height_range()->max);
  EXPECT_EQ(j["file"], "hills.asc");
  RoadOptions r;
  r.width_m = 2.0;
  r.height_m = 2.0;
  const RoadTerrain t = generate_road(r);
  const auto jr = nlohmann::json::parse(road_metadata(r, t, "road.csv", "csv"));
  EXPECT_DOUBLE_EQ(jr["sigma_m"].get<double>(), std::sqrt(t.spectrum.sigma2));
  EXPECT_EQ(jr["class"], std::string(1, r.road_class));
}

}  // namespace
}  // namespace starnav
