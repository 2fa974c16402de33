// TerrainAnalysis against brute-force computations and hand-built terrains.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/terrain/terrain_analysis.hpp"
#include "terrain_test_util.hpp"

namespace {

using namespace starnav;
using terrain_test::brute_ruggedness;
using terrain_test::geometry;
using terrain_test::random_terrain;

// Least-squares plane over the observed cells of the clipped 3x3 block, minimum-norm in the
// gradient (data centred, SVD solve): Eigen's solver, independent of the library's closed forms.
Vec2 brute_gradient(const ElevationMap& m, int x, int y) {
  std::vector<double> xs, ys, zs;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int i = x + dx, j = y + dy;
      if (!m.contains(i, j) || !m.observed_at(i, j)) continue;
      xs.push_back(dx * m.resolution());
      ys.push_back(dy * m.resolution());
      zs.push_back(m.height_at(i, j));
    }
  const int n = static_cast<int>(zs.size());
  if (n == 0) return {0, 0};
  double mx = 0, my = 0, mz = 0;
  for (int i = 0; i < n; ++i) mx += xs[i], my += ys[i], mz += zs[i];
  mx /= n, my /= n, mz /= n;
  Eigen::MatrixXd a(n, 2);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    a(i, 0) = xs[i] - mx;
    a(i, 1) = ys[i] - my;
    b(i) = zs[i] - mz;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(1e-9);
  const Eigen::Vector2d g = svd.solve(b);
  return {g(0), g(1)};
}

// The Liu obstacle definition, written out from heights.
bool brute_liu_obstacle(const ElevationMap& m, int x, int y, const LiuCostParams& p, UnobservedPolicy pol) {
  if (!m.observed_at(x, y)) return pol == UnobservedPolicy::Blocked;
  if (brute_ruggedness(m, x, y) >= p.s_y) return true;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const int i = x + dx, j = y + dy;
      if (!m.contains(i, j) || !m.observed_at(i, j)) continue;
      const double h = std::abs(m.height_at(i, j) - m.height_at(x, y));
      const double l = std::hypot(dx, dy) * m.resolution();
      if (h >= p.h_y || std::atan(h / l) >= p.a_y) return true;
    }
  return false;
}

std::vector<std::uint8_t> brute_expand(const std::vector<std::uint8_t>& mask, int w, int h, double r_cells) {
  std::vector<std::uint8_t> out(mask.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int j = 0; j < h && !out[y * w + x]; ++j)
        for (int i = 0; i < w; ++i)
          if (mask[j * w + i] && (i - x) * (i - x) + (j - y) * (j - y) <= r_cells * r_cells + 1e-9) {
            out[y * w + x] = 1;
            break;
          }
  return out;
}

void expect_same_analysis(const TerrainAnalysis& a, const TerrainAnalysis& b) {
  ASSERT_EQ(a.width(), b.width());
  EXPECT_EQ(a.heights(), b.heights());
  EXPECT_EQ(a.observed(), b.observed());
  EXPECT_EQ(a.ruggedness(), b.ruggedness());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) ASSERT_EQ(a.gradient(x, y), b.gradient(x, y)) << x << "," << y;
  EXPECT_EQ(a.obstacle_mask(), b.obstacle_mask());
  EXPECT_EQ(a.li_blocked_mask(), b.li_blocked_mask());
  EXPECT_EQ(a.expanded_obstacle_mask(), b.expanded_obstacle_mask());
  EXPECT_EQ(a.expanded_li_blocked_mask(), b.expanded_li_blocked_mask());
}

TEST(TerrainAnalysis, MovesAndTheirOrder) {
  for (int k = 0; k < kMoveCount; ++k) {
    EXPECT_EQ(move_index(kMoveDx[k], kMoveDy[k]), k);
    EXPECT_EQ(move_is_diagonal(k), kMoveDx[k] != 0 && kMoveDy[k] != 0);
    if (move_is_diagonal(k)) {
      const int a = kDiagonalSideA[k], b = kDiagonalSideB[k];
      EXPECT_EQ(kMoveDx[a] + kMoveDx[b], kMoveDx[k]);
      EXPECT_EQ(kMoveDy[a] + kMoveDy[b], kMoveDy[k]);
    }
  }
  EXPECT_EQ(move_index(0, 0), -1);
  EXPECT_EQ(move_index(2, 0), -1);
}

TEST(TerrainAnalysis, RuggednessGradientAndMovesMatchBruteForce) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const double unobserved = seed <= 2 ? 0.0 : 0.15 * static_cast<double>(seed - 2);
    const ElevationMap m = random_terrain(seed, 17, 13, 0.1 + 0.05 * static_cast<double>(seed), 0.03, unobserved);
    TerrainAnalysisOptions o;
    o.unobserved = UnobservedPolicy::FreeFlat;
    const TerrainAnalysis t(m, o);
    for (int y = 0; y < m.height(); ++y)
      for (int x = 0; x < m.width(); ++x) {
        SCOPED_TRACE(::testing::Message() << "seed " << seed << " cell " << x << "," << y);
        EXPECT_NEAR(t.ruggedness(x, y), brute_ruggedness(m, x, y), 1e-15);
        const Vec2 g = m.observed_at(x, y) ? brute_gradient(m, x, y) : Vec2(0, 0);
        EXPECT_NEAR(t.gradient(x, y).x(), g.x(), 1e-11);
        EXPECT_NEAR(t.gradient(x, y).y(), g.y(), 1e-11);
        EXPECT_NEAR(t.cell_slope(x, y), std::atan(g.norm()), 1e-11);
        for (int k = 0; k < kMoveCount; ++k) {
          const int i = x + kMoveDx[k], j = y + kMoveDy[k];
          const MoveTerrain mv = t.move(x, y, k);
          const double l = std::hypot(kMoveDx[k], kMoveDy[k]) * m.resolution();
          EXPECT_NEAR(mv.length, l, 1e-15);
          const bool known = m.contains(i, j) && m.observed_at(i, j) && m.observed_at(x, y);
          ASSERT_EQ(mv.known, known);
          if (!known) continue;
          const double h = std::abs(m.height_at(i, j) - m.height_at(x, y));
          EXPECT_EQ(mv.h, h);
          EXPECT_NEAR(mv.a, std::atan2(h, l), 1e-15);
        }
      }
  }
}

TEST(TerrainAnalysis, PlaneNormalsAndSlopesAreExact) {
  // z = 0.3 x - 0.2 y on a grid rotated by 0.7 rad: the normal in the world frame is the grid
  // frame's (-0.3, 0.2, 1) rotated by the yaw, at every cell including the border.
  const double yaw = 0.7;
  ElevationMap m(geometry(9, 7, 0.25, Pose2(1.0, -2.0, yaw)));
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x) m.set_height(x, y, 0.3 * (x + 0.5) * 0.25 - 0.2 * (y + 0.5) * 0.25 + 5.0);
  const TerrainAnalysis t(m);
  const Vec3 grid_normal = Vec3(-0.3, 0.2, 1.0).normalized();
  const Vec3 world_normal = Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * grid_normal;
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x) {
      EXPECT_NEAR(t.gradient(x, y).x(), 0.3, 1e-12);
      EXPECT_NEAR(t.gradient(x, y).y(), -0.2, 1e-12);
      EXPECT_NEAR((t.normal(x, y) - world_normal).norm(), 0.0, 1e-12);
      EXPECT_NEAR(t.cell_slope(x, y), std::atan(std::hypot(0.3, 0.2)), 1e-12);
    }
  // Ruggedness of a plane: interior 3x3 of z = a x + b y has variance (2/3)(a^2 + b^2) res^2.
  const double expected = 2.0 / 3.0 * (0.09 + 0.04) * 0.0625;
  EXPECT_NEAR(t.ruggedness(4, 3), expected, 1e-15);
}

TEST(TerrainAnalysis, LiuObstacleMaskMatchesItsDefinition) {
  LiuCostParams p;
  p.s_y = 0.0004;  // low enough to matter on these terrains
  for (std::uint64_t seed = 10; seed < 16; ++seed) {
    const ElevationMap m = random_terrain(seed, 20, 15, 0.1, 0.025, seed % 2 ? 0.1 : 0.0);
    for (const auto pol : {UnobservedPolicy::Blocked, UnobservedPolicy::FreeFlat, UnobservedPolicy::UnknownCost}) {
      TerrainAnalysisOptions o;
      o.unobserved = pol;
      o.thresholds = p;
      const TerrainAnalysis t(m, o);
      int obstacles = 0;
      for (int y = 0; y < m.height(); ++y)
        for (int x = 0; x < m.width(); ++x) {
          const bool want = brute_liu_obstacle(m, x, y, p, pol);
          obstacles += want;
          ASSERT_EQ(t.obstacle_mask()[t.index(x, y)] != 0, want) << "seed " << seed << " cell " << x << "," << y;
        }
      EXPECT_GT(obstacles, 0);
      EXPECT_LT(obstacles, m.width() * m.height());
      EXPECT_EQ(liu_obstacle_mask(t, p), t.obstacle_mask());
    }
  }
}

TEST(TerrainAnalysis, SlopeThresholdAloneMakesObstacles) {
  // At 1 m cells a 0.04 m step stays below h_y = 0.05 but a slope threshold of 0.03 rad
  // (tan 0.03 * 1 m = 0.030 m) is reached by straight moves, and not by diagonal ones
  // (0.04 / 1.414 = 0.028 rad).
  ElevationMap m(geometry(4, 3, 1.0));
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) m.set_height(x, y, x >= 2 ? 0.04 : 0.0);
  TerrainAnalysisOptions o;
  o.thresholds.a_y = 0.03;
  o.robot_radius_m = 0.0;
  const TerrainAnalysis t(m, o);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(t.obstacle_mask()[t.index(x, y)], (x == 1 || x == 2) ? 1 : 0);
  o.thresholds.a_y = 0.02;  // now diagonals reach it too, but they only join columns 1 and 2
  const TerrainAnalysis t2(m, o);
  EXPECT_EQ(t2.obstacle_mask(), t.obstacle_mask());
}

TEST(TerrainAnalysis, LiCriteriaBlockExactlyTheExpectedCells) {
  // Flat ground at 0.1 m with (a) one cell whose own spread is 0.06 > 0.05 m and (b) a step of
  // 0.03 m between columns 9 and 10: 0.03 > tan(15 deg) * 0.1 = 0.0268 blocks both sides of the
  // step; the diagonal pairs across it (0.03 < 0.0379) would not on their own.
  ElevationMap m(geometry(16, 8, 0.1));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) m.set_height(x, y, x >= 10 ? 0.03 : 0.0);
  m.set_cell(3, 4, 0.0, -0.03, 0.03);   // spread 0.06, mid unchanged
  m.set_cell(5, 2, 0.0, -0.02, 0.025);  // spread 0.045: fine; mid 0.0025: fine
  TerrainAnalysisOptions o;
  o.robot_radius_m = 0.0;
  const TerrainAnalysis t(m, o);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      const bool want = (x == 3 && y == 4) || x == 9 || x == 10;
      EXPECT_EQ(t.li_blocked_mask()[t.index(x, y)] != 0, want) << x << "," << y;
    }
  // Just below the slope limit (0.026 < 0.0268): nothing blocked by the step.
  ElevationMap low(geometry(16, 8, 0.1));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) low.set_height(x, y, x >= 10 ? 0.026 : 0.0);
  const TerrainAnalysis tl(low, o);
  for (const auto v : tl.li_blocked_mask()) EXPECT_EQ(v, 0);
  // A diagonal-only neighbour relation: a single raised cell (0.03) blocks itself and its 4
  // straight neighbours; its diagonal neighbours only if 0.03 > 0.0268 * sqrt 2 = 0.0379: no.
  ElevationMap bump(geometry(7, 7, 0.1));
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) bump.set_height(x, y, (x == 3 && y == 3) ? 0.03 : 0.0);
  const TerrainAnalysis tb(bump, o);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) {
      const bool want = std::abs(x - 3) + std::abs(y - 3) <= 1;
      EXPECT_EQ(tb.li_blocked_mask()[tb.index(x, y)] != 0, want) << x << "," << y;
    }
  // Unobserved neighbours are ignored; unobserved cells are blocked only under Blocked.
  bump.clear_cell(3, 3);
  const TerrainAnalysis tu(bump, o);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) EXPECT_EQ(tu.li_blocked_mask()[tu.index(x, y)] != 0, x == 3 && y == 3);
  o.unobserved = UnobservedPolicy::FreeFlat;
  const TerrainAnalysis tf(bump, o);
  for (const auto v : tf.li_blocked_mask()) EXPECT_EQ(v, 0);
}

TEST(TerrainAnalysis, ExpansionMatchesBruteForce) {
  const ElevationMap m = random_terrain(21, 23, 19, 0.1, 0.02, 0.03);
  for (const double radius : {0.0, 0.1, 0.15, 0.3, 0.36, 0.5}) {
    TerrainAnalysisOptions o;
    o.thresholds.h_y = 0.045;
    o.robot_radius_m = radius;
    const TerrainAnalysis t(m, o);
    const double rc = radius / 0.1;
    EXPECT_EQ(t.expanded_obstacle_mask(), brute_expand(t.obstacle_mask(), 23, 19, rc)) << radius;
    EXPECT_EQ(t.expanded_li_blocked_mask(), brute_expand(t.li_blocked_mask(), 23, 19, rc)) << radius;
  }
}

TEST(TerrainAnalysis, IncrementalUpdateEqualsFullRecompute) {
  ElevationMap m = random_terrain(31, 40, 30, 0.1, 0.02, 0.05);
  TerrainAnalysisOptions o;
  o.thresholds.h_y = 0.04;
  o.robot_radius_m = 0.32;
  TerrainAnalysis t(m, o);
  Rng rng(99);
  for (int round = 0; round < 25; ++round) {
    CellRect r;
    r.x0 = static_cast<int>(rng.uniform_int(-2, 39));
    r.y0 = static_cast<int>(rng.uniform_int(-2, 29));
    r.x1 = r.x0 + static_cast<int>(rng.uniform_int(1, 8));
    r.y1 = r.y0 + static_cast<int>(rng.uniform_int(1, 8));
    for (int y = std::max(0, r.y0); y < std::min(30, r.y1); ++y)
      for (int x = std::max(0, r.x0); x < std::min(40, r.x1); ++x) {
        if (rng.uniform() < 0.2) {
          m.clear_cell(x, y);
        } else {
          const double z = 0.1 * rng.normal();
          m.set_cell(x, y, z, z - 0.04 * rng.uniform(), z + 0.04 * rng.uniform());
        }
      }
    t.update(m, r);
    const TerrainAnalysis full(m, o);
    SCOPED_TRACE(round);
    expect_same_analysis(t, full);
  }
}

TEST(TerrainAnalysis, UnobservedPolicies) {
  ElevationMap m(geometry(5, 5, 0.1));
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) m.set_height(x, y, 0.0);
  m.clear_cell(2, 2);
  TerrainAnalysisOptions o;
  o.robot_radius_m = 0.0;
  const TerrainAnalysis blocked(m, o);
  EXPECT_EQ(blocked.obstacle_mask()[blocked.index(2, 2)], 1);
  EXPECT_EQ(blocked.li_blocked_mask()[blocked.index(2, 2)], 1);
  EXPECT_EQ(blocked.ruggedness(2, 2), 0.0);
  EXPECT_FALSE(blocked.move(2, 1, move_index(0, 1)).known);
  o.unobserved = UnobservedPolicy::FreeFlat;
  const TerrainAnalysis flat(m, o);
  EXPECT_EQ(flat.obstacle_mask()[flat.index(2, 2)], 0);
  o.unobserved = UnobservedPolicy::UnknownCost;
  const TerrainAnalysis unknown(m, o);
  EXPECT_EQ(unknown.obstacle_mask()[unknown.index(2, 2)], 0);
  EXPECT_EQ(parse_unobserved_policy("free_flat"), UnobservedPolicy::FreeFlat);
  EXPECT_STREQ(unobserved_policy_name(UnobservedPolicy::UnknownCost), "unknown_cost");
  EXPECT_THROW(parse_unobserved_policy("free"), Error);
}

TEST(TerrainAnalysis, BadOptionsNameTheField) {
  const ElevationMap m = random_terrain(1, 4, 4);
  TerrainAnalysisOptions o;
  o.robot_radius_m = -1.0;
  try {
    TerrainAnalysis t(m, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "robot_radius_m");
  }
  o = {};
  o.li.max_slope_rad = 2.0;
  try {
    TerrainAnalysis t(m, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "max_slope_rad");
  }
}

}  // namespace
