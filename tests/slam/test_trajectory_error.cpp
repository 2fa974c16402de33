// Errors against known truth: the absolute trajectory error of a trajectory offset from the
// truth by a known amount; wall distances of a map against itself (no error), against a map
// whose east wall moved 0.15 m (that error on the east-west distances, none on the others), and
// the probes a built map did not see.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/slam/trajectory_error.hpp"

namespace starnav {
namespace {

TEST(AbsoluteTrajectoryError, MeasuresAKnownOffsetAgainstInterpolatedTruth) {
  RobotLog log;
  for (int k = 0; k <= 10; ++k) log.truth.push_back({k * 1'000'000, Pose2(k * 1.0, 0.0, 0.0), Pose2()});
  std::vector<TrajectoryPose> t;
  for (int k = 0; k < 20; ++k) t.push_back({k * 500'000, Pose2(k * 0.5, 0.3, 0.01 * k)});  // 0.3 m to the side
  t.push_back({20'000'000, Pose2()});                                                       // beyond the truth
  const AbsoluteTrajectoryError e = absolute_trajectory_error(t, log);
  EXPECT_EQ(e.translation_m.n, 20u);
  EXPECT_EQ(e.unmatched, 1u);
  EXPECT_NEAR(e.translation_m.mean, 0.3, 1e-12);
  EXPECT_NEAR(e.rmse_m, 0.3, 1e-12);
  EXPECT_NEAR(e.rotation_deg.max, 0.19 * 180.0 / 3.141592653589793, 1e-9);
  EXPECT_THROW(absolute_trajectory_error(t, RobotLog{}), Error);
}

// A 10 m x 6 m room at 0.05 m with 0.1 m walls and a 0.1 m partition at x = 4 from y = 0 to 3.
OccupancyGrid room(int east_wall_x) {
  OccupancyGrid g(GridGeometry{220, 140, 0.05, Pose2(-0.5, -0.5, 0.0)}, -1);
  for (int y = 10; y < 130; ++y)
    for (int x = 10; x < 210; ++x) g(x, y) = 0;
  for (int y = 10; y < 130; ++y)
    for (int x = 10; x < 210; ++x)
      if (x < 12 || y < 12 || x >= east_wall_x || y >= 128 || (x >= 90 && x < 92 && y < 70)) g(x, y) = 100;
  return g;
}

TEST(WallDistances, NoErrorAgainstItselfAndAMovedWallShows) {
  const OccupancyGrid truth = room(208);
  const WallDistanceOptions many{.count = 100, .stride_cells = 10};
  const std::vector<WallDistance> same = wall_distances(truth, {&truth}, many);
  ASSERT_GE(same.size(), 10u);
  // Measured between the centres of the walls' first cells: one cell longer than the free run.
  for (const WallDistance& w : same) EXPECT_NEAR(w.error_m(), 0.05, 1e-9);
  EXPECT_NEAR(wall_distance_mean_abs_error(same), 0.05, 1e-12);
  // A built map whose east wall stands 3 cells further east (0.15 m); both maps measured on the
  // same lines.
  OccupancyGrid moved(GridGeometry{230, 140, 0.05, Pose2(-0.5, -0.5, 0.0)}, -1);
  for (int y = 0; y < 140; ++y)
    for (int x = 0; x < 220; ++x) moved(x, y) = truth(x, y);
  for (int y = 10; y < 130; ++y)
    for (int x = 208; x < 214; ++x) moved(x, y) = x < 211 && y >= 12 && y < 128 ? 0 : 100;
  const std::vector<WallDistance> m = wall_distances(truth, {&truth, &moved}, many);
  ASSERT_EQ(m.size(), same.size());
  std::size_t east = 0;
  for (const WallDistance& w : m) {
    ASSERT_EQ(w.built_m.size(), 2u);
    EXPECT_NEAR(w.error_m(0), 0.05, 1e-9);
    // Along x, the runs ending at the east wall (from the partition, x = 4.6, or the west wall).
    const bool to_east = w.along_x && w.midpoint.x() > 4.6;
    EXPECT_NEAR(w.error_m(1) - w.error_m(0), to_east ? 0.15 : 0.0, 1e-9) << w.midpoint.transpose();
    east += to_east;
  }
  EXPECT_GT(east, 3u);
  // A built map that saw nothing of the room's north half: no line there is chosen.
  OccupancyGrid half = truth;
  for (int y = 70; y < 140; ++y)
    for (int x = 0; x < 220; ++x) half(x, y) = -1;
  const std::vector<WallDistance> h = wall_distances(truth, {&half}, many);
  EXPECT_LT(h.size(), same.size());
  for (const WallDistance& w : h) EXPECT_LT(w.midpoint.y() + (w.along_x ? 0.0 : 0.5 * w.true_m), 3.0);
  const OccupancyGrid rotated(GridGeometry{4, 4, 0.05, Pose2(0, 0, 0.1)}, 0);
  EXPECT_THROW(wall_distances(rotated, {&truth}), Error);
  EXPECT_THROW(wall_distances(truth, {}), Error);
}

}  // namespace
}  // namespace starnav
