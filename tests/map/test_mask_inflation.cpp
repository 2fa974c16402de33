// The inflation stage: the incremental update equals inflating the whole mask (random masks,
// random changes, radii on and off cell multiples), and the radius rule includes a distance of
// exactly k cells for a radius given as k * resolution in metres.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/map/mask_inflation.hpp"

namespace starnav {
namespace {

// Brute force: every pair of cells.
std::vector<std::uint8_t> brute_inflate(const std::vector<std::uint8_t>& mask, int w, int h, double rc) {
  std::vector<std::uint8_t> out(mask.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool hit = mask[static_cast<std::size_t>(y * w + x)] != 0;
      for (int v = 0; v < h && !hit; ++v)
        for (int u = 0; u < w && !hit; ++u)
          if (mask[static_cast<std::size_t>(v * w + u)])
            hit = within_inflation_radius(static_cast<double>((u - x) * (u - x) + (v - y) * (v - y)), rc);
      out[static_cast<std::size_t>(y * w + x)] = hit ? 1 : 0;
    }
  return out;
}

TEST(MaskInflation, WholeGridMatchesBruteForce) {
  Rng rng(3);
  for (double rc : {0.0, 1.0, 1.5, 2.9999999999999996, 3.2}) {
    const int w = 23, h = 17;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(w * h));
    for (auto& m : mask) m = rng.uniform() < 0.04 ? 1 : 0;
    EXPECT_EQ(inflate_mask(mask, w, h, rc), brute_inflate(mask, w, h, rc)) << rc;
  }
}

TEST(MaskInflation, IncrementalUpdatesEqualInflatingTheWholeMask) {
  Rng rng(11);
  IncrementalInflation inc;
  for (double rc : {0.0, 2.0, 3.7}) {
    const int w = 60, h = 45;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(w * h));
    for (auto& m : mask) m = rng.uniform() < 0.02 ? 1 : 0;
    std::vector<std::uint8_t> out = inflate_mask(mask, w, h, rc);
    for (int step = 0; step < 40; ++step) {
      // Change a random rectangle: set or clear cells in it.
      const int x0 = static_cast<int>(rng.uniform_int(0, w - 1)), y0 = static_cast<int>(rng.uniform_int(0, h - 1));
      const CellRect r{x0, y0, std::min(w, x0 + 1 + static_cast<int>(rng.uniform_int(0, 6))),
                       std::min(h, y0 + 1 + static_cast<int>(rng.uniform_int(0, 6)))};
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) mask[static_cast<std::size_t>(y * w + x)] = rng.uniform() < 0.5 ? 1 : 0;
      inc.update(mask, w, h, rc, r, out);
      ASSERT_EQ(out, inflate_mask(mask, w, h, rc)) << "radius " << rc << ", step " << step;
    }
  }
}

TEST(MaskInflation, ARadiusOfKCellsInMetresIncludesDistanceK) {
  // 0.3 m / 0.1 m = 2.9999999999999996 cells: a cell 3 cells away is inside.
  EXPECT_TRUE(within_inflation_radius(9.0, inflation_radius_cells(0.3, 0.1)));
  EXPECT_FALSE(within_inflation_radius(10.0, inflation_radius_cells(0.3, 0.1)));
  EXPECT_FALSE(within_inflation_radius(0.0, 0.0));  // radius 0 inflates nothing
  EXPECT_EQ(inflation_margin_cells(inflation_radius_cells(0.3, 0.1)), 4);
}

}  // namespace
}  // namespace starnav
