// Dubins and Reeds-Shepp curves (plan/car_curves.hpp) against closed forms proved from the heading
// bound, invariants over random pose pairs, an independent integration of the segments, and a
// brute-force search over every path of up to five arcs and straights.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/plan/car_curves.hpp"

namespace starnav {
namespace {

using Kind = CurveSegmentKind;

Pose2 random_pose(Rng& rng, double extent) {
  return {rng.uniform(-extent, extent), rng.uniform(-extent, extent), rng.uniform(-kPi, kPi)};
}

double pose_error(const Pose2& a, const Pose2& b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(angle_diff(a.yaw, b.yaw))});
}

// ---- Closed forms -------------------------------------------------------------------------------
// The heading can change at most 1/R per metre driven, so any path that turns the heading by a
// (mod 2 pi, |a| <= pi) is at least R |a| long; a single arc of that angle reaches its end pose and
// is therefore the shortest, for Dubins (forward arcs) and Reeds-Shepp alike. The straight line is
// the shortest path between two points, so a goal straight ahead or behind costs its distance.

TEST(CarCurves, StraightAheadCostsTheDistance) {
  for (const double d : {0.01, 1.0, 7.5}) {
    const Pose2 start{1.0, -2.0, 0.7};
    const Pose2 goal = start.compose({d, 0.0, 0.0});
    for (const CarPath& p : {shortest_dubins_path(start, goal, 1.3), shortest_reeds_shepp_path(start, goal, 1.3)}) {
      EXPECT_NEAR(p.length, d, 1e-9);
      EXPECT_EQ(car_path_word(p), "S+");
    }
  }
}

TEST(CarCurves, StraightBackwardsCostsTheDistanceWithReedsShepp) {
  for (const double d : {0.01, 1.0, 7.5}) {
    const Pose2 start{0.0, 0.0, -2.0};
    const Pose2 goal = start.compose({-d, 0.0, 0.0});
    const CarPath rs = shortest_reeds_shepp_path(start, goal, 2.0);
    EXPECT_NEAR(rs.length, d, 1e-9);
    EXPECT_EQ(car_path_word(rs), "S-");
    // Forward only, the car must turn around twice: far longer.
    EXPECT_GT(shortest_dubins_path(start, goal, 2.0).length, d + 2.0 * kPi);
  }
}

TEST(CarCurves, PureTurnCostsRadiusTimesAngle) {
  const double radius = 2.5;
  for (const double a : {0.2, 1.0, kPi / 2, 2.5, kPi - 1e-6}) {
    const Pose2 start{3.0, 4.0, -0.4};
    const Pose2 left = start.compose({radius * std::sin(a), radius * (1.0 - std::cos(a)), a});
    const Pose2 right = start.compose({radius * std::sin(a), -radius * (1.0 - std::cos(a)), -a});
    EXPECT_NEAR(shortest_dubins_path(start, left, radius).length, radius * a, 1e-9);
    EXPECT_NEAR(shortest_dubins_path(start, right, radius).length, radius * a, 1e-9);
    EXPECT_EQ(car_path_word(shortest_dubins_path(start, left, radius)), "L+");
    EXPECT_EQ(car_path_word(shortest_reeds_shepp_path(start, right, radius)), "R+");
    // The same arcs driven in reverse.
    const Pose2 back_left = start.compose({-radius * std::sin(a), radius * (1.0 - std::cos(a)), -a});
    const CarPath rs = shortest_reeds_shepp_path(start, back_left, radius);
    EXPECT_NEAR(rs.length, radius * a, 1e-9);
    EXPECT_EQ(car_path_word(rs), "L-");
  }
}

TEST(CarCurves, UTurnToThePoseBesideCostsPiR) {
  for (const double radius : {0.5, 1.0, 4.0}) {
    const Pose2 start{0.0, 0.0, 0.0};
    EXPECT_NEAR(shortest_dubins_path(start, {0.0, 2.0 * radius, kPi}, radius).length, kPi * radius, 1e-9);
    EXPECT_NEAR(shortest_dubins_path(start, {0.0, -2.0 * radius, kPi}, radius).length, kPi * radius, 1e-9);
    EXPECT_NEAR(shortest_reeds_shepp_path(start, {0.0, 2.0 * radius, kPi}, radius).length, kPi * radius, 1e-9);
  }
}

TEST(CarCurves, SamePoseIsAnEmptyPath) {
  const Pose2 p{1.0, 2.0, 3.0};
  for (const CarPath& path : {shortest_dubins_path(p, p, 1.0), shortest_reeds_shepp_path(p, p, 1.0)}) {
    EXPECT_EQ(path.length, 0.0);
    EXPECT_EQ(path.segment_count, 0u);
    const auto samples = sample_car_path(path, 0.1);
    ASSERT_EQ(samples.size(), 1u);
    EXPECT_LT(pose_error(samples[0].pose, p), 1e-12);
  }
}

// Sideways by less than the turning diameter (parallel parking): no forward path is short, Reeds-Shepp
// reverses. Its length lies between the displacement and the Dubins loop.
TEST(CarCurves, SidewaysShiftNeedsAReversal) {
  const double radius = 2.5;
  for (const double d : {0.3, 1.0, 2.0}) {
    const Pose2 start{0.0, 0.0, 0.0}, goal{0.0, d, 0.0};
    const CarPath rs = shortest_reeds_shepp_path(start, goal, radius);
    EXPECT_GE(rs.cusp_count(), 1u) << car_path_word(rs);
    EXPECT_GT(rs.length, d);
    EXPECT_LT(rs.length, shortest_dubins_path(start, goal, radius).length);
    EXPECT_LT(pose_error(rs.end(), goal), 1e-9);
  }
}

TEST(CarCurves, RefusesBadInput) {
  const Pose2 a{0.0, 0.0, 0.0}, b{1.0, 1.0, 1.0};
  for (const double r : {0.0, -1.0, std::nan(""), kInfinity}) {
    EXPECT_THROW(shortest_dubins_path(a, b, r), Error);
    EXPECT_THROW(shortest_reeds_shepp_path(a, b, r), Error);
  }
  EXPECT_THROW(shortest_reeds_shepp_path(a, {std::nan(""), 0.0, 0.0}, 1.0), Error);
  const CarPath p = shortest_reeds_shepp_path(a, b, 1.0);
  EXPECT_THROW(sample_car_path(p, 0.0), Error);
  EXPECT_THROW(sample_car_path(p, -0.1), Error);
  EXPECT_THROW(sample_car_path(p, std::nan("")), Error);
}

// ---- Invariants on random pose pairs -------------------------------------------------------------

TEST(CarCurves, EveryCandidateWordReachesTheGoal) {
  Rng rng(11);
  std::size_t rs_words = 0, dubins_words = 0;
  for (int i = 0; i < 2000; ++i) {
    const Pose2 a = random_pose(rng, 5.0), b = random_pose(rng, 5.0);
    const double radius = rng.uniform(0.3, 3.0);
    for (const CarPath& p : reeds_shepp_candidates(a, b, radius)) {
      ASSERT_LT(pose_error(p.end(), b), 1e-9) << car_path_word(p);
      ++rs_words;
    }
    for (const CarPath& p : dubins_candidates(a, b, radius)) {
      ASSERT_LT(pose_error(p.end(), b), 1e-9) << car_path_word(p);
      for (std::size_t k = 0; k < p.segment_count; ++k) ASSERT_GT(p.segments[k].length, 0.0);
      ++dubins_words;
    }
  }
  // Several formulas apply to most pairs (so the check above covers every formula many times).
  EXPECT_GT(rs_words, 2000u * 5u);
  EXPECT_GT(dubins_words, 2000u * 4u);
}

TEST(CarCurves, RandomPairsInvariants) {
  Rng rng(5);
  for (int i = 0; i < 3000; ++i) {
    const Pose2 a = random_pose(rng, 6.0), b = random_pose(rng, 6.0);
    const double radius = rng.uniform(0.2, 4.0);
    const CarPath rs = shortest_reeds_shepp_path(a, b, radius);
    const CarPath du = shortest_dubins_path(a, b, radius);
    ASSERT_LT(pose_error(rs.end(), b), 1e-9);
    ASSERT_LT(pose_error(du.end(), b), 1e-9);
    ASSERT_LE(rs.length, du.length + 1e-9);
    const double euclid = std::hypot(b.x - a.x, b.y - a.y);
    ASSERT_GE(rs.length, euclid - 1e-9);
    ASSERT_GE(rs.length, radius * std::abs(angle_diff(b.yaw, a.yaw)) - 1e-9);
    // Reeds-Shepp is symmetric: the reverse of a path from b to a drives from a to b.
    ASSERT_NEAR(shortest_reeds_shepp_path(b, a, radius).length, rs.length, 1e-9 * (1.0 + rs.length));
    // Scaling the poses and the radius together scales every length.
    const double k = rng.uniform(0.1, 10.0);
    const Pose2 ak{k * a.x, k * a.y, a.yaw}, bk{k * b.x, k * b.y, b.yaw};
    ASSERT_NEAR(shortest_reeds_shepp_path(ak, bk, k * radius).length, k * rs.length, 1e-9 * k * (1.0 + rs.length));
    ASSERT_NEAR(shortest_dubins_path(ak, bk, k * radius).length, k * du.length, 1e-9 * k * (1.0 + du.length));
    // Every candidate is at least as long as the shortest.
    for (const CarPath& p : reeds_shepp_candidates(a, b, radius)) ASSERT_GE(p.length, rs.length - 1e-12);
    for (const CarPath& p : dubins_candidates(a, b, radius)) ASSERT_GE(p.length, du.length - 1e-12);
    ASSERT_LE(rs.segment_count, 5u);
    ASSERT_LE(du.segment_count, 3u);
    ASSERT_EQ(du.cusp_count(), 0u);
  }
}

// ---- Sampling ------------------------------------------------------------------------------------

// The pose after driving `s` metres, integrated independently of the library with small RK4 steps of
// x' = d cos(theta), y' = d sin(theta), theta' = d kappa (d the direction, kappa the segment's curvature).
Pose2 integrate_to(const CarPath& path, double s) {
  Pose2 p = path.start;
  double left = s;
  for (std::size_t i = 0; i < path.segment_count && left > 0.0; ++i) {
    const CurveSegment& seg = path.segments[i];
    const double kappa = path.curvature(seg), dir = seg.length > 0.0 ? 1.0 : -1.0;
    const double drive = std::min(std::abs(seg.length), left);
    const int steps = std::max(1, static_cast<int>(std::ceil(drive / 4e-3)));
    const double h = drive / steps;
    auto f = [&](double th) { return std::array<double, 3>{dir * std::cos(th), dir * std::sin(th), dir * kappa}; };
    for (int k = 0; k < steps; ++k) {
      const auto k1 = f(p.yaw), k2 = f(p.yaw + 0.5 * h * k1[2]), k3 = f(p.yaw + 0.5 * h * k2[2]),
                 k4 = f(p.yaw + h * k3[2]);
      p.x += h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
      p.y += h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
      p.yaw += h / 6.0 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
    }
    left -= drive;
  }
  return p;
}

TEST(CarCurves, SamplesFollowThePath) {
  Rng rng(23);
  std::size_t cusps_seen = 0;
  for (int i = 0; i < 80; ++i) {
    const Pose2 a = random_pose(rng, 5.0), b = random_pose(rng, 5.0);
    const double radius = rng.uniform(0.5, 3.0), step = rng.uniform(0.01, 0.3);
    for (const CarPath& path : {shortest_reeds_shepp_path(a, b, radius), shortest_dubins_path(a, b, radius)}) {
      const auto samples = sample_car_path(path, step);
      ASSERT_GE(samples.size(), 2u);
      EXPECT_LT(pose_error(samples.front().pose, a), 1e-12);
      EXPECT_LT(pose_error(samples.back().pose, b), 1e-6);
      EXPECT_NEAR(samples.back().s, path.length, 1e-12);
      // Segment boundaries (arc length) and the direction of each segment.
      std::vector<double> ends;
      double acc = 0.0;
      for (std::size_t k = 0; k < path.segment_count; ++k) ends.push_back(acc += std::abs(path.segments[k].length));
      auto segment_at = [&](double s) {  // the segment driven just after s
        std::size_t k = 0;
        while (k + 1 < ends.size() && s >= ends[k] - 1e-12) ++k;
        return k;
      };
      std::size_t cusps = 0;
      for (std::size_t j = 0; j < samples.size(); ++j) {
        const CarPathSample& sm = samples[j];
        if (j % 8 == 0 || j + 1 == samples.size()) {
          EXPECT_LT(pose_error(sm.pose, integrate_to(path, sm.s)), 1e-8);
        }
        EXPECT_GT(sm.pose.yaw, -kPi);
        EXPECT_LE(sm.pose.yaw, kPi);
        if (j + 1 == samples.size()) break;
        const CarPathSample& nx = samples[j + 1];
        const double ds = nx.s - sm.s;
        ASSERT_GT(ds, 0.0);
        ASSERT_LE(ds, step + 1e-12);
        // Exactly one step apart, except into a cusp or the end.
        if (!nx.cusp && j + 2 < samples.size()) {
          EXPECT_NEAR(ds, step, 1e-9);
        }
        // The curvature bound between any two samples, and within a segment the segment's own
        // curvature: 0 or +-1/R, read off the samples' headings.
        const double dyaw = angle_diff(nx.pose.yaw, sm.pose.yaw);
        EXPECT_LE(std::abs(dyaw), ds / radius + 1e-9);
        const std::size_t seg = segment_at(sm.s);
        if (segment_at(nx.s - 1e-9) == seg) {
          const double kappa = dyaw / (sm.direction * ds);
          const double expected = path.curvature(path.segments[seg]);
          EXPECT_NEAR(kappa, expected, 1e-6);
          EXPECT_TRUE(expected == 0.0 || std::abs(std::abs(expected) - 1.0 / radius) < 1e-12);
          // The chord of an arc (or a straight) of arc length ds.
          const double chord = expected == 0.0 ? ds : 2.0 * radius * std::sin(ds / (2.0 * radius));
          EXPECT_NEAR(std::hypot(nx.pose.x - sm.pose.x, nx.pose.y - sm.pose.y), chord, 1e-9);
        }
        // Direction: the sign of the segment being driven away from the sample.
        EXPECT_EQ(sm.direction, path.segments[seg].length > 0.0 ? 1 : -1);
        if (nx.cusp) {
          ++cusps;
          EXPECT_NE(nx.direction, sm.direction);
        } else if (j + 2 < samples.size()) {
          EXPECT_EQ(nx.direction, sm.direction);
        }
      }
      EXPECT_EQ(cusps, path.cusp_count());
      cusps_seen += cusps;
    }
  }
  EXPECT_GT(cusps_seen, 30u);  // the pairs exercise reversals
}

// ---- Brute force -----------------------------------------------------------------------------------
// An independent search for short paths, knowing nothing of Dubins' or Reeds & Shepp's formulas: for
// every sequence of 3, 4 or 5 segment kinds (L, S, R; neighbours differ, as two equal neighbours are
// one segment), the first k - 3 signed lengths are set on a grid and the last three solved by Newton's
// method on the end-pose equations (x, y, heading) from several starting guesses; the best solution
// of each kind sequence is then refined by a shrinking coordinate search on its free lengths. Every
// path it keeps is checked to end at the goal by its own integration, so it is a real path: the
// analytic length must never exceed it (no shorter path exists, up to 1e-7). Reeds & Shepp proved an
// optimal path has at most five segments, so when the search meets the analytic length (it must in
// most pairs, checked below) it has found the optimum independently. Units: R = 1, start at origin.
struct BruteForce {
  bool forward_only = false;
  double goal_x = 0.0, goal_y = 0.0, goal_phi = 0.0;

  static double kappa(Kind k) { return k == Kind::kLeft ? 1.0 : k == Kind::kRight ? -1.0 : 0.0; }

  // Poses after each segment (index 0 = start).
  using Kinds = std::vector<Kind>;
  using Lens = std::array<double, 5>;
  using Poses = std::array<std::array<double, 3>, 6>;

  static void integrate(const Kinds& kinds, const Lens& lens, Poses& poses) {
    poses[0] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      auto [x, y, th] = poses[i];
      const double l = lens[i], kp = kappa(kinds[i]);
      if (kp == 0.0) {
        poses[i + 1] = {x + l * std::cos(th), y + l * std::sin(th), th};
      } else {
        const double th1 = th + kp * l;
        poses[i + 1] = {x + (std::sin(th1) - std::sin(th)) / kp, y + (std::cos(th) - std::cos(th1)) / kp, th1};
      }
    }
  }

  // Newton on the last three lengths; true when the end pose meets the goal.
  bool solve(const Kinds& kinds, Lens& lens) const {
    const std::size_t n = kinds.size();
    Poses poses;
    for (int it = 0; it < 40; ++it) {
      integrate(kinds, lens, poses);
      const auto& e = poses[n];
      const Eigen::Vector3d r(e[0] - goal_x, e[1] - goal_y, angle_diff(e[2], goal_phi));
      if (r.norm() < 1e-12) return true;
      Eigen::Matrix3d jac;
      for (int c = 0; c < 3; ++c) {
        const std::size_t j = n - 3 + static_cast<std::size_t>(c);
        const auto& pj = poses[j + 1];
        const double kp = kappa(kinds[j]);
        jac.col(c) << std::cos(pj[2]) - kp * (e[1] - pj[1]), std::sin(pj[2]) + kp * (e[0] - pj[0]), kp;
      }
      if (std::abs(jac.determinant()) < 1e-12) return false;
      Eigen::Vector3d delta = -jac.partialPivLu().solve(r);
      const double norm = delta.norm();
      if (norm > 1.0) delta /= norm;  // damped: stay near the starting guess's basin
      for (int c = 0; c < 3; ++c) lens[n - 3 + static_cast<std::size_t>(c)] += delta[c];
    }
    return false;
  }

  // The path's length if `lens` (first k - 3 fixed, last three a guess) solves to a valid path.
  double solved_length(const Kinds& kinds, Lens& lens) const {
    if (!solve(kinds, lens)) return kInfinity;
    double total = 0.0;
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      const double l = lens[i];
      if (forward_only && l < -1e-9) return kInfinity;
      total += std::abs(l);
    }
    Poses poses;
    integrate(kinds, lens, poses);
    const auto& e = poses[kinds.size()];
    if (std::hypot(e[0] - goal_x, e[1] - goal_y) > 1e-9 || std::abs(angle_diff(e[2], goal_phi)) > 1e-9)
      return kInfinity;
    return total;
  }

  double shortest(int max_segments) const {
    const double reach = std::hypot(goal_x, goal_y) + 4.0;
    const std::vector<double> guesses =
        forward_only ? std::vector<double>{0.5, 2.5, 5.0} : std::vector<double>{-2.5, -0.7, 0.7, 2.5};
    // Fewer guesses for the tail where a grid of prefixes already spreads the starting points.
    const std::vector<double> coarse_guesses =
        forward_only ? std::vector<double>{1.0, 4.0} : std::vector<double>{-1.5, 1.5};
    double best = kInfinity;
    for (int n = 3; n <= max_segments; ++n) {
      std::vector<Kind> kinds(static_cast<std::size_t>(n));
      const int combos = static_cast<int>(std::pow(3, n));
      for (int code = 0; code < combos; ++code) {
        int c = code;
        bool distinct = true;
        for (int i = 0; i < n; ++i, c /= 3) {
          kinds[static_cast<std::size_t>(i)] = static_cast<Kind>(c % 3);
          if (i > 0 && kinds[static_cast<std::size_t>(i)] == kinds[static_cast<std::size_t>(i - 1)]) distinct = false;
        }
        if (!distinct) continue;
        // Grid over the free lengths (arcs within a turn either way, straights within reach).
        const std::size_t free = static_cast<std::size_t>(n - 3);
        auto grid_values = [&](Kind k) {
          std::vector<double> v;
          const double hi = k == Kind::kStraight ? reach : kPi;
          const double lo = forward_only ? 0.0 : -hi;
          const int cells = 8;
          for (int g = 0; g <= cells; ++g) v.push_back(lo + (hi - lo) * g / cells);
          return v;
        };
        std::vector<std::vector<double>> axes;
        for (std::size_t f = 0; f < free; ++f) axes.push_back(grid_values(kinds[f]));
        std::size_t grid_points = 1;
        for (const auto& ax : axes) grid_points *= ax.size();
        double pattern_best = kInfinity;
        Lens pattern_lens{};
        for (std::size_t gp = 0; gp < grid_points; ++gp) {
          Lens prefix{};
          std::size_t rest = gp;
          for (std::size_t f = 0; f < free; ++f) {
            prefix[f] = axes[f][rest % axes[f].size()];
            rest /= axes[f].size();
          }
          const std::vector<double>& tail_guesses = n == 3 ? guesses : coarse_guesses;
          for (const double g0 : tail_guesses)
            for (const double g1 : tail_guesses)
              for (const double g2 : tail_guesses) {
                Lens lens = prefix;
                lens[free] = g0;
                lens[free + 1] = g1;
                lens[free + 2] = g2;
                const double l = solved_length(kinds, lens);
                if (l < pattern_best) {
                  pattern_best = l;
                  pattern_lens = lens;
                }
              }
        }
        if (pattern_best == kInfinity) continue;
        // Refine the free lengths by a shrinking coordinate search, re-solving from the current tail.
        for (double h = 0.2; free > 0 && h > 1e-9; h *= 0.5) {
          bool improved = true;
          while (improved) {
            improved = false;
            for (std::size_t f = 0; f < free; ++f)
              for (const double sgn : {-1.0, 1.0}) {
                Lens lens = pattern_lens;
                lens[f] += sgn * h;
                const double l = solved_length(kinds, lens);
                if (l < pattern_best - 1e-13) {
                  pattern_best = l;
                  pattern_lens = lens;
                  improved = true;
                }
              }
          }
        }
        best = std::min(best, pattern_best);
      }
    }
    return best;
  }
};

void brute_force_pairs(bool reeds_shepp, int pairs, int max_segments, std::uint64_t seed) {
  Rng rng(seed);
  int matched = 0;
  for (int i = 0; i < pairs; ++i) {
    const Pose2 goal = random_pose(rng, 3.0);
    const Pose2 start{0.0, 0.0, 0.0};
    const double analytic = reeds_shepp ? shortest_reeds_shepp_path(start, goal, 1.0).length
                                        : shortest_dubins_path(start, goal, 1.0).length;
    BruteForce bf;
    bf.forward_only = !reeds_shepp;
    bf.goal_x = goal.x;
    bf.goal_y = goal.y;
    bf.goal_phi = goal.yaw;
    const double found = bf.shortest(max_segments);
    EXPECT_GE(found, analytic - 1e-7) << "a shorter path to (" << goal.x << ", " << goal.y << ", " << goal.yaw
                                      << "): " << found << " < " << analytic;
    if (std::abs(found - analytic) < 1e-6) ++matched;
  }
  // The search is thorough enough to meet the optimum on nearly every pair.
  EXPECT_GE(matched, pairs - pairs / 10) << matched << " of " << pairs;
}

// Dubins proved three segments suffice forward; the search still tries four.
TEST(CarCurves, DubinsNoShorterPathByBruteForce) { brute_force_pairs(false, 10, 4, 101); }
TEST(CarCurves, ReedsSheppNoShorterPathByBruteForce) { brute_force_pairs(true, 10, 5, 202); }

}  // namespace
}  // namespace starnav
