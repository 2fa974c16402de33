// Map layers: named layers on one grid and the inflation stage over the obstacle layers, kept up
// to date incrementally; after every change it equals a from-scratch stage, and the cells it
// reports as changed are exactly those whose value changed.
#include <gtest/gtest.h>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/map/map_layers.hpp"

namespace starnav {
namespace {

GridGeometry geometry() {
  GridGeometry g;
  g.width = 50;
  g.height = 35;
  g.resolution = 0.1;
  g.origin = Pose2(-1.0, 2.0, 0.0);
  return g;
}

TEST(MapLayers, IncrementalInflationEqualsAFreshStageAfterEveryChange) {
  Rng rng(5);
  const GridGeometry g = geometry();
  OccupancyGrid fixed(g, kFreeOccupancy);
  for (int k = 0; k < 20; ++k)
    fixed.set(static_cast<int>(rng.uniform_int(0, 49)), static_cast<int>(rng.uniform_int(0, 34)), kOccupiedOccupancy);
  MapLayers layers(g);
  layers.set_layer("static", fixed);
  layers.set_layer("sensed", OccupancyGrid(g, kUnknownOccupancy));
  layers.set_layer("notes", OccupancyGrid(g, kOccupiedOccupancy));  // not an obstacle layer
  layers.set_inflation({"static", "sensed"}, 0.25);
  for (int step = 0; step < 60; ++step) {
    const OccupancyGrid before = layers.inflated();
    for (int k = 0; k < 1 + static_cast<int>(rng.uniform_int(0, 5)); ++k) {
      const Cell c{static_cast<int>(rng.uniform_int(0, 49)), static_cast<int>(rng.uniform_int(0, 34))};
      const double u = rng.uniform();
      layers.set_cell("sensed", c, u < 0.4 ? kOccupiedOccupancy : u < 0.8 ? kFreeOccupancy : kUnknownOccupancy);
    }
    const auto changed = layers.update_inflation();
    MapLayers fresh(g);
    fresh.set_layer("static", layers.layer("static"));
    fresh.set_layer("sensed", layers.layer("sensed"));
    fresh.set_inflation({"static", "sensed"}, 0.25);
    ASSERT_TRUE(std::equal(layers.inflated().data().begin(), layers.inflated().data().end(), fresh.inflated().data().begin()))
        << "step " << step;
    std::vector<Cell> expected;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        if (before.at(x, y) != layers.inflated().at(x, y)) expected.push_back({x, y});
    ASSERT_EQ(changed, expected) << "step " << step;
  }
}

TEST(MapLayers, InflatedValuesFollowTheRadiusRuleAndObservation) {
  const GridGeometry g = geometry();
  MapLayers layers(g);
  layers.set_layer("sensed", OccupancyGrid(g, kUnknownOccupancy));
  layers.set_inflation({"sensed"}, 0.3);  // 0.3 / 0.1: three cells, distance 3 included
  layers.set_cell("sensed", {20, 20}, kOccupiedOccupancy);
  layers.set_cell("sensed", {25, 20}, kFreeOccupancy);
  layers.update_inflation();
  EXPECT_EQ(layers.inflated().at(23, 20), kOccupiedOccupancy);  // 3 cells away
  EXPECT_EQ(layers.inflated().at(25, 20), kFreeOccupancy);      // 5 cells away, observed free
  EXPECT_EQ(layers.inflated().at(40, 30), kUnknownOccupancy);   // never observed
  EXPECT_EQ(layers.names(), (std::vector<std::string>{"sensed", "inflated"}));
}

TEST(MapLayers, BadUseIsAnErrorNamingTheField) {
  const GridGeometry g = geometry();
  MapLayers layers(g);
  GridGeometry other = g;
  other.width = 10;
  EXPECT_THROW(layers.set_layer("x", OccupancyGrid(other, 0)), Error);
  EXPECT_THROW(layers.set_layer("inflated", OccupancyGrid(g, 0)), Error);
  EXPECT_THROW(layers.set_inflation({"missing"}, 0.2), Error);
  layers.set_layer("a", OccupancyGrid(g, 0));
  EXPECT_THROW(layers.set_inflation({"a"}, -1.0), Error);
  EXPECT_THROW(layers.set_cell("a", {-1, 0}, 100), Error);
  EXPECT_THROW(layers.update_inflation(), Error);  // no stage yet
  GridGeometry down = g;
  down.y_down = true;
  EXPECT_THROW(MapLayers{down}, Error);
}

}  // namespace
}  // namespace starnav
