// ElevationMap: observed cells, setters that refuse non-finite heights, height range.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "starnav/core/error.hpp"
#include "starnav/map/elevation_map.hpp"

namespace {

using starnav::ElevationMap;
using starnav::GridGeometry;

GridGeometry geometry(int w, int h, double res = 0.5) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = starnav::Pose2(3.0, 4.0, 0.25);
  return g;
}

}  // namespace

TEST(ElevationMap, StartsUnobserved) {
  const ElevationMap m(geometry(4, 3));
  EXPECT_EQ(m.width(), 4);
  EXPECT_EQ(m.height(), 3);
  EXPECT_EQ(m.cell_count(), 12u);
  EXPECT_DOUBLE_EQ(m.resolution(), 0.5);
  EXPECT_DOUBLE_EQ(m.origin().yaw, 0.25);
  EXPECT_EQ(m.observed_count(), 0u);
  EXPECT_FALSE(m.height_range().has_value());
  EXPECT_FALSE(m.observed_at(2, 1));
  EXPECT_FALSE(m.height_checked(2, 1).has_value());
  EXPECT_EQ(m.height_at(2, 1), 0.0);
  const ElevationMap empty;
  EXPECT_EQ(empty.cell_count(), 0u);
  EXPECT_FALSE(empty.height_range().has_value());
}

TEST(ElevationMap, SetHeightAndCellAndClear) {
  ElevationMap m(geometry(4, 3));
  m.set_height(1, 2, -0.75);
  m.set_cell(3, 0, 2.0, 1.5, 2.5);
  EXPECT_EQ(m.observed_count(), 2u);
  EXPECT_TRUE(m.observed_at(1, 2));
  EXPECT_TRUE(m.observed_at_index(m.geometry().index(3, 0)));
  EXPECT_EQ(m.height_checked(1, 2), -0.75);
  EXPECT_EQ(m.min_height_at(1, 2), -0.75);
  EXPECT_EQ(m.max_height_at(1, 2), -0.75);
  EXPECT_EQ(m.height_at(3, 0), 2.0);
  EXPECT_EQ(m.height_at_index(m.geometry().index(3, 0)), 2.0);
  EXPECT_EQ(m.min_height_at(3, 0), 1.5);
  EXPECT_EQ(m.max_height_at(3, 0), 2.5);
  auto r = m.height_range();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->min, -0.75);
  EXPECT_EQ(r->max, 2.5);  // max of the per-cell maxima
  m.clear_cell(3, 0);
  EXPECT_EQ(m.observed_count(), 1u);
  EXPECT_FALSE(m.height_checked(3, 0).has_value());
  EXPECT_EQ(m.height_at(3, 0), 0.0);
  r = m.height_range();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->min, -0.75);
  EXPECT_EQ(r->max, -0.75);
  m.clear_cell(1, 2);
  EXPECT_FALSE(m.height_range().has_value());
  // Unobserved cells hold 0 but do not count toward the range.
  m.set_height(0, 0, 10.0);
  r = m.height_range();
  EXPECT_EQ(r->min, 10.0);
  EXPECT_EQ(r->max, 10.0);
}

TEST(ElevationMap, RejectsNonFiniteAndInconsistentHeights) {
  ElevationMap m(geometry(2, 2));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(m.set_height(0, 0, nan), starnav::Error);
  EXPECT_THROW(m.set_height(0, 0, inf), starnav::Error);
  EXPECT_THROW(m.set_height(0, 0, -inf), starnav::Error);
  EXPECT_THROW(m.set_cell(0, 0, 1.0, nan, 2.0), starnav::Error);
  EXPECT_THROW(m.set_cell(0, 0, 1.0, 0.0, inf), starnav::Error);
  EXPECT_THROW(m.set_cell(0, 0, 1.0, 1.5, 2.0), starnav::Error);  // h < min
  EXPECT_THROW(m.set_cell(0, 0, 3.0, 1.5, 2.0), starnav::Error);  // h > max
  try {
    m.set_height(1, 1, nan);
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.field(), "height");
  }
  EXPECT_EQ(m.observed_count(), 0u);  // nothing stored by the failed calls
  for (double h : m.heights()) EXPECT_TRUE(std::isfinite(h));
}

TEST(ElevationMap, OutsideTheMapThrowsOutOfRange) {
  ElevationMap m(geometry(2, 2));
  EXPECT_THROW(m.set_height(2, 0, 1.0), std::out_of_range);
  EXPECT_THROW(m.set_height(0, -1, 1.0), std::out_of_range);
  EXPECT_THROW(m.set_cell(5, 5, 1.0, 1.0, 1.0), std::out_of_range);
  EXPECT_THROW(m.clear_cell(-1, 0), std::out_of_range);
  EXPECT_THROW((void)m.height_checked(0, 2), std::out_of_range);
}

TEST(ElevationMap, GeometryValidation) {
  EXPECT_THROW(ElevationMap(geometry(0, 2)), starnav::Error);
  EXPECT_THROW(ElevationMap(geometry(2, -2)), starnav::Error);
  try {
    ElevationMap m(geometry(2, 2, 0.0));
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.field(), "resolution");
    EXPECT_NE(std::string(e.what()).find("elevation map"), std::string::npos);
  }
  GridGeometry g = geometry(2, 2);
  g.origin.y = std::nan("");
  try {
    ElevationMap m(g);
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.field(), "origin");
  }
}

TEST(ElevationMap, Equality) {
  ElevationMap a(geometry(3, 3)), b(geometry(3, 3));
  EXPECT_TRUE(a == b);
  a.set_height(1, 1, 0.0);  // observed 0 differs from unobserved 0
  EXPECT_FALSE(a == b);
  b.set_height(1, 1, 0.0);
  EXPECT_TRUE(a == b);
  b.set_cell(1, 1, 0.0, -0.1, 0.0);
  EXPECT_FALSE(a == b);
  b.set_height(1, 1, 0.0);
  b.mutable_geometry().y_down = true;
  EXPECT_FALSE(a == b);
}
