// Pictures of a DWA run (harness/local_planning_pictures): the crop of a map keeps its cells in
// place, a step picture draws the samples and the chosen one, the speed profile has its three
// series; and a run asked for snapshots keeps a step at each time with every sample.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "starnav/harness/local_planning_pictures.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {
namespace {

TEST(LocalPlanningPictures, CropKeepsCellsInPlace) {
  GridGeometry g;
  g.resolution = 0.1;
  g.width = 50;
  g.height = 40;
  OccupancyGrid map(g, kFreeOccupancy);
  map(20, 15) = kOccupiedOccupancy;
  const OccupancyGrid crop = crop_map(map, {2.05, 1.55}, 1.0);
  EXPECT_EQ(crop.width(), 10);
  const auto c = crop.geometry().world_to_cell(map.geometry().cell_center(20, 15));
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(crop(c->x, c->y), kOccupiedOccupancy);
  // Beyond the map: unknown.
  const OccupancyGrid edge = crop_map(map, {0.05, 0.05}, 1.0);
  EXPECT_EQ(edge(0, 0), kUnknownOccupancy);
}

TEST(LocalPlanningPictures, ARunKeepsItsSnapshotsAndDrawsThem) {
  const std::string file = std::string(STARNAV_SOURCE_DIR) + "/scenarios/dwa_doorway.yaml";
  NavigationOptions o;
  o.record_steps = false;
  o.dwa_snapshot_times_s = {4.0, 2.0};
  NavigationRun run(load_scenario(file), o);
  run.run();
  ASSERT_EQ(run.dwa_snapshots().size(), 2u);
  EXPECT_GE(run.dwa_snapshots()[0].step.t_s, 2.0);
  EXPECT_LT(run.dwa_snapshots()[0].step.t_s, 2.1);
  EXPECT_GE(run.dwa_snapshots()[1].step.t_s, 4.0);
  const DwaSnapshot& s = run.dwa_snapshots()[0];
  EXPECT_EQ(s.step.samples.size(), 15u * 9u * 15u);
  ASSERT_GE(s.step.chosen, 0);
  const std::string svg = dwa_step_picture(s, "t").svg_string();
  EXPECT_NE(svg.find("chosen"), std::string::npos);
  EXPECT_NE(svg.find("robot"), std::string::npos);
  const std::string speed = speed_profile_plot(run.simulation().trajectory(), "v").svg_string();
  for (const char* series : {">vx<", ">vy<", ">wz<"}) EXPECT_NE(speed.find(series), std::string::npos) << series;
  // Pictures of another controller's run are refused.
  const std::string e3 = std::string(STARNAV_SOURCE_DIR) + "/scenarios/e3_three_obstacles.yaml";
  EXPECT_THROW(NavigationRun(load_scenario(e3), o), Error);
}

}  // namespace
}  // namespace starnav
