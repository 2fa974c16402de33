// The exact Euclidean distance transform against brute force (min over all obstacle cells) on
// many random masks, and against closed forms on special masks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace {

using starnav::DistanceTransform;
using starnav::kNoObstacle;

struct Brute {
  std::vector<double> squared;
  std::vector<std::int32_t> nearest;  // first obstacle (lowest column, then lowest row) at min distance
};

Brute brute_force(const std::vector<std::uint8_t>& mask, int w, int h) {
  Brute b;
  b.squared.assign(mask.size(), std::numeric_limits<double>::infinity());
  b.nearest.assign(mask.size(), kNoObstacle);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      for (int ox = 0; ox < w; ++ox) {
        for (int oy = 0; oy < h; ++oy) {
          if (!mask[static_cast<std::size_t>(oy) * w + ox]) continue;
          const double d = double(x - ox) * (x - ox) + double(y - oy) * (y - oy);
          if (d < b.squared[i]) {
            b.squared[i] = d;
            b.nearest[i] = oy * w + ox;
          }
        }
      }
    }
  }
  return b;
}

std::vector<std::uint8_t> random_mask(starnav::Rng& rng, int w, int h, double density) {
  std::vector<std::uint8_t> m(static_cast<std::size_t>(w) * h);
  for (auto& v : m) v = rng.bernoulli(density) ? 1 : 0;
  return m;
}

void expect_matches_brute_force(const std::vector<std::uint8_t>& mask, int w, int h, DistanceTransform& dt,
                                const std::string& what) {
  dt.compute(mask, w, h, /*with_nearest=*/true);
  const Brute b = brute_force(mask, w, h);
  ASSERT_EQ(dt.squared_cells().size(), mask.size()) << what;
  ASSERT_EQ(dt.nearest().size(), mask.size()) << what;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    ASSERT_EQ(dt.squared_cells()[i], b.squared[i]) << what << " cell " << i;
    const std::int32_t n = dt.nearest()[i];
    if (b.nearest[i] == kNoObstacle) {
      ASSERT_EQ(n, kNoObstacle) << what << " cell " << i;
      continue;
    }
    ASSERT_GE(n, 0) << what;
    ASSERT_LT(static_cast<std::size_t>(n), mask.size()) << what;
    ASSERT_TRUE(mask[static_cast<std::size_t>(n)]) << what << " nearest of cell " << i << " is not an obstacle";
    // The documented tie rule (lowest column, then lowest row) makes the index unique.
    ASSERT_EQ(n, b.nearest[i]) << what << " cell " << i;
  }
}

}  // namespace

TEST(DistanceTransform, MatchesBruteForceOnRandomMasks) {
  starnav::Rng rng(12345);
  DistanceTransform dt;  // reused on purpose: buffers of all sizes must be handled
  const double densities[] = {0.0, 0.002, 0.01, 0.05, 0.2, 0.5, 0.9, 1.0};
  int tested = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int w = static_cast<int>(rng.uniform_int(1, 40));
    const int h = static_cast<int>(rng.uniform_int(1, 40));
    const double density = densities[trial % 8];
    const auto mask = random_mask(rng, w, h, density);
    expect_matches_brute_force(mask, w, h, dt,
                               "trial " + std::to_string(trial) + " (" + std::to_string(w) + "x" + std::to_string(h) +
                                   ", density " + std::to_string(density) + ")");
    if (HasFatalFailure()) return;
    ++tested;
  }
  EXPECT_EQ(tested, 400);
}

TEST(DistanceTransform, MatchesBruteForceOnThinAndTinyMasks) {
  starnav::Rng rng(7);
  DistanceTransform dt;
  for (int w = 1; w <= 4; ++w) {
    for (int h = 1; h <= 4; ++h) {
      const std::size_t n = static_cast<std::size_t>(w) * h;
      for (std::uint32_t bits = 0; bits < (1u << n); ++bits) {  // every mask up to 4x4
        std::vector<std::uint8_t> mask(n);
        for (std::size_t i = 0; i < n; ++i) mask[i] = (bits >> i) & 1u;
        expect_matches_brute_force(mask, w, h, dt, std::to_string(w) + "x" + std::to_string(h) + " bits " + std::to_string(bits));
        if (HasFatalFailure()) return;
      }
    }
  }
  for (int trial = 0; trial < 40; ++trial) {  // single rows and columns
    const int len = static_cast<int>(rng.uniform_int(1, 200));
    const auto row = random_mask(rng, len, 1, 0.03);
    expect_matches_brute_force(row, len, 1, dt, "row " + std::to_string(trial));
    const auto col = random_mask(rng, 1, len, 0.03);
    expect_matches_brute_force(col, 1, len, dt, "column " + std::to_string(trial));
    if (HasFatalFailure()) return;
  }
}

TEST(DistanceTransform, EmptyMaskIsInfiniteEverywhere) {
  const std::vector<std::uint8_t> mask(13 * 7, 0);
  std::vector<std::int32_t> nearest;
  const auto d = starnav::squared_distance_transform(mask, 13, 7, &nearest);
  ASSERT_EQ(d.size(), mask.size());
  for (double v : d) EXPECT_TRUE(std::isinf(v) && v > 0);
  for (auto n : nearest) EXPECT_EQ(n, kNoObstacle);
  DistanceTransform dt;
  dt.compute(mask, 13, 7);
  EXPECT_FALSE(dt.has_obstacle());
  EXPECT_TRUE(dt.nearest().empty());
}

TEST(DistanceTransform, FullMaskIsZeroEverywhere) {
  const std::vector<std::uint8_t> mask(17 * 5, 1);
  std::vector<std::int32_t> nearest;
  const auto d = starnav::squared_distance_transform(mask, 17, 5, &nearest);
  for (std::size_t i = 0; i < d.size(); ++i) {
    EXPECT_EQ(d[i], 0.0);
    EXPECT_EQ(nearest[i], static_cast<std::int32_t>(i));
  }
}

TEST(DistanceTransform, SingleObstacleClosedForm) {
  const int w = 61, h = 37, ox = 20, oy = 29;
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(w) * h, 0);
  mask[static_cast<std::size_t>(oy) * w + ox] = 1;
  DistanceTransform dt;
  dt.compute(mask, w, h, true);
  EXPECT_TRUE(dt.has_obstacle());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      EXPECT_EQ(dt.squared_at(x, y), double((x - ox) * (x - ox) + (y - oy) * (y - oy)));
      EXPECT_EQ(dt.nearest()[static_cast<std::size_t>(y) * w + x], oy * w + ox);
    }
}

TEST(DistanceTransform, LargeDistancesStayExact) {
  // One obstacle in a corner of a long, thin map: distances up to ~ 3000^2 + 40^2.
  const int w = 3000, h = 40;
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(w) * h, 0);
  mask[0] = 1;
  const auto d = starnav::squared_distance_transform(mask, w, h);
  EXPECT_EQ(d[static_cast<std::size_t>(h - 1) * w + (w - 1)], double(w - 1) * (w - 1) + double(h - 1) * (h - 1));
  EXPECT_EQ(d[static_cast<std::size_t>(w - 1)], double(w - 1) * (w - 1));
}

TEST(DistanceTransform, ReuseAcrossSizesAndNearestToggle) {
  starnav::Rng rng(99);
  DistanceTransform dt;
  const auto a = random_mask(rng, 30, 20, 0.05);
  dt.compute(a, 30, 20, true);
  EXPECT_EQ(dt.nearest().size(), a.size());
  const auto first = dt.squared_cells();
  const auto b = random_mask(rng, 7, 50, 0.1);
  dt.compute(b, 7, 50, false);
  EXPECT_TRUE(dt.nearest().empty());
  EXPECT_EQ(dt.width(), 7);
  EXPECT_EQ(dt.height(), 50);
  dt.compute(a, 30, 20, false);
  EXPECT_EQ(dt.squared_cells(), first);
}

TEST(DistanceTransform, RejectsBadSizes) {
  const std::vector<std::uint8_t> mask(12, 0);
  DistanceTransform dt;
  EXPECT_THROW(dt.compute(mask, 0, 12), starnav::Error);
  EXPECT_THROW(dt.compute(mask, -3, -4), starnav::Error);
  EXPECT_THROW(dt.compute(mask, 5, 2), starnav::Error);  // 10 != 12
  try {
    dt.compute(mask, 5, 5);
    FAIL() << "size mismatch accepted";
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.field(), "mask");
  }
  EXPECT_THROW(dt.compute(mask, 65536, 65536), starnav::Error);  // more than 2^31 - 1 cells
}

TEST(DistanceTransform, ObstacleDistanceInMetresOnAnOccupancyGrid) {
  starnav::GridGeometry g;
  g.width = 9;
  g.height = 6;
  g.resolution = 0.25;
  g.origin = starnav::Pose2(-3.0, 2.0, 0.7);  // rotation must not matter
  starnav::OccupancyGrid grid(g, 0);
  grid.set(2, 1, 100);  // occupied
  grid.set(8, 5, -1);   // unknown
  grid.set(5, 3, 50);   // between thresholds: occupied by default
  std::vector<std::int32_t> nearest;
  const auto blocked_unknown = starnav::obstacle_distance_m(grid, {}, true, &nearest);
  const auto free_unknown = starnav::obstacle_distance_m(grid, {}, false);
  starnav::OccupancyThresholds between_free;
  between_free.between_is_free = true;
  const auto only_wall = starnav::obstacle_distance_m(grid, between_free, false);
  auto dist = [](int x, int y, int ox, int oy) { return 0.25 * std::sqrt(double((x - ox) * (x - ox) + (y - oy) * (y - oy))); };
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * g.width + x;
      const double to_wall = dist(x, y, 2, 1), to_unknown = dist(x, y, 8, 5), to_between = dist(x, y, 5, 3);
      EXPECT_DOUBLE_EQ(blocked_unknown[i], std::min({to_wall, to_unknown, to_between})) << x << "," << y;
      EXPECT_DOUBLE_EQ(free_unknown[i], std::min(to_wall, to_between)) << x << "," << y;
      EXPECT_DOUBLE_EQ(only_wall[i], to_wall) << x << "," << y;
      // The nearest index points at a cell at exactly that distance.
      const auto c = g.cell_of_index(static_cast<std::size_t>(nearest[i]));
      EXPECT_DOUBLE_EQ(dist(x, y, c.x, c.y), blocked_unknown[i]);
    }
  const starnav::OccupancyGrid free_grid(g, 0);
  for (double v : starnav::obstacle_distance_m(free_grid)) EXPECT_TRUE(std::isinf(v));
}

TEST(DistanceTransform, ThreadCountDoesNotChangeTheResult) {
  starnav::Rng rng(2024);
  const int w = 1203, h = 1001;  // big enough for several bands, odd sizes
  const auto mask = random_mask(rng, w, h, 0.002);
  DistanceTransform one, many;
  one.compute(mask, w, h, true, 1);
  many.compute(mask, w, h, true, 4);
  EXPECT_EQ(one.squared_cells(), many.squared_cells());
  EXPECT_EQ(one.nearest(), many.nearest());
  DistanceTransform automatic;
  automatic.compute(mask, w, h, false, 0);
  EXPECT_EQ(one.squared_cells(), automatic.squared_cells());
  // Spot-check against brute force on a sample of cells.
  std::vector<int> obstacles;
  for (int i = 0; i < w * h; ++i)
    if (mask[static_cast<std::size_t>(i)]) obstacles.push_back(i);
  for (int s = 0; s < 300; ++s) {
    const int x = static_cast<int>(rng.uniform_int(0, w - 1)), y = static_cast<int>(rng.uniform_int(0, h - 1));
    double best = std::numeric_limits<double>::infinity();
    for (int o : obstacles) {
      const int ox = o % w, oy = o / w;
      best = std::min(best, double(x - ox) * (x - ox) + double(y - oy) * (y - oy));
    }
    ASSERT_EQ(many.squared_at(x, y), best) << x << "," << y;
  }
  EXPECT_THROW(one.compute(mask, w, h, false, -1), starnav::Error);
}
