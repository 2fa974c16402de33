#pragma once
// Named occupancy layers over one grid (after grid_map's named layers): a static map (map_server),
// the sensed map, ... and one inflation stage over them. The inflated layer holds 100 where a cell
// lies within the inflation radius of an occupied cell of any obstacle layer (the
// inflation-radius rule of distance_transform.hpp), -1 where no obstacle layer has observed the
// cell, 0 elsewhere; it is brought up to date incrementally, over the window the changes since
// the last update can affect (mask_inflation.hpp), and always equals a recomputation from scratch.
//
//   MapLayers layers(geometry);
//   layers.set_layer("static", map_server_grid);
//   layers.set_layer("sensed", OccupancyGrid(geometry, kUnknownOccupancy));
//   layers.set_inflation({"static", "sensed"}, 0.25);
//   layers.set_cell("sensed", {12, 7}, kOccupiedOccupancy);
//   const auto changed = layers.update_inflation();   // cells of "inflated" that changed
//   const OccupancyGrid& local = layers.inflated();
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/mask_inflation.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

class MapLayers {
 public:
  // Throws Error for a grid without cells or with y_down rows (layers are metric).
  explicit MapLayers(const GridGeometry& geometry);

  const GridGeometry& geometry() const { return geometry_; }
  // Adds or replaces a layer. Throws Error (field "layer") for a grid of another geometry, an
  // empty name, or the name "inflated" (the stage's own).
  void set_layer(const std::string& name, OccupancyGrid grid);
  bool has(const std::string& name) const;
  // Throws Error (field "layer") for an unknown name.
  const OccupancyGrid& layer(const std::string& name) const;
  std::vector<std::string> names() const;  // in the order added, "inflated" last once set
  // One cell of a layer; returns whether its value changed. Throws Error for an unknown layer or a
  // cell outside the grid.
  bool set_cell(const std::string& name, Cell cell, std::int8_t value);

  // The inflation stage: which layers hold obstacles, the radius (m, >= 0) and how their values
  // are classified. Recomputes the inflated layer from scratch.
  void set_inflation(std::vector<std::string> obstacle_layers, double radius_m, const OccupancyThresholds& thresholds = {});
  // Brings the inflated layer up to date with every change since the last update (set_layer of an
  // obstacle layer recomputes all of it; set_cell only the window it can affect). Returns the cells
  // whose inflated value changed, row-major.
  std::vector<Cell> update_inflation();
  const OccupancyGrid& inflated() const { return inflated_; }
  double inflation_radius_m() const { return radius_m_; }

 private:
  struct Layer {
    std::string name;
    OccupancyGrid grid;
  };
  Layer* find(const std::string& name);
  const Layer* find(const std::string& name) const;
  bool is_obstacle_layer(const std::string& name) const;
  void rebuild_masks(const CellRect& region);
  std::int8_t inflated_value(std::size_t i) const;

  GridGeometry geometry_;
  std::vector<Layer> layers_;
  std::vector<std::string> obstacle_layers_;
  OccupancyThresholds thresholds_;
  double radius_m_ = 0.0;
  bool inflation_set_ = false;
  std::vector<std::uint8_t> occupied_;  // any obstacle layer occupied
  std::vector<std::uint8_t> observed_;  // any obstacle layer not unknown
  std::vector<std::uint8_t> blocked_;   // occupied_, inflated
  OccupancyGrid inflated_;
  CellRect dirty_;                      // cells changed since the last update (empty: none)
  bool dirty_all_ = false;
  IncrementalInflation inflation_;
};

}  // namespace starnav
