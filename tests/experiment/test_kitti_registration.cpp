// The KITTI registration experiment, short: one pair per sequence and two matchers against the
// reference poses, and the floor against the ground labels.
#include <gtest/gtest.h>

#include "starnav/core/error.hpp"
#include "starnav/experiment/kitti_registration_experiment.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(KittiRegistration, MatchersAgreeWithTheReferenceMotionOnRealScans) {
  const std::string dataset = test::shared_path("datasets/lidar3d/kitti_odometry_mini");
  if (dataset.empty()) GTEST_SKIP() << "../shared/datasets/lidar3d is not here";
  KittiRegistrationConfig c;
  c.dataset = dataset;
  c.frames = 2;
  c.matchers = {"icp_plane", "ndt_mt"};
  const KittiRegistrationResult r = run_kitti_registration(c);
  ASSERT_EQ(r.pairs.size(), 6u);
  for (const KittiPairResult& p : r.pairs) {
    SCOPED_TRACE(p.sequence + " " + p.matcher);
    EXPECT_TRUE(p.converged);
    // The sensor moved 0.1-0.9 m; the reference check of SOURCES.md reaches about 1 cm.
    EXPECT_GT(p.reference_motion_m, 0.05);
    EXPECT_LT(p.translation_error_m, 0.03);
    EXPECT_LT(p.rotation_error_deg, 0.15);
  }
  ASSERT_EQ(r.floors.size(), 6u);  // every frame read
  for (const KittiFloorResult& f : r.floors) {
    SCOPED_TRACE(f.sequence + " frame " + std::to_string(f.frame));
    ASSERT_TRUE(f.found);
    EXPECT_GT(f.normal_z, 0.99);
    EXPECT_NEAR(f.d, 1.75, 0.1);  // the sensor about 1.73 m above the road
    EXPECT_LT(f.median_ground_distance_m, 0.06);
    // The floor found from the scan alone is within 1.5 cm of the best any plane reaches on the
    // labelled ground, and that search does not lose to it by more than rounding.
    EXPECT_LT(f.median_ground_distance_m, f.least_median_ground_distance_m + 0.015);
    EXPECT_LE(f.least_median_ground_distance_m, f.median_ground_distance_m + 0.002);
  }
  EXPECT_EQ(r.references, (std::vector<std::string>{"semantickitti", "kitti_gt", "kitti_gt"}));
  EXPECT_NE(kitti_registration_markdown(r).find("| ndt_mt | 3 |"), std::string::npos);
}

TEST(KittiRegistration, BadConfigurationsNameTheirFlag) {
  KittiRegistrationConfig c;
  c.matchers = {"loam"};
  try {
    c.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--matchers");
  }
  c = {};
  c.sequences = {"03"};
  EXPECT_THROW(c.validate(), Error);
  c = {};
  c.dataset = "/nonexistent";
  EXPECT_THROW(run_kitti_registration(c), Error);
}

}  // namespace
}  // namespace starnav
