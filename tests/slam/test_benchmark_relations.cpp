// Relations made from a trajectory's truth by the benchmark's rule (slam/benchmark_relations.hpp):
// the set the hashed search finds equals a brute-force scan over every pair of key poses; every
// relation is the true relative pose; the written file reads back through the relation reader
// and evaluates to zero on the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/slam/benchmark_relations.hpp"

namespace starnav {
namespace {

// Three laps of a 30 m x 20 m rectangle, every 0.1 m, wobbling sideways, with turns on the spot at
// the corners and a wander off the rectangle on the second lap: laps that meet again in space.
std::vector<TrajectoryPose> looping_truth() {
  Rng rng(5);
  std::vector<TrajectoryPose> t;
  std::int64_t stamp = 1'000'000;
  const double corners[4][2] = {{0, 0}, {30, 0}, {30, 20}, {0, 20}};
  for (int lap = 0; lap < 3; ++lap)
    for (int c = 0; c < 4; ++c) {
      const double* a = corners[c];
      const double* b = corners[(c + 1) % 4];
      const double yaw = std::atan2(b[1] - a[1], b[0] - a[0]);
      for (int turn = 0; turn < 15; ++turn) t.push_back({stamp += 100'000, Pose2(a[0], a[1], wrap_angle(yaw - 1.5 + 0.1 * turn))});
      const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
      for (double s = 0; s < len; s += 0.1) {
        const double side = 0.3 * std::sin(s / 3.0 + lap) + rng.normal(0.0, 0.01) + (lap == 1 && c == 2 ? 3.0 * std::sin(s / len * kPi) : 0.0);
        t.push_back({stamp += 100'000, Pose2(a[0] + (b[0] - a[0]) * s / len - std::sin(yaw) * side,
                                             a[1] + (b[1] - a[1]) * s / len + std::cos(yaw) * side, yaw)});
      }
    }
  return t;
}

TEST(BenchmarkRelations, TheRuleMatchesABruteForceScan) {
  const std::vector<TrajectoryPose> truth = looping_truth();
  RelationRule rule;
  rule.loop_max_distance_m = 1.5;
  rule.loop_min_travel_m = 40.0;
  rule.loop_every = 3;
  const BenchmarkRelations r = make_benchmark_relations(truth, rule);

  // Brute force: key poses by the rule's words, then every pair.
  std::vector<std::size_t> keys = {0};
  std::vector<double> travel_at = {0.0};
  double travel = 0, dist = 0, turned = 0;
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const double step = (truth[i].pose.translation() - truth[i - 1].pose.translation()).norm();
    travel += step, dist += step, turned += std::abs(wrap_angle(truth[i].pose.yaw - truth[i - 1].pose.yaw));
    if (dist >= rule.key_distance_m || turned >= deg_to_rad(rule.key_angle_deg)) keys.push_back(i), travel_at.push_back(travel), dist = turned = 0;
  }
  EXPECT_EQ(r.key_poses, keys.size());
  std::set<std::pair<std::int64_t, std::int64_t>> expected;
  for (std::size_t k = 0; k + 1 < keys.size(); ++k) expected.insert({truth[keys[k]].stamp_us, truth[keys[k + 1]].stamp_us});
  std::size_t loops = 0;
  for (std::size_t i = 0; i < keys.size(); i += rule.loop_every) {
    const Vec2 p = truth[keys[i]].pose.translation();
    std::size_t best = 0;
    double best_d = 1e300;
    bool in_visit = false;
    for (std::size_t j = i + 1; j <= keys.size(); ++j) {
      const bool near = j < keys.size() && travel_at[j] - travel_at[i] >= rule.loop_min_travel_m &&
                        (truth[keys[j]].pose.translation() - p).norm() <= rule.loop_max_distance_m;
      if (near) {
        const double d = (truth[keys[j]].pose.translation() - p).norm();
        if (!in_visit || d < best_d) best = j, best_d = d;
        in_visit = true;
      } else if (in_visit) {
        expected.insert({truth[keys[i]].stamp_us, truth[keys[best]].stamp_us});
        ++loops;
        in_visit = false;
      }
    }
  }
  EXPECT_EQ(r.loops, loops);
  EXPECT_GT(loops, 100u);  // three laps meet: many loop relations
  EXPECT_EQ(r.local, keys.size() - 1);
  std::set<std::pair<std::int64_t, std::int64_t>> found;
  for (const PoseRelation& rel : r.relations) found.insert({rel.t_i_us, rel.t_j_us});
  EXPECT_EQ(found, expected);
  EXPECT_EQ(r.relations.size(), expected.size());

  // Written and read back: the true relative poses to the printed precision, zero error on the truth.
  const std::vector<PoseRelation> back = parse_relations(relations_text(r.relations), "x.relations");
  ASSERT_EQ(back.size(), r.relations.size());
  for (std::size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].t_i_us, r.relations[k].t_i_us);
    EXPECT_EQ(back[k].tolerance_us, 1);
    EXPECT_NEAR(back[k].delta.x, r.relations[k].delta.x, 5e-7);
    EXPECT_NEAR(std::abs(wrap_angle(back[k].delta.yaw - r.relations[k].delta.yaw)), 0.0, 5e-7);
  }
  const RelativePoseError e = relative_pose_error(truth, back);
  EXPECT_EQ(e.unmatched, 0u);
  EXPECT_LT(e.translation_m.max, 2e-6);
}

TEST(BenchmarkRelations, WorseThanAReferenceCountsPerRelation) {
  // Two trajectories scored on the same relations: one pose moved 1.5 m spoils the two relations
  // that touch it, by more than 1 m beyond the truth's zero error.
  std::vector<TrajectoryPose> truth;
  for (int i = 0; i < 10; ++i) truth.push_back({1'000'000 + i * 100'000, Pose2(0.5 * i, 0.0, 0.0)});
  RelationRule rule;
  const BenchmarkRelations r = make_benchmark_relations(truth, rule);
  std::vector<TrajectoryPose> moved = truth;
  moved[4].pose.y += 1.5;
  const RelativePoseError good = relative_pose_error(truth, r.relations), bad = relative_pose_error(moved, r.relations);
  EXPECT_EQ(relations_worse_than(bad, good), 2u);
  EXPECT_EQ(relations_worse_than(bad, good, 1.0), 2u);
  EXPECT_EQ(relations_worse_than(bad, good, 1.6), 0u);
  EXPECT_EQ(relations_worse_than(good, bad), 0u);
  EXPECT_NEAR(bad.translation_m.max, 1.5, 1e-9);
  std::vector<PoseRelation> fewer(r.relations.begin(), r.relations.begin() + 3);
  EXPECT_THROW(relations_worse_than(bad, relative_pose_error(truth, fewer)), Error);
  std::vector<TrajectoryPose> backwards = truth;
  backwards[3].stamp_us = backwards[2].stamp_us;
  EXPECT_THROW(make_benchmark_relations(backwards, rule), Error);
  rule.loop_every = 0;
  EXPECT_THROW(make_benchmark_relations(truth, rule), Error);
}

}  // namespace
}  // namespace starnav
