// Pictures of a controller's steps (harness/local_planning_pictures): the crop of a map keeps its cells in
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
  o.controller_snapshot_times_s = {4.0, 2.0};
  NavigationRun run(load_scenario(file), o);
  run.run();
  ASSERT_EQ(run.controller_snapshots().size(), 2u);
  EXPECT_GE(run.controller_snapshots()[0].step.t_s, 2.0);
  EXPECT_LT(run.controller_snapshots()[0].step.t_s, 2.1);
  EXPECT_GE(run.controller_snapshots()[1].step.t_s, 4.0);
  const ControllerSnapshot& s = run.controller_snapshots()[0];
  // The DWA's every sample (15 x 9 x 15), each with its rollout from the step's pose.
  ASSERT_EQ(s.step.candidates.size(), 15u * 9u * 15u);
  ASSERT_GE(s.step.chosen, 0);
  for (const ControlCandidate& c : s.step.candidates) ASSERT_FALSE(c.trajectory.empty());
  const ControlCandidate& chosen = s.step.candidates[static_cast<std::size_t>(s.step.chosen)];
  EXPECT_EQ(chosen.status, CandidateStatus::Valid);
  EXPECT_EQ(chosen.twist.vx, s.step.command.vx);
  for (const ControlCandidate& c : s.step.candidates) {
    if (c.status == CandidateStatus::Valid) {
      EXPECT_GE(c.cost, chosen.cost);  // the chosen one is the cheapest valid
    }
  }
  ASSERT_EQ(s.step.points.size(), 1u);
  EXPECT_EQ(s.step.points[0].first, "local goal");
  const std::string svg = controller_step_picture(s, "t").svg_string();
  for (const char* label : {"chosen", "robot", "local goal", "valid (darker: cheaper)"})
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  const std::string speed = speed_profile_plot(run.simulation().trajectory(), "v").svg_string();
  for (const char* series : {">vx<", ">vy<", ">wz<"}) EXPECT_NE(speed.find(series), std::string::npos) << series;

  // The path follower's steps through the same role: its look-ahead point and tracking terms.
  const std::string e3 = std::string(STARNAV_SOURCE_DIR) + "/scenarios/e3_three_obstacles.yaml";
  o.controller_snapshot_times_s = {5.0};
  NavigationRun follower(load_scenario(e3), o);
  follower.run();
  ASSERT_EQ(follower.controller_snapshots().size(), 1u);
  const ControllerSnapshot& f = follower.controller_snapshots()[0];
  EXPECT_TRUE(f.step.candidates.empty());
  ASSERT_EQ(f.step.points.size(), 1u);
  EXPECT_EQ(f.step.points[0].first, "look-ahead");
  EXPECT_NE(controller_step_picture(f, "t").svg_string().find("look-ahead"), std::string::npos);
  // A controller without diagnostics is refused pictures.
  NavigationOptions toy = o;
  toy.controller = "straight_to_goal";
  EXPECT_THROW(NavigationRun(load_scenario(e3), toy), Error);
}

}  // namespace
}  // namespace starnav
