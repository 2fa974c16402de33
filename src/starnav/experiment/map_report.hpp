#pragma once
// What `starnav map info --json` prints of a map, as one library call (the Python bindings'
// Map.info() reads the same): file, format, size, resolution, origin, index_grid, then the cell
// counts of an occupancy grid (free, occupied, unknown) or an elevation map's observed cells and
// height range.
#include <string>

#include "starnav/io/map_file.hpp"

namespace starnav {

// `file` null in the JSON when empty; `format` the file's format when empty (a map built another
// way names how). Indented by `indent` spaces per level (-1: one line).
std::string map_info_json(const LoadedMap& map, const std::string& file, const std::string& format = {}, int indent = 2);

}  // namespace starnav
