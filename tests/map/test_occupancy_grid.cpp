// OccupancyGrid: thresholds, counts, blocked masks, checked access, geometry validation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "starnav/core/error.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace {

using starnav::CellState;
using starnav::GridGeometry;
using starnav::OccupancyGrid;
using starnav::OccupancyThresholds;

GridGeometry grid_geometry(int w, int h, double res = 0.05) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = starnav::Pose2(-1.0, -2.0, 0.0);
  return g;
}

std::string error_field(const GridGeometry& g) {
  try {
    OccupancyGrid grid(g);
    return "<no error>";
  } catch (const starnav::Error& e) {
    return e.field();
  }
}

}  // namespace

TEST(OccupancyThresholds, DefaultClassification) {
  const OccupancyThresholds t;  // >= 65 occupied, <= 19.6 free, between occupied
  EXPECT_EQ(t.classify(-1), CellState::Unknown);
  EXPECT_EQ(t.classify(0), CellState::Free);
  EXPECT_EQ(t.classify(19), CellState::Free);
  EXPECT_EQ(t.classify(20), CellState::Occupied);  // 20 > 19.6: between
  EXPECT_EQ(t.classify(50), CellState::Occupied);
  EXPECT_EQ(t.classify(64), CellState::Occupied);
  EXPECT_EQ(t.classify(65), CellState::Occupied);
  EXPECT_EQ(t.classify(100), CellState::Occupied);
  OccupancyThresholds lenient;
  lenient.between_is_free = true;
  EXPECT_EQ(lenient.classify(20), CellState::Free);
  EXPECT_EQ(lenient.classify(64), CellState::Free);
  EXPECT_EQ(lenient.classify(65), CellState::Occupied);
  EXPECT_EQ(lenient.classify(-1), CellState::Unknown);
}

TEST(OccupancyThresholds, CustomThresholdsAreInclusive) {
  OccupancyThresholds t;
  t.occupied_percent = 50.0;
  t.free_percent = 10.0;
  t.between_is_free = true;
  EXPECT_EQ(t.classify(10), CellState::Free);
  EXPECT_EQ(t.classify(11), CellState::Free);  // between, treated free
  EXPECT_EQ(t.classify(49), CellState::Free);
  EXPECT_EQ(t.classify(50), CellState::Occupied);
  t.between_is_free = false;
  EXPECT_EQ(t.classify(11), CellState::Occupied);
  EXPECT_EQ(t.classify(10), CellState::Free);
}

TEST(OccupancyGrid, FillAccessAndCounts) {
  OccupancyGrid grid(grid_geometry(5, 4), starnav::kUnknownOccupancy);
  EXPECT_EQ(grid.width(), 5);
  EXPECT_EQ(grid.height(), 4);
  EXPECT_EQ(grid.cell_count(), 20u);
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.05);
  EXPECT_DOUBLE_EQ(grid.origin().x, -1.0);
  auto c = grid.counts();
  EXPECT_EQ(c.unknown, 20u);
  EXPECT_EQ(c.free + c.occupied, 0u);
  grid.set(0, 0, 0);
  grid.set(4, 3, 100);
  grid.set(2, 1, 40);  // between
  grid.set(3, 1, 10);
  grid(1, 2) = 0;      // unchecked write
  EXPECT_EQ(grid.at(4, 3), 100);
  EXPECT_EQ(grid(2, 1), 40);
  EXPECT_EQ(grid[grid.geometry().index(3, 1)], 10);
  EXPECT_EQ(grid.data()[static_cast<std::size_t>(2 * 5 + 1)], 0);
  EXPECT_EQ(grid.state(4, 3), CellState::Occupied);
  EXPECT_EQ(grid.state(0, 1), CellState::Unknown);
  c = grid.counts();
  EXPECT_EQ(c.free, 3u);
  EXPECT_EQ(c.occupied, 2u);
  EXPECT_EQ(c.unknown, 15u);
  OccupancyThresholds lenient;
  lenient.between_is_free = true;
  c = grid.counts(lenient);
  EXPECT_EQ(c.free, 4u);
  EXPECT_EQ(c.occupied, 1u);
  EXPECT_EQ(c.free + c.occupied + c.unknown, grid.cell_count());
}

TEST(OccupancyGrid, BlockedMaskWithUnknownFreeOrBlocked) {
  OccupancyGrid grid(grid_geometry(3, 2), 0);
  grid.set(0, 0, -1);
  grid.set(1, 0, 100);
  grid.set(2, 0, 30);
  grid.set(0, 1, 19);
  grid.set(1, 1, 65);
  // row-major, iy = 0 first
  EXPECT_EQ(grid.blocked_mask(), (std::vector<std::uint8_t>{1, 1, 1, 0, 1, 0}));
  EXPECT_EQ(grid.blocked_mask({}, /*unknown_is_free=*/true), (std::vector<std::uint8_t>{0, 1, 1, 0, 1, 0}));
  OccupancyThresholds lenient;
  lenient.between_is_free = true;
  EXPECT_EQ(grid.blocked_mask(lenient, true), (std::vector<std::uint8_t>{0, 1, 0, 0, 1, 0}));
  EXPECT_EQ(grid.blocked_mask(lenient, false), (std::vector<std::uint8_t>{1, 1, 0, 0, 1, 0}));
}

TEST(OccupancyGrid, CheckedAccessorsThrow) {
  OccupancyGrid grid(grid_geometry(3, 2), 0);
  EXPECT_THROW((void)grid.at(3, 0), std::out_of_range);
  EXPECT_THROW((void)grid.at(0, 2), std::out_of_range);
  EXPECT_THROW((void)grid.at(-1, 0), std::out_of_range);
  EXPECT_THROW(grid.set(0, -1, 0), std::out_of_range);
  EXPECT_THROW(grid.set(5, 5, 0), std::out_of_range);
  EXPECT_THROW(grid.set(0, 0, 101), starnav::Error);
  EXPECT_THROW(grid.set(0, 0, -2), starnav::Error);
  EXPECT_THROW(grid.set(0, 0, std::numeric_limits<std::int8_t>::min()), starnav::Error);
  EXPECT_EQ(grid.at(0, 0), 0);  // unchanged by the failed writes
  EXPECT_NO_THROW(grid.set(2, 1, -1));
  EXPECT_NO_THROW(grid.set(2, 1, 100));
  EXPECT_THROW(OccupancyGrid(grid_geometry(2, 2), 101), starnav::Error);
  EXPECT_THROW(OccupancyGrid(grid_geometry(2, 2), -5), starnav::Error);
}

TEST(OccupancyGrid, GeometryValidation) {
  EXPECT_THROW(OccupancyGrid(grid_geometry(0, 3)), starnav::Error);
  EXPECT_THROW(OccupancyGrid(grid_geometry(3, -1)), starnav::Error);
  EXPECT_THROW(OccupancyGrid(grid_geometry(70000, 70000)), starnav::Error);  // > 2^31 - 1 cells
  EXPECT_EQ(error_field(grid_geometry(3, 3, 0.0)), "resolution");
  EXPECT_EQ(error_field(grid_geometry(3, 3, -0.1)), "resolution");
  EXPECT_EQ(error_field(grid_geometry(3, 3, std::nan(""))), "resolution");
  EXPECT_EQ(error_field(grid_geometry(3, 3, std::numeric_limits<double>::infinity())), "resolution");
  GridGeometry g = grid_geometry(3, 3);
  g.origin.yaw = std::nan("");
  EXPECT_EQ(error_field(g), "origin");
  g = grid_geometry(3, 3);
  g.origin.x = std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_field(g), "origin");
  EXPECT_EQ(error_field(grid_geometry(3, 3)), "<no error>");
  try {
    OccupancyGrid bad(grid_geometry(0, 3));
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_NE(std::string(e.what()).find("occupancy grid"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(starnav::validate_geometry(grid_geometry(1, 1)));
  EXPECT_THROW(starnav::validate_geometry(grid_geometry(1, 0), "x"), starnav::Error);
}

TEST(OccupancyGrid, EqualityComparesGeometryAndData) {
  OccupancyGrid a(grid_geometry(3, 2), 0), b(grid_geometry(3, 2), 0);
  EXPECT_TRUE(a == b);
  b.set(1, 1, 100);
  EXPECT_FALSE(a == b);
  b.set(1, 1, 0);
  EXPECT_TRUE(a == b);
  b.mutable_geometry().origin.yaw = 0.1;
  EXPECT_FALSE(a == b);
  b.mutable_geometry().origin.yaw = 0.0;
  b.mutable_geometry().y_down = true;  // an index grid is not the same map as a metric one
  EXPECT_FALSE(a == b);
  const OccupancyGrid c(grid_geometry(2, 3), 0);  // same cell count, other shape
  EXPECT_FALSE(a == c);
}
