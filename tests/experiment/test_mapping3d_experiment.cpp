// The simulated 3D mapping experiment, short: one seed, a few seconds of the indoor run at a coarse
// horizontal resolution, GICP with and without the floor constraint.
#include <gtest/gtest.h>

#include <fstream>

#include "starnav/core/error.hpp"
#include "starnav/experiment/mapping3d_experiment.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(Mapping3dExperiment, ShortRunMapsWithinCentimetresAndTheFloorHelps) {
  Mapping3dExperimentConfig c;
  c.scenario = test::scenario_path("ou2022_mapping3d.yaml");
  c.seeds = 1;
  c.matchers = {"gicp"};
  c.overrides = {parse_scenario_override("sim.duration_s=15"), parse_scenario_override("sensors.lidar.horizontal_resolution_deg=0.5")};
  c.plan_goal = Vec2(4.5, 1.2);  // along the corridor the short run has seen
  const Mapping3dResult r = run_mapping3d_experiment(c);
  ASSERT_EQ(r.runs.size(), 2u);
  const Mapping3dRun& with = r.runs[0];
  const Mapping3dRun& without = r.runs[1];
  EXPECT_EQ(with.variant, "gicp");
  EXPECT_EQ(without.variant, "gicp_no_floor");
  EXPECT_EQ(with.frames, 151u);
  EXPECT_GT(with.driven_m, 4.0);
  EXPECT_LT(with.ate_rmse_m, 0.05);
  EXPECT_LT(with.elevation_drift_m, 0.04);
  EXPECT_GT(with.floor_edges, 0u);
  EXPECT_EQ(without.floor_edges, 0u);
  // The floor constraint never makes the height worse (a little slack for rounding).
  EXPECT_LE(with.elevation_drift_m, without.elevation_drift_m + 0.005);
  // The map of the GICP run against the world's true occupancy, and the improved A* on it.
  ASSERT_TRUE(with.mapped);
  EXPECT_FALSE(without.mapped);
  EXPECT_GT(with.occupied_cells, 200u);
  EXPECT_GE(with.occupied_iou, 0.9);
  EXPECT_TRUE(with.path_found);
  EXPECT_TRUE(with.path_collision_free);
  EXPECT_GT(with.path_length_m, 2.5);  // about 2.8 m in a straight line
  // The filters shrink every frame, in order (Fig. 9).
  EXPECT_GT(with.raw_points, with.voxelised_points);
  EXPECT_GE(with.voxelised_points, with.kept_points);
  test::ScratchDir dir;
  write_mapping3d_figures(r, dir.path().string());
  for (const char* f : {"x.svg", "y.svg", "z.svg", "error.svg", "filters.svg"})
    EXPECT_TRUE(std::ifstream(dir.file(f)).good()) << f;
  EXPECT_NE(mapping3d_markdown(r).find("| gicp_no_floor | 1 |"), std::string::npos);
}

TEST(Mapping3dExperiment, BadConfigurationsNameTheirFlag) {
  Mapping3dExperimentConfig c;
  c.matchers = {"loam"};
  try {
    c.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--matchers");
  }
  c = {};
  c.seeds = 0;
  EXPECT_THROW(c.validate(), Error);
}

}  // namespace
}  // namespace starnav
