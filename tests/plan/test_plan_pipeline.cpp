// The plan pipeline (plan_on_grid): the same search as the planner alone, the metrics of the
// reported path with the clearance field the planner saw, gradient smoothing on the inflated map
// that keeps the path out of the inflation, and the inflated map computed only when needed.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/plan/plan_pipeline.hpp"

namespace starnav {
namespace {

OccupancyGrid room() {
  GridGeometry g;
  g.width = 40;
  g.height = 20;
  g.resolution = 0.1;
  OccupancyGrid grid(g, kFreeOccupancy);
  for (int y = 0; y < 14; ++y) grid.set(20, y, kOccupiedOccupancy);
  return grid;
}

TEST(PlanPipeline, SearchesExactlyAsThePlannerAloneAndMeasuresTheReportedPath) {
  const OccupancyGrid grid = room();
  PlanRequest rq;
  rq.planner = "jps";
  const PlanOutcome out = plan_on_grid(grid, {2, 2}, {37, 2}, rq);
  const PlanResult alone = make_grid_planner("jps", grid)->plan({2, 2}, {37, 2});
  ASSERT_TRUE(out.result.found());
  EXPECT_EQ(out.result.cost, alone.cost);
  EXPECT_EQ(out.result.path_cells, alone.path_cells);
  EXPECT_FALSE(out.inflated.has_value());  // nothing needed it
  const ClearanceField clearance = ClearanceField::of_grid(grid);
  const PathMetrics m = compute_path_metrics(out.path(), &clearance);
  EXPECT_EQ(out.metrics.length, m.length);
  EXPECT_EQ(out.metrics.clearance_min, m.clearance_min);
}

TEST(PlanPipeline, GradientSmoothingStaysOutOfTheInflationAndShortensNothingBelowTheStraightLine) {
  const OccupancyGrid grid = room();
  PlanRequest rq;
  rq.options.ou2022.inflation.radius_m = 0.2;
  rq.smoothing = PlanSmoothing::Gradient;
  const PlanOutcome out = plan_on_grid(grid, {2, 2}, {37, 2}, rq);
  ASSERT_TRUE(out.result.found());
  ASSERT_TRUE(out.smoothed.has_value());
  ASSERT_TRUE(out.inflated.has_value());
  EXPECT_EQ(&out.path(), &out.smoothed->points);
  // Every smoothed point keeps more than the inflation radius from the wall (x = 2.0..2.1 m, y < 1.4 m).
  for (const Vec2& p : out.path()) {
    const double dx = std::max({0.0, 2.0 - p.x(), p.x() - 2.1});
    const double dy = std::max(0.0, p.y() - 1.4);
    EXPECT_GT(std::hypot(dx, dy), 0.2 - 0.05) << p.transpose();
  }
  EXPECT_GT(out.metrics.clearance_min, 0.2);
  // Longer than the straight line, since the wall is in the way.
  EXPECT_GT(out.metrics.length, (grid.geometry().cell_center(37, 2) - grid.geometry().cell_center(2, 2)).norm());
}

TEST(PlanPipeline, BadRequestsAreErrorsAndNoPathIsAResult) {
  const OccupancyGrid grid = room();
  PlanRequest rq;
  rq.planner = "nonesuch";
  EXPECT_THROW(plan_on_grid(grid, {2, 2}, {37, 2}, rq), Error);
  EXPECT_THROW(parse_plan_smoothing("spline"), Error);
  EXPECT_EQ(parse_plan_smoothing("gradient"), PlanSmoothing::Gradient);
  rq.planner = "astar";
  const PlanOutcome blocked = plan_on_grid(grid, {2, 2}, {20, 2}, rq);  // the goal is in the wall
  EXPECT_FALSE(blocked.result.found());
  EXPECT_FALSE(blocked.smoothed.has_value());
}

}  // namespace
}  // namespace starnav
