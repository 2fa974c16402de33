#pragma once
// An indoor world from a map_server map (`world.occupancy_map` in scenarios): every occupied cell
// (occupancy at or above the map's occupied threshold; unknown cells are not walls) becomes part
// of a wall of the given height standing on z = 0, as map_server's users picture the map. Cells
// are merged into as few boxes as a greedy pass finds (runs along rows, then runs of equal
// columns stacked over rows), because the vehicle's collision test visits every static part.
#include <string>

#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sim/obstacles.hpp"

namespace starnav {

// The most boxes a map may make (a map of scattered single cells, 200 m x 200 m at 5 cm, would
// make millions): above it an Error names the map.
inline constexpr std::size_t kMaxOccupancyWallBoxes = 200'000;

// `occupied_percent`: cells with value >= it (0..100) are walls. Throws Error for a height that is
// not positive and finite, or for more than kMaxOccupancyWallBoxes boxes.
Obstacle occupancy_walls(const OccupancyGrid& grid, double occupied_percent, double wall_height_m, const std::string& name);

}  // namespace starnav
