// Uses an installed starnav: builds an OccupancyGrid, parses a MovingAI map from text, converts
// cells to world coordinates, plans with inflation and gradient smoothing in one call
// (plan_on_grid, what `starnav plan --smooth gradient` runs), and calls into the file readers (which pull yaml-cpp, libpng and,
// when starnav was built with it, GDAL into the link). scripts/install-check.sh checks the output.
#include <cstdio>
#include <string>

#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/plan_pipeline.hpp"

int main() {
  std::printf("starnav %s, gdal=%d\n", STARNAV_VERSION, STARNAV_HAVE_GDAL);

  // A metric grid: 4 x 3 cells of 0.5 m, lower-left corner at (1, 2).
  starnav::GridGeometry geometry;
  geometry.width = 4;
  geometry.height = 3;
  geometry.resolution = 0.5;
  geometry.origin = starnav::Pose2(1.0, 2.0, 0.0);
  starnav::OccupancyGrid grid(geometry, starnav::kFreeOccupancy);
  grid.set(1, 2, starnav::kOccupiedOccupancy);
  grid.set(3, 0, starnav::kUnknownOccupancy);
  const auto counts = grid.counts();
  const starnav::Vec2 centre = grid.geometry().cell_center(1, 2);
  std::printf("grid: %dx%d free=%zu occupied=%zu unknown=%zu cell(1,2)->(%.2f, %.2f)\n", grid.width(),
              grid.height(), counts.free, counts.occupied, counts.unknown, centre.x(), centre.y());

  // A MovingAI map from text (index grid: resolution 1, origin 0).
  const std::string text = "type octile\nheight 3\nwidth 4\nmap\n.@..\n..T.\n....\n";
  const starnav::MovingAiMap map = starnav::parse_movingai_map(text, "consumer.map");
  const starnav::OccupancyGrid occupancy = map.to_occupancy();
  const auto map_counts = occupancy.counts();
  const starnav::Vec2 c = occupancy.geometry().cell_center(2, 1);
  std::printf("movingai: %dx%d free=%zu occupied=%zu cell(2,1)='%c'->(%.2f, %.2f)\n", map.width, map.height,
              map_counts.free, map_counts.occupied, map.at(2, 1), c.x(), c.y());

  // One planning query as `starnav plan --inflate 0.2 --smooth gradient` runs it: improved A*
  // features, gradient smoothing on the inflated map, path metrics, in one call.
  starnav::GridGeometry room_geometry;
  room_geometry.width = 40;
  room_geometry.height = 20;
  room_geometry.resolution = 0.1;
  starnav::OccupancyGrid room(room_geometry, starnav::kFreeOccupancy);
  for (int y = 0; y < 14; ++y) room.set(20, y, starnav::kOccupiedOccupancy);  // a wall with a gap at the top
  starnav::PlanRequest request;
  request.planner = "astar";
  request.options.ou2022.inflation.radius_m = 0.2;
  request.smoothing = starnav::PlanSmoothing::Gradient;
  const starnav::PlanOutcome plan = starnav::plan_on_grid(room, {2, 2}, {37, 2}, request);
  std::printf("plan: %s found=%d smoothed=%d clearance_min=%.2f m\n", std::string(plan.planner->name()).c_str(),
              plan.result.found() ? 1 : 0, plan.smoothed ? 1 : 0, plan.metrics.clearance_min);

  // Bad input is a starnav::Error (and these calls link the YAML/PNG and GDAL code paths).
  int errors = 0;
  try {
    (void)starnav::parse_movingai_map("type octile\nheight 1\nwidth 2\nmap\n.\n", "bad.map");
  } catch (const starnav::Error&) {
    ++errors;
  }
  try {
    (void)starnav::read_elevation_yaml("/nonexistent/starnav-consumer.yaml");
  } catch (const starnav::Error&) {
    ++errors;
  }
  try {
    (void)starnav::read_geotiff("/nonexistent/starnav-consumer.tif");
  } catch (const starnav::Error&) {
    ++errors;
  }
  std::printf("errors: %d of 3\n", errors);
  std::printf("consumer: ok\n");
  return errors == 3 ? 0 : 1;
}
