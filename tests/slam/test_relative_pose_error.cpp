// The relative-pose error against hand-built trajectories with known answers (angle wrap
// included), the stamp matching rule, the relation file format, and on ../shared/ the
// odometry-only errors carmen_raw/SOURCES.md states for aces, mit-csail and fr079.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/relative_pose_error.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

PoseRelation relation(std::int64_t i, std::int64_t j, const Pose2& d) {
  PoseRelation r;
  r.t_i_us = i;
  r.t_j_us = j;
  r.delta = d;
  return r;
}

TEST(RelativePoseError, ZeroOnTheTruthAndKnownValuesOnAPerturbedTrajectory) {
  // A square drive; relations between consecutive poses from the truth.
  std::vector<TrajectoryPose> truth;
  for (int k = 0; k < 8; ++k) truth.push_back({k * 1'000'000, Pose2(std::cos(k * 0.8), std::sin(k * 0.8), wrap_angle(k * 0.8 + 1.5))});
  std::vector<PoseRelation> rel;
  for (int k = 0; k + 1 < 8; ++k) rel.push_back(relation(k * 1'000'000, (k + 1) * 1'000'000, truth[k].pose.inverse().compose(truth[k + 1].pose)));
  const RelativePoseError zero = relative_pose_error(truth, rel);
  EXPECT_EQ(zero.translation_m.n, 7u);
  EXPECT_NEAR(zero.translation_m.max, 0.0, 1e-12);
  EXPECT_NEAR(zero.rotation_deg.max, 0.0, 1e-9);
  // Moving the whole trajectory rigidly changes no relation.
  std::vector<TrajectoryPose> moved = truth;
  for (TrajectoryPose& p : moved) p.pose = Pose2(3.0, -2.0, 1.0).compose(p.pose);
  EXPECT_NEAR(relative_pose_error(moved, rel).translation_m.max, 0.0, 1e-12);
  // Pose 3 moved 0.1 m along its own x and turned 2 deg: relations 2-3 and 3-4 change.
  std::vector<TrajectoryPose> bent = truth;
  bent[3].pose = bent[3].pose.compose(Pose2(0.1, 0.0, deg_to_rad(2.0)));
  const RelativePoseError e = relative_pose_error(bent, rel);
  EXPECT_NEAR(e.rotation_deg.mean, 4.0 / 7.0, 1e-9);
  EXPECT_NEAR(e.rotation_deg.max, 2.0, 1e-9);
  // Relation 2-3: the end moved by 0.1 m. Relation 3-4: the start moved and turned, so the end
  // seen from it moves by the rotation of the 3-4 vector plus the 0.1 m shift.
  const Pose2 d34 = truth[3].pose.inverse().compose(truth[4].pose);
  const Pose2 est34 = Pose2(0.1, 0.0, deg_to_rad(2.0)).inverse().compose(d34);
  const double e34 = std::hypot(est34.x - d34.x, est34.y - d34.y);
  EXPECT_NEAR(e.translation_m.max, std::max(0.1, e34), 1e-12);
  EXPECT_NEAR(e.translation_m.mean, (0.1 + e34) / 7.0, 1e-12);
  // The laser offset: a mount ahead of the base turns rotation errors into translation errors.
  const RelativePoseError laser = relative_pose_error(bent, rel, Pose2(0.5, 0.0, 0.0));
  EXPECT_NE(laser.translation_m.mean, e.translation_m.mean);
  EXPECT_NEAR(laser.rotation_deg.mean, e.rotation_deg.mean, 1e-9);
}

TEST(RelativePoseError, RotationErrorsWrapAroundPi) {
  const std::vector<TrajectoryPose> t = {{0, Pose2(0, 0, 0)}, {1'000'000, Pose2(0, 0, -3.1)}};
  const RelativePoseError e = relative_pose_error(t, {relation(0, 1'000'000, Pose2(0, 0, 3.1))});
  EXPECT_NEAR(e.rotation_deg.mean, rad_to_deg(2 * kPi - 6.2), 1e-9);  // 4.77 deg, not 355
}

TEST(RelativePoseError, StampsMatchWithinOneUnitOfTheLastDecimal) {
  const std::vector<PoseRelation> rel = parse_relations(
      "# comment\n"
      "1.000000 2.000000 1 0 0 0 0 0\n"
      "1.00001 2.00000 1 0 0  0 0 0\n"
      "1.000003 2.000000 1 0 0 0 0 0\n",
      "r.relations");
  ASSERT_EQ(rel.size(), 3u);
  EXPECT_EQ(rel[0].tolerance_us, 1);
  EXPECT_EQ(rel[1].tolerance_us, 10);
  const std::vector<TrajectoryPose> t = {{1'000'002, Pose2(0, 0, 0)}, {2'000'000, Pose2(1, 0, 0)}, {1'000'015, Pose2(5, 5, 0)}};
  const RelativePoseError e = relative_pose_error(t, rel);
  // 1.000000 is 2 us from the nearest pose: unmatched at 6 decimals; 1.00001 (5 decimals) takes
  // the nearest within 10 us (1.000015); 1.000003 is 1 us from 1.000002: matched.
  EXPECT_EQ(e.translation_m.n, 2u);
  EXPECT_EQ(e.unmatched, 1u);
  EXPECT_NEAR(e.translation_m.max, std::hypot(5.0, 5.0), 1e-12);  // (5, 5) to (1, 0) is (-4, -5), against (1, 0)
}

TEST(RelativePoseError, MalformedRelationFilesNameLineAndColumn) {
  struct Row {
    const char* text;
    int line;
    const char* field;
  };
  for (const Row& r : {Row{"1 2 3\n", 1, ""}, Row{"# x\n1.0 2.0 a 0 0 0 0 0\n", 2, "dx"}, Row{"1.0 x 0 0 0 0 0 0\n", 1, "t_j"},
                       Row{"1.0 2.0 0 0 0 0 0 inf\n", 1, "dyaw"}}) {
    try {
      parse_relations(r.text, "bad.relations");
      ADD_FAILURE() << r.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.line(), r.line) << r.text;
      EXPECT_EQ(e.field(), r.field) << r.text;
    }
  }
  EXPECT_THROW(parse_relations("# only\n", "empty.relations"), Error);
}

// carmen_raw/SOURCES.md: odometry-only RPE over all relations (pose at a scan = odometry
// interpolated at its stamp): aces 0.55 m / 2.2 deg, mit-csail 1.68 m / 5.1 deg, fr079 6.50 m / 30.3 deg.
TEST(RelativePoseError, OdometryAloneGivesTheErrorsTheSourcesState) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/slam_benchmark_relations/aces.relations");
  struct Row {
    const char* log;
    const char* relations;
    double trans_m, rot_deg;
    std::size_t count;
  };
  for (const Row& r : {Row{"datasets/carmen_raw/ros1_bags/aces.orig.bag", "datasets/slam_benchmark_relations/aces.relations", 0.55, 2.2, 1279},
                       Row{"datasets/carmen_raw/mit-csail.clf.gz", "datasets/slam_benchmark_relations/mit-csail.relations", 1.68, 5.1, 1172},
                       Row{"datasets/carmen_raw/ros1_bags/fr079.orig.bag", "datasets/slam_benchmark_relations/fr079.relations", 6.50, 30.3, 1685}}) {
    if (test::shared_path(r.log).empty()) continue;
    const RobotLog log = read_robot_log(test::shared_path(r.log));
    const RelativePoseError e = relative_pose_error(odometry_trajectory(log), read_relations(test::shared_path(r.relations)));
    EXPECT_EQ(e.unmatched, 0u) << r.log;
    EXPECT_EQ(e.translation_m.n, r.count) << r.log;
    EXPECT_NEAR(e.translation_m.mean, r.trans_m, 0.006) << r.log;
    EXPECT_NEAR(e.rotation_deg.mean, r.rot_deg, 0.06) << r.log;
  }
}

}  // namespace
}  // namespace starnav

namespace starnav {
namespace {

// Short relations are those at most 10 s apart (inclusive), long the rest; unmatched ones
// (NaN) are in neither; the means and maxima are the hand-computed ones.
TEST(RelationSpans, SplitsTheErrorsByTheirPosesTimeApart) {
  const auto rel = [](std::int64_t ti, std::int64_t tj) {
    PoseRelation r;
    r.t_i_us = ti;
    r.t_j_us = tj;
    return r;
  };
  const std::vector<PoseRelation> relations = {rel(0, 1'000'000), rel(5'000'000, 15'000'000), rel(0, 2'000'000),
                                               rel(20'000'000, 9'500'000), rel(0, 100'000'000)};
  RelativePoseError e;
  e.translation_each_m = {0.1, 0.2, std::numeric_limits<double>::quiet_NaN(), 0.4, 0.8};
  const RelationSpans s = relation_spans(e, relations);
  EXPECT_EQ(s.short_m.n, 2u);
  EXPECT_NEAR(s.short_m.mean, 0.15, 1e-12);
  EXPECT_EQ(s.long_m.n, 2u);  // 10.5 s apart (in either order) and 100 s
  EXPECT_NEAR(s.long_m.mean, 0.6, 1e-12);
  EXPECT_NEAR(s.long_m.max, 0.8, 1e-12);
  EXPECT_NEAR(s.long_p95_m, 0.4 + 0.95 * 0.4, 1e-12);
  e.translation_each_m.pop_back();
  EXPECT_THROW(relation_spans(e, relations), Error);
}

}  // namespace
}  // namespace starnav
