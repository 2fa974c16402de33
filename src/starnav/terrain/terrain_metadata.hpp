#pragma once
// The metadata of a generated terrain (the sidecar FILE.terrain.json of `starnav terrain
// generate`, docs/terrain.md): the generator and its settings, the map's size and height range and
// the pits and mounds, so that a terrain file says how to make it again.
#include <string>
#include <vector>

#include "starnav/terrain/terrain_generator.hpp"

namespace starnav {

// The JSON document (indented, one trailing newline): kind "hills", seed, amplitude and the hills'
// settings, then the map's size, features and height range, then `file` and `format`.
std::string hills_metadata(const HillsOptions& h, const ElevationMap& map, const std::string& file,
                           const std::string& format);
// The same for a road: kind "road", seed, class, method, the spectrum and its band, then the map's.
std::string road_metadata(const RoadOptions& r, const RoadTerrain& t, const std::string& file, const std::string& format);

}  // namespace starnav
