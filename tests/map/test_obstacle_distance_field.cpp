// The navigation map's distance field: after any sequence of changes, every cell a reader refreshed
// equals the brute-force distance to the nearest obstacle cell (cells outside the grid count),
// capped at the range, and its nearest cell is an obstacle at that distance; regions nobody
// refreshed stay stale until read.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/map/obstacle_distance_field.hpp"

namespace starnav {
namespace {

// Brute force over every obstacle cell and the one-cell frame outside the grid.
double brute_squared(const std::vector<std::uint8_t>& mask, int w, int h, int x, int y, double range_cells) {
  double best = std::numeric_limits<double>::infinity();
  for (int v = -1; v <= h; ++v)
    for (int u = -1; u <= w; ++u) {
      const bool outside = u < 0 || v < 0 || u >= w || v >= h;
      if (!outside && !mask[static_cast<std::size_t>(v * w + u)]) continue;
      best = std::min(best, static_cast<double>((u - x) * (u - x) + (v - y) * (v - y)));
    }
  return best <= range_cells * range_cells + 1e-9 ? best : std::numeric_limits<double>::infinity();
}

void expect_exact(const ObstacleDistanceField& field, const std::vector<std::uint8_t>& mask, const CellRect& region,
                  double range_cells) {
  const GridGeometry& g = field.geometry();
  ASSERT_TRUE(field.up_to_date(region));
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const std::size_t i = g.index(x, y);
      const double truth = brute_squared(mask, g.width, g.height, x, y, range_cells);
      ASSERT_EQ(field.squared_cells(i), truth) << x << "," << y;
      if (!std::isfinite(truth)) continue;
      const Cell n = field.nearest_cell(i);
      EXPECT_TRUE(field.obstacle(n.x, n.y)) << x << "," << y;
      EXPECT_EQ(static_cast<double>((n.x - x) * (n.x - x) + (n.y - y) * (n.y - y)), truth) << x << "," << y;
      EXPECT_NEAR(field.distance_m(i), std::sqrt(truth) * g.resolution, 1e-12);
    }
}

TEST(ObstacleDistanceField, RefreshedRegionsEqualBruteForceAfterRandomChanges) {
  for (const double range_m : {0.35, 0.8, 3.0}) {  // within one tile, across tiles, beyond the grid
    GridGeometry g;
    g.width = 97;
    g.height = 71;
    g.resolution = 0.1;
    std::vector<std::uint8_t> mask(g.cell_count(), 0);
    Rng rng(static_cast<std::uint64_t>(range_m * 100));
    for (std::uint8_t& m : mask) m = rng.uniform() < 0.02 ? 1 : 0;
    ObstacleDistanceField field(g, &mask, range_m);
    const double range_cells = range_m / g.resolution;
    EXPECT_FALSE(field.up_to_date({0, 0, g.width, g.height}));
    for (int round = 0; round < 12; ++round) {
      // A cluster of flips (obstacles appear and vanish), noted as its bounding rectangle.
      const int cx = static_cast<int>(rng.uniform_int(0, g.width - 1)), cy = static_cast<int>(rng.uniform_int(0, g.height - 1));
      const int half = static_cast<int>(rng.uniform_int(0, 6));
      CellRect changed{std::max(0, cx - half), std::max(0, cy - half), std::min(g.width, cx + half + 1), std::min(g.height, cy + half + 1)};
      for (int y = changed.y0; y < changed.y1; ++y)
        for (int x = changed.x0; x < changed.x1; ++x)
          if (rng.uniform() < 0.3) mask[g.index(x, y)] ^= 1;
      field.mark_changed(changed);
      // A reader's window somewhere (often not where the change was).
      const int rx = static_cast<int>(rng.uniform_int(-5, g.width - 1)), ry = static_cast<int>(rng.uniform_int(-5, g.height - 1));
      const CellRect read{rx, ry, rx + static_cast<int>(rng.uniform_int(1, 40)), ry + static_cast<int>(rng.uniform_int(1, 40))};
      field.refresh(read);
      const CellRect clipped = read.grown(0, g.width, g.height);
      expect_exact(field, mask, clipped, range_cells);
    }
    field.refresh();
    expect_exact(field, mask, {0, 0, g.width, g.height}, range_cells);
  }
}

TEST(ObstacleDistanceField, AChangeStalesOnlyTheTilesWithinRangeOfIt) {
  GridGeometry g;
  g.width = 256;
  g.height = 256;
  g.resolution = 0.05;
  std::vector<std::uint8_t> mask(g.cell_count(), 0);
  ObstacleDistanceField field(g, &mask, 0.5);  // 10 cells
  field.refresh();
  mask[g.index(10, 10)] = 1;
  field.mark_changed({10, 10, 11, 11});
  EXPECT_FALSE(field.up_to_date({0, 0, 20, 20}));
  EXPECT_TRUE(field.up_to_date({100, 100, 256, 256}));  // far beyond the range: untouched
  field.refresh({200, 200, 256, 256});
  EXPECT_FALSE(field.up_to_date({0, 0, 20, 20}));  // refreshing elsewhere leaves it stale
  field.refresh({0, 0, 5, 5});
  EXPECT_TRUE(field.up_to_date({0, 0, 20, 20}));
  EXPECT_EQ(field.squared_cells(g.index(13, 14)), 25.0);
}

}  // namespace
}  // namespace starnav
