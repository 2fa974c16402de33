// Graph SLAM and its parts: the branch and bound finds the best lattice pose an exhaustive search
// finds; the scan-constraint measure tells a corridor from a room; on a ring corridor driven with
// drifting odometry (local matching off, so only loop closure can help) the closures pull the
// trajectory back onto the truth; the registry makes it; the first scans of mit-csail (an odometry jump among
// them) beat the odometry on the benchmark relations inside them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <vector>

#include "room_fixture.hpp"
#include "slam_playback.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/slam/graph_slam.hpp"
#include "starnav/slam/relative_pose_error.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// The field cache's rule against every prefix tried: the longest prefix of at most max_fields
// fields whose bytes fit max_bytes, and never fewer than the newest one.
TEST(FieldCache, KeepsTheLongestPrefixWithinTheCountAndTheBytesAndAlwaysTheNewest) {
  Rng rng(11);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::size_t> sizes(static_cast<std::size_t>(rng.uniform_int(0, 8)));
    for (std::size_t& b : sizes) b = static_cast<std::size_t>(rng.uniform_int(1, 100));
    const auto max_fields = static_cast<std::size_t>(rng.uniform_int(1, 9));
    const auto max_bytes = static_cast<std::size_t>(rng.uniform_int(1, 400));
    std::size_t expected = 0;
    for (std::size_t k = 1; k <= sizes.size(); ++k) {
      std::size_t sum = 0;
      for (std::size_t i = 0; i < k; ++i) sum += sizes[i];
      if (k <= max_fields && (k == 1 || sum <= max_bytes)) expected = k;
    }
    ASSERT_EQ(cached_fields_kept(sizes, max_fields, max_bytes), expected) << "trial " << trial;
  }
  // A single field larger than the cap stays (it is being searched).
  const std::vector<std::size_t> huge{kMaxFieldCacheBytes + 1, 1};
  EXPECT_EQ(cached_fields_kept(huge, 48, kMaxFieldCacheBytes), 1U);
  const std::vector<std::size_t> halves{kMaxFieldCacheBytes / 2, kMaxFieldCacheBytes / 2, 1};
  EXPECT_EQ(cached_fields_kept(halves, 48, kMaxFieldCacheBytes), 2U);
}

TEST(BranchAndBound, FindsTheBestLatticePoseAnExhaustiveSearchFinds) {
  Rng rng(5);
  for (int trial = 0; trial < 4; ++trial) {
    // A reference of clutter and a scan of part of it, moved by an unknown transform.
    std::vector<Vec2> reference;
    for (int i = 0; i < 300; ++i) reference.emplace_back(rng.uniform(-4, 4), rng.uniform(-3, 3));
    const Pose2 truth(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), rng.uniform(-0.3, 0.3));
    std::vector<Vec2> scan;
    for (int i = 0; i < 120; ++i) scan.push_back(truth.inverse().transform(reference[static_cast<std::size_t>(i)]) + Vec2(0.01 * rng.normal(), 0.01 * rng.normal()));
    CorrelativeMatcherConfig c;
    c.refine = false;
    const CorrelativeScanMatcher m(c);
    const MatchWindow window{0.8, 0.35, 0.0};
    const CorrelativeScanMatcher::Field deep = m.field_of_points(reference, {-6, -5}, {6, 5}, 6);
    const ScanMatch found = m.match_to_field(deep, scan, Pose2(), window);
    // The exhaustive search over the same lattice, written out here.
    const double r = deep.resolution;
    double d_max = r;
    for (const Vec2& p : scan) d_max = std::max(d_max, p.norm());
    const double step_a = std::acos(1.0 - r * r / (2.0 * d_max * d_max));
    const int n_a = static_cast<int>(std::ceil(window.angular_rad / step_a)), n_l = static_cast<int>(std::ceil(window.linear_m / r));
    double best = -1.0;
    Pose2 best_pose;
    for (int a = -n_a; a <= n_a; ++a)
      for (int ix = -n_l; ix <= n_l; ++ix)
        for (int iy = -n_l; iy <= n_l; ++iy) {
          const Pose2 t(0.0, 0.0, a * step_a);
          double s = 0.0;
          for (const Vec2& p : scan) {
            const Vec2 q = t.transform(p);
            const int cx = static_cast<int>(std::floor((q.x() - deep.origin.x()) / r)) + ix;
            const int cy = static_cast<int>(std::floor((q.y() - deep.origin.y()) / r)) + iy;
            if (cx >= 0 && cy >= 0 && cx < deep.width && cy < deep.height) s += deep.fine[static_cast<std::size_t>(cy * deep.width + cx)];
          }
          s /= static_cast<double>(scan.size());
          if (s > best) best = s, best_pose = Pose2(ix * r, iy * r, a * step_a);
        }
    EXPECT_NEAR(found.score, best, 1e-6) << trial;
    EXPECT_NEAR(found.transform.x, best_pose.x, 1e-9) << trial;
    EXPECT_NEAR(found.transform.y, best_pose.y, 1e-9) << trial;
    EXPECT_NEAR(found.transform.yaw, best_pose.yaw, 1e-9) << trial;
    EXPECT_LT((found.transform.translation() - truth.translation()).norm(), 0.08) << trial;
    // A floor above the best score finds nothing.
    EXPECT_FALSE(m.match_to_field(deep, scan, Pose2(), MatchWindow{0.8, 0.35, std::min(1.0, best + 0.05)}).converged);
  }
}

// A search falls due every `every` nodes and is owed until a searchable node comes: checked
// against the rule written out (a node searches when it is searchable and a due node lies at or
// before it with no search since) over random runs of searchable and unsearchable nodes.
TEST(ClosureSchedule, ADueSearchAtAnUnsearchableNodeIsOwedToTheNextSearchableOne) {
  ClosureSchedule hand(4);
  std::vector<std::size_t> searched;
  for (std::size_t n = 0; n < 13; ++n)
    if (hand.due(n, n != 4 && n != 5 && n != 7)) searched.push_back(n);
  EXPECT_EQ(searched, (std::vector<std::size_t>{0, 6, 8, 12}));
  ClosureSchedule never(0);
  for (std::size_t n = 0; n < 50; ++n) EXPECT_FALSE(never.due(n, true));
  Rng rng(41);
  for (int every : {1, 2, 3, 7, 100}) {
    ClosureSchedule schedule(every);
    std::optional<std::size_t> last_due, last_search;
    for (std::size_t n = 0; n < 2000; ++n) {
      const bool searchable = rng.bernoulli(0.3);
      if (n % static_cast<std::size_t>(every) == 0) last_due = n;
      const bool expected = searchable && last_due && (!last_search || *last_search < *last_due);
      ASSERT_EQ(schedule.due(n, searchable), expected) << every << " " << n;
      if (expected) last_search = n;
    }
  }
}

// The drift bound and the windows it sets, against hand-computed values: 2 % of the distance
// driven where the scans pin the position down, 10 % (the odometry's) where they do not; no wide
// search while the bound is within the local search's 2 m, at most 8 m; the rivals' reach is the
// bound, at most 8 m.
TEST(ClosureWindow, TheSearchesGrowWithTheDriftBoundSinceTheSubmap) {
  GraphSlamConfig c;  // global_drift_per_m 0.02, loop_window_linear_m 2, global_window_linear_m 8
  c.unconstrained_drift_per_m = 0.1;
  EXPECT_EQ(drift_per_m(c, c.loop_min_constraint), 0.02);
  EXPECT_EQ(drift_per_m(c, 0.5), 0.02);
  EXPECT_EQ(drift_per_m(c, c.loop_min_constraint * 0.99), 0.1);
  EXPECT_EQ(drift_per_m(c, 0.0), 0.1);
  // 100 m along rooms and junctions, then 30 m down a featureless corridor: 2 m + 3 m.
  const double bound = 100.0 * drift_per_m(c, 0.3) + 30.0 * drift_per_m(c, 0.0);
  EXPECT_NEAR(bound, 5.0, 1e-12);
  EXPECT_NEAR(global_search_window_m(c, bound), 5.0, 1e-12);
  EXPECT_NEAR(rival_search_window_m(c, bound), 5.0, 1e-12);
  EXPECT_EQ(global_search_window_m(c, 0.0), 0.0);
  EXPECT_EQ(global_search_window_m(c, 2.0), 0.0);  // the local search covers it
  EXPECT_NEAR(rival_search_window_m(c, 2.0), 2.0, 1e-12);
  EXPECT_NEAR(global_search_window_m(c, 7.98), 7.98, 1e-12);
  EXPECT_EQ(global_search_window_m(c, 40.0), 8.0);  // the largest window
  EXPECT_EQ(rival_search_window_m(c, 40.0), 8.0);
  c.loop_window_linear_m = 1.0;
  EXPECT_NEAR(global_search_window_m(c, 1.5), 1.5, 1e-12);
  EXPECT_EQ(global_search_window_m(c, 1.0), 0.0);
  c.global_drift_per_m = 0.0;
  c.unconstrained_drift_per_m = 0.0;
  EXPECT_EQ(global_search_window_m(c, 1e6 * drift_per_m(c, 0.0)), 0.0);  // no drift: never a wide search
}

// The prior on closure searches, against hand-computed values: sigma = multiple x the drift bound
// (at least 0.1 m), weight 1 / (2 sigma^2); none when the multiple is 0.
TEST(ClosureWindow, ThePriorWidensWithTheDriftBound) {
  GraphSlamConfig c;
  c.loop_prior_drift_multiple = 0.0;
  EXPECT_EQ(closure_prior_weight(c, 1.0), 0.0);  // no prior
  c.loop_prior_drift_multiple = 2.0;
  // 52 m at 2 %/m: sigma 2.08 m; a pose 2.75 m from the estimate keeps 42 % of its score.
  const double w = closure_prior_weight(c, 52.0 * 0.02);
  EXPECT_NEAR(w, 1.0 / (2.0 * 2.08 * 2.08), 1e-12);
  EXPECT_NEAR(std::exp(-w * 2.75 * 2.75), 0.41728, 1e-5);
  EXPECT_NEAR(closure_prior_weight(c, 0.0), 1.0 / (2.0 * 0.2 * 0.2), 1e-12);  // at least 0.1 m x 2
  EXPECT_NEAR(closure_prior_weight(c, 0.05), closure_prior_weight(c, 0.1), 1e-12);
  c.loop_prior_drift_multiple = 1.0;
  EXPECT_NEAR(closure_prior_weight(c, 3.0), 1.0 / 18.0, 1e-12);
}

// A node's wide closures: those implying the best one's pose enter the graph; with the ambiguity
// check on, none when one implying another pose rivals the best. Hand-built cases, then random
// sets against the rule spelled out pair by pair.
TEST(WideClosures, TheBestOnesPoseIsKeptUnlessAnotherPoseRivalsIt) {
  GraphSlamConfig c;  // 0.5 m, 3 deg; ambiguity check off
  using Poses = std::vector<Pose2>;
  using Scores = std::vector<double>;
  using Kept = std::vector<std::size_t>;
  EXPECT_EQ(wide_closures_kept(c, Poses{}, Scores{}), Kept{});
  EXPECT_EQ(wide_closures_kept(c, Poses{{4, 2, 1}}, Scores{0.8}), Kept{0});
  // The true place in three submaps, a repeat 3 m on in one.
  const Poses three_and_repeat{{0, 0, 0}, {0.3, 0.35, 0.02}, {3.0, 0, 0}, {0.1, 0.1, 0.01}};
  EXPECT_EQ(wide_closures_kept(c, three_and_repeat, Scores{0.90, 0.97, 0.93, 0.80}), (Kept{0, 1, 3}));
  EXPECT_EQ(wide_closures_kept(c, three_and_repeat, Scores{0.90, 0.91, 0.97, 0.80}), Kept{2});  // the repeat fits best
  c.loop_max_ambiguity = 0.95;
  EXPECT_EQ(wide_closures_kept(c, three_and_repeat, Scores{0.90, 0.97, 0.92, 0.80}), (Kept{0, 1, 3}));  // 0.92 < 0.95 x 0.97
  EXPECT_EQ(wide_closures_kept(c, three_and_repeat, Scores{0.90, 0.97, 0.93, 0.80}), Kept{});           // 0.93 >= 0.9215
  EXPECT_EQ(wide_closures_kept(c, Poses{{0, 0, 3.13}, {0, 0, -3.13}}, Scores{0.9, 0.9}), (Kept{0, 1}));  // across +-pi
  EXPECT_EQ(wide_closures_kept(c, Poses{{0, 0, 0}, {0, 0, 0.06}}, Scores{0.9, 0.9}), Kept{});            // 3.4 deg apart
  EXPECT_EQ(wide_closures_kept(c, Poses{{0, 0, 0}, {0, 0, 0.06}}, Scores{0.9, 0.5}), Kept{0});
  Rng rng(11);
  for (int trial = 0; trial < 500; ++trial) {
    const std::size_t n = static_cast<std::size_t>(rng.uniform(1.0, 8.99));
    Poses implied;
    Scores scores;
    for (std::size_t i = 0; i < n; ++i) {
      const double place = rng.uniform() < 0.7 ? 0.0 : 3.0;
      implied.push_back({place + rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.03, 0.03)});
      scores.push_back(0.75 + 0.01 * std::floor(rng.uniform(0.0, 24.99)));
    }
    std::size_t best = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (scores[i] > scores[best]) best = i;
    Kept expected;
    bool rivalled = false;
    for (std::size_t i = 0; i < n; ++i) {
      const bool near = std::hypot(implied[i].x - implied[best].x, implied[i].y - implied[best].y) <= 0.5 &&
                        std::abs(implied[i].yaw - implied[best].yaw) <= c.global_agreement_rad;
      if (near) expected.push_back(i);
      rivalled = rivalled || (!near && scores[i] >= 0.95 * scores[best]);
    }
    if (rivalled) expected.clear();
    EXPECT_EQ(wide_closures_kept(c, implied, scores), expected) << "trial " << trial;
  }
}

// Two looks at one place correct the estimate the same way: the first node's implied pose carried
// by the motion between the two nodes is the second's implied pose. Hand-built: the
// estimate 3 m off along x and turned 10 degrees, the second node 5 m on; moved 0.4 m or 2 degrees
// they still agree, 0.6 m or 4 degrees not (0.5 m, 3 degrees), unless the drift bound grew by
// 0.2 m between the two nodes.
TEST(AppearanceClosures, TwoLooksAgreeWhenTheyCorrectTheEstimateTheSameWay) {
  const GraphSlamConfig c;
  const Pose2 correction(3.0, 0.0, deg_to_rad(10.0));  // truth = correction * estimate
  const Pose2 e1(10, 5, 0.3), e2 = e1.compose(Pose2(5.0, 0.0, 0.2));
  const ClosureLook first{e1, correction.compose(e1), 2.0};
  const auto second = [&](const Pose2& nudge, double drift) { return ClosureLook{e2, nudge.compose(correction.compose(e2)), drift}; };
  EXPECT_TRUE(appearance_closures_agree(c, first, second(Pose2(), 2.0)));
  EXPECT_TRUE(appearance_closures_agree(c, first, second(Pose2(0.4, 0, 0), 2.0)));
  EXPECT_FALSE(appearance_closures_agree(c, first, second(Pose2(0.6, 0, 0), 2.0)));
  EXPECT_TRUE(appearance_closures_agree(c, first, second(Pose2(0.6, 0, 0), 2.2)));
  // A turn about the second node's own position.
  const auto turned = [&](double deg) {
    ClosureLook l = second(Pose2(), 2.0);
    l.implied.yaw += deg_to_rad(deg);
    return l;
  };
  EXPECT_TRUE(appearance_closures_agree(c, first, turned(2.0)));
  EXPECT_FALSE(appearance_closures_agree(c, first, turned(4.0)));
  // A lookalike 20 m along the building corrects it otherwise.
  EXPECT_FALSE(appearance_closures_agree(c, first, second(Pose2(20.0, 0, 0), 2.0)));
}

// A T junction: a corridor 2 m wide along x, a side corridor leaving it at x = 0 towards +y.
std::vector<test::Segment> t_junction_world() {
  return {{{-30, -1}, {30, -1}}, {{-30, 1}, {-1, 1}}, {{1, 1}, {30, 1}}, {{-1, 1}, {-1, 15}},
          {{1, 1}, {1, 15}},     {{-30, -1}, {-30, 1}}, {{30, -1}, {30, 1}}};
}

// A submap of scans from `poses`, in the first pose's frame.
std::vector<Vec2> t_junction_submap(const std::vector<Pose2>& poses, double range_m) {
  std::vector<Vec2> out;
  for (const Pose2& p : poses)
    for (const Vec2& q : test::scan_from(p, 720, t_junction_world(), range_m)) out.push_back(poses.front().inverse().compose(p).transform(q));
  return out;
}

// The closure check on a symmetric corridor: a scan at the junction placed 16 m down the corridor
// onto a submap of plain corridor (a planted false closure) lies mostly on the submap's walls, yet
// what the submap confirms is two parallel walls and is refused; placed at the junction onto a
// submap that saw the junction it is kept.
TEST(ClosureCheck, RefusesAFalseClosureAlongASymmetricCorridorAndKeepsTheTrueOne) {
  const GraphSlamConfig config;
  const std::vector<Vec2> scan = test::scan_from(Pose2(0, 0, 0), 720, t_junction_world(), 10.0);
  ASSERT_GT(scan_constraint(scan), config.loop_min_constraint);  // the junction pins the scan down

  const std::vector<Vec2> corridor = t_junction_submap({Pose2(-22, 0, 0), Pose2(-20, 0, 0), Pose2(-18, 0, 0), Pose2(-16, 0, 0)}, 6.0);
  const Pose2 planted(6.0, 0.0, 0.0);  // the junction's scan 16 m down the corridor: x = -16 + 6 in the world = -10
  const std::vector<Vec2> confirmed_false = overlapping_points(scan, planted, PointNeighbourhood(corridor, config.loop_overlap_radius_m));
  EXPECT_GT(confirmed_false.size(), scan.size() / 3);  // most of the scan lies on the corridor's walls
  EXPECT_LT(scan_constraint(confirmed_false), config.loop_min_constraint);

  const std::vector<Vec2> junction = t_junction_submap({Pose2(-4, 0, 0), Pose2(-2, 0, 0), Pose2(0, 0, 0), Pose2(2, 0, 0)}, 6.0);
  const Pose2 truth(4.0, 0.0, 0.0);  // the scan's pose (0, 0) in the submap's frame, anchored at (-4, 0)
  const std::vector<Vec2> confirmed_true = overlapping_points(scan, truth, PointNeighbourhood(junction, config.loop_overlap_radius_m));
  EXPECT_GE(scan_constraint(confirmed_true), config.loop_min_constraint);
}

// overlapping_points against the pairwise definition over random clouds and poses.
TEST(ClosureCheck, OverlappingPointsAreThoseWithinTheRadiusOfAReferencePoint) {
  Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec2> scan, reference;
    for (int i = 0; i < 200; ++i) scan.emplace_back(rng.uniform(-5, 5), rng.uniform(-5, 5));
    for (int i = 0; i < 300; ++i) reference.emplace_back(rng.uniform(-8, 8), rng.uniform(-8, 8));
    const Pose2 pose(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-kPi, kPi));
    const double radius = rng.uniform(0.05, 0.6);
    std::vector<Vec2> expected;
    for (const Vec2& p : scan) {
      const Vec2 q = pose.transform(p);
      if (std::any_of(reference.begin(), reference.end(), [&](const Vec2& r) { return (r - q).norm() <= radius; })) expected.push_back(p);
    }
    const std::vector<Vec2> got = overlapping_points(scan, pose, PointNeighbourhood(reference, radius));
    ASSERT_EQ(got.size(), expected.size()) << trial;
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], expected[i]);
  }
}

TEST(SeeThrough, RaysCrossingAMeasuredWallCountAndRaysEndingAtItDoNot) {
  // The reference measured a wall along x = 2 from y = -1 to 1 (points 1 cm apart, cells 5 cm).
  std::vector<Vec2> wall;
  for (int i = 0; i <= 200; ++i) wall.emplace_back(2.0, -1.0 + 0.01 * i);
  const SurfaceGrid surfaces(wall, 0.05, 1);
  // The sensor at (0.5, 0) facing +x; its points in its own frame land (in the wall's frame) at:
  // (3, 0): crosses the wall at y = 0; (3, 1.2): crosses it at y = 0.8; (3, -2): passes it at
  // y = -1.33; (1.5, 0.5): ends before it; (2, 0.3): ends on it (within the 0.3 m margin).
  const Pose2 pose(0.5, 0.0, 0.0);
  std::vector<Vec2> scan;
  for (const Vec2& world : {Vec2(3.0, 0.0), Vec2(3.0, 1.2), Vec2(3.0, -2.0), Vec2(1.5, 0.5), Vec2(2.0, 0.3)})
    scan.push_back(pose.inverse().transform(world));
  EXPECT_DOUBLE_EQ(see_through_share(scan, pose, surfaces, 0.3), 2.0 / 5.0);
  // Turned half a circle and placed beyond the wall, the same world points: the rays now start
  // at (4, 0) and only (1.5, 0.5) lies beyond the wall from there (crossing it at y = 0.4).
  const Pose2 behind(4.0, 0.0, kPi);
  std::vector<Vec2> seen_from_behind;
  for (const Vec2& world : {Vec2(3.0, 0.0), Vec2(1.5, 0.5), Vec2(3.0, -2.0)}) seen_from_behind.push_back(behind.inverse().transform(world));
  EXPECT_DOUBLE_EQ(see_through_share(seen_from_behind, behind, surfaces, 0.3), 1.0 / 3.0);
  // A margin longer than the rays: nothing is seen through; the sensor's own cell never counts.
  EXPECT_EQ(see_through_share(scan, pose, surfaces, 10.0), 0.0);
  EXPECT_FALSE(surfaces.crosses_surface(Vec2(2.0, 0.0), Vec2(2.5, 0.0), 0.5));
  EXPECT_TRUE(surfaces.crosses_surface(Vec2(1.0, 0.0), Vec2(2.5, 0.0), 1.2));
  EXPECT_FALSE(surfaces.crosses_surface(Vec2(1.0, 0.0), Vec2(2.5, 0.0), 0.9));
  EXPECT_EQ(see_through_share({}, pose, surfaces, 0.3), 0.0);
  // A surface is a cell holding min_hits points: the wall's cells hold five (1 cm apart, 5 cm
  // cells) or six, a stray return one.
  std::vector<Vec2> with_stray = wall;
  with_stray.emplace_back(1.0, 0.02);
  EXPECT_TRUE(SurfaceGrid(with_stray, 0.05, 1).crosses_surface(Vec2(0.0, 0.02), Vec2(1.5, 0.02), 1.5));
  EXPECT_FALSE(SurfaceGrid(with_stray, 0.05, 3).crosses_surface(Vec2(0.0, 0.02), Vec2(1.5, 0.02), 1.5));
  EXPECT_TRUE(SurfaceGrid(with_stray, 0.05, 3).crosses_surface(Vec2(0.0, 0.02), Vec2(2.5, 0.02), 2.5));
  EXPECT_FALSE(SurfaceGrid(with_stray, 0.05, 7).crosses_surface(Vec2(0.0, 0.02), Vec2(2.5, 0.02), 2.5));
  // Points 100 km apart: coarser cells, not 4e12 of them.
  const SurfaceGrid far_apart(std::vector<Vec2>{{0.0, 0.0}, {1e5, 1e5}}, 0.05, 1);
  EXPECT_LE(far_apart.bytes(), 2 * kMaxSurfaceGridCells);
  EXPECT_TRUE(far_apart.crosses_surface(Vec2(-1e4, -1e4), Vec2(5e4, 5e4), 5e4));
}

// crosses_surface against a dense walk along the segment (steps of a two-hundredth of a cell) on
// random grids: whatever the walk finds, the exact traversal finds; the traversal may also find a
// cell the segment only grazes by less than a step, which must be rare.
TEST(SeeThrough, CrossingsAreThoseADenseWalkFinds) {
  Rng rng(23);
  const double cell = 0.05;
  const auto cell_of = [&](const Vec2& p) {
    return std::pair{static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell))};
  };
  int grazes = 0, trials = 0, crossing = 0;
  for (int grid = 0; grid < 10; ++grid) {
    std::vector<Vec2> points;
    for (int i = 0; i < 300; ++i) points.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1));
    std::set<std::pair<std::int64_t, std::int64_t>> occupied;
    for (const Vec2& p : points) occupied.insert(cell_of(p));
    const SurfaceGrid surfaces(points, cell, 1);
    for (int k = 0; k < 50; ++k, ++trials) {
      const Vec2 from(rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2)), to(rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2));
      const double length = (to - from).norm(), stop = rng.uniform(0.0, 1.2 * length), reach = std::min(stop, length);
      const int steps = static_cast<int>(reach / (cell / 200.0)) + 1;
      bool walked = false;
      for (int i = 0; i <= steps && !walked; ++i) {
        const Vec2 at = from + (to - from) * (reach * i / steps / length);
        walked = cell_of(at) != cell_of(from) && occupied.count(cell_of(at)) > 0;
      }
      const bool exact = surfaces.crosses_surface(from, to, stop);
      if (walked) {
        EXPECT_TRUE(exact) << "grid " << grid << " segment " << k;
      }
      grazes += exact && !walked;
      crossing += walked;
    }
  }
  EXPECT_LE(grazes, trials / 50);
  // Both kinds of segment were tried.
  EXPECT_GT(crossing, trials / 10);
  EXPECT_LT(crossing, trials * 9 / 10);
}

TEST(ScanConstraint, TellsACorridorFromARoom) {
  std::vector<Vec2> corridor, room;
  for (int i = 0; i < 100; ++i) corridor.emplace_back(-5.0 + 0.1 * i, 1.0);
  for (int i = 0; i < 100; ++i) corridor.emplace_back(5.0 - 0.1 * i, -1.0);
  EXPECT_LT(scan_constraint(corridor), 0.01);
  room = test::scan_from(Pose2(2.0, 2.0, 0.3));
  EXPECT_GT(scan_constraint(room), 0.2);
  EXPECT_EQ(scan_constraint(std::vector<Vec2>{{1, 0}, {2, 0}}), 0.0);
}

TEST(GraphSlam, LoopClosuresPullADriftingRingDriveBackOntoTheTruth) {
  std::vector<Pose2> truth;
  const RobotLog log = test::ring_drive(truth);
  // Local matching off: the front end is the odometry, so what corrects it is the closures.
  GraphSlamConfig c;
  CorrelativeMatcherConfig m = local_slam_matcher_config();
  m.window_linear_m = 0.0;
  m.window_angular_rad = 0.0;
  m.refine = false;
  c.loop_window_linear_m = 3.0;
  c.loop_max_distance_m = 10.0;
  GraphSlam slam(c, std::make_unique<CorrelativeScanMatcher>(m));
  test::play_log(slam, log);
  const std::vector<TrajectoryPose> t = planar_trajectory(slam.trajectory());
  ASSERT_EQ(t.size(), truth.size());
  double odom_end = (log.scans.back().odometry->translation() - truth.back().translation()).norm();
  double slam_end = (t.back().pose.translation() - truth.back().translation()).norm();
  EXPECT_GT(odom_end, 1.0);
  EXPECT_LT(slam_end, 0.15) << "odometry ended " << odom_end << " m off";
  const SlamGraph g = slam.graph();
  std::size_t closures = 0;
  for (const SlamGraphEdge& e : g.edges) closures += e.kind != SlamEdgeKind::Local;
  EXPECT_GT(closures, 5u);
  EXPECT_GT(slam.stats().optimisations, 0u);
  // Every node is a scan of the trajectory, at that scan's pose.
  for (std::size_t i = 0; i < g.nodes.size(); i += 50) {
    const auto it = std::find_if(t.begin(), t.end(), [&](const TrajectoryPose& p) { return p.stamp_us == g.nodes[i].stamp_us; });
    ASSERT_NE(it, t.end());
    EXPECT_NEAR(it->pose.x, g.nodes[i].pose.x, 1e-12);
  }
  // The map of the kept scans has the outer wall at y = 0 (occupied within a cell of it) and a
  // free corridor centre.
  const OccupancyGrid map = slam.map(OccupancyMappingParams{});
  const auto value = [&](double x, double y) {
    const auto cell = map.geometry().world_to_cell(Vec2(x, y));
    return cell ? static_cast<int>(map(cell->x, cell->y)) : -2;
  };
  int wall = -1;
  for (double y = -0.05; y <= 0.051; y += 0.025) wall = std::max(wall, value(10.5, y));
  EXPECT_GE(wall, 65);
  EXPECT_GE(value(10.5, 1.5), 0);
  EXPECT_LE(value(10.5, 1.5), 25);
}

TEST(GraphSlam, TheRegistryMakesItAndNamesBadSettings) {
  const SlamDef& def = find_slam("graph");
  EXPECT_EQ(def.info.role, Role::Slam);
  SlamContext ctx;
  ctx.file = "x.yaml";
  std::unique_ptr<Slam> slam = def.make(ctx, std::vector<ParamSetting>{{"loop_min_score", "0.6", "x.yaml", 3, "slam.loop_min_score"}});
  EXPECT_EQ(slam->name(), "graph");
  try {
    def.make(ctx, std::vector<ParamSetting>{{"local.window_nodes", "0", "x.yaml", 4, "slam.local.window_nodes"}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slam.local.window_nodes"), std::string::npos) << e.what();
  }
  EXPECT_THROW(find_slam("gmapping"), Error);
  // A search whose cost passes the matcher's limits is refused by the factory, at the setting that
  // made it (its own field's, else the last one the message names).
  struct Row {
    std::vector<ParamSetting> settings;
    std::string at;
  };
  const std::vector<Row> rows = {
      {{{"local.matcher.resolution_m", "0.005", "x.yaml", 5, "slam.local.matcher.resolution_m"},
        {"local.matcher.window_linear_m", "10", "x.yaml", 6, "slam.local.matcher.window_linear_m"},
        {"local.matcher.window_angular_deg", "180", "x.yaml", 7, "slam.local.matcher.window_angular_deg"}},
       "x.yaml:6: slam.local.matcher.window_linear_m: local.matcher.window_linear_m 10 m / local.matcher.resolution_m 0.005 m"},
      {{{"local.matcher.resolution_m", "0.01", "x.yaml", 5, "slam.local.matcher.resolution_m"}},
       "x.yaml:5: slam.local.matcher.resolution_m: local.max_range_m 30 m / local.matcher.resolution_m 0.01 m: the likelihood field"},
      {{{"loop_window_linear_m", "100", "x.yaml", 8, "slam.loop_window_linear_m"}, {"search_depth", "0", "x.yaml", 9, "slam.search_depth"}},
       "x.yaml:8: slam.loop_window_linear_m: loop_window_linear_m 100 m / local.matcher.resolution_m 0.05 m and loop_window_angular_deg 19.99"},
  };
  for (const Row& r : rows) {
    const std::string what = test::error_of([&] { def.make(ctx, r.settings); });
    EXPECT_EQ(what.find(r.at), 0u) << what;
  }
}

// The first 450 scans hold the odometry's first freeze and jump (scan 313: 0.85 m and 50 deg at once).
TEST(GraphSlam, BeatsTheOdometryOnTheFirstScansOfMitCsail) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/carmen_raw/mit-csail.clf.gz");
  RobotLog log = read_robot_log(test::shared_path("datasets/carmen_raw/mit-csail.clf.gz"));
  log.scans.resize(450);
  GraphSlam slam(GraphSlamConfig{}, std::make_unique<CorrelativeScanMatcher>(local_slam_matcher_config()));
  test::play_log(slam, log);
  const std::vector<PoseRelation> relations = read_relations(test::shared_path("datasets/slam_benchmark_relations/mit-csail.relations"));
  const RelativePoseError e = relative_pose_error(planar_trajectory(slam.trajectory()), relations);
  const RelativePoseError o = relative_pose_error(odometry_trajectory(log), relations);
  ASSERT_GT(e.translation_m.n, 100u);
  EXPECT_EQ(e.translation_m.n, o.translation_m.n);
  // The odometry is good between its glitches, but one relation spans the freeze and the jump
  // (0.85 m and 22 deg off); SLAM matches through it (0.27 m, 2 deg) and stays near
  // Cartographer's whole-log mean (0.032 m).
  EXPECT_GT(o.translation_m.max, 0.5);
  EXPECT_GT(o.rotation_deg.max, 20.0);
  EXPECT_LT(e.translation_m.max, 0.35) << "mean " << e.translation_m.mean;
  EXPECT_LT(e.translation_m.mean, 0.035);
  EXPECT_LT(e.rotation_deg.max, 3.0) << "odometry " << o.rotation_deg.max;
}

}  // namespace
}  // namespace starnav
