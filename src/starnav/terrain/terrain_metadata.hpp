#pragma once
// The metadata of a generated terrain (the sidecar FILE.terrain.json of `starnav terrain
// generate`, docs/terrain.md): the generator and its settings, the map's size and height range and
// the pits and mounds, so that a terrain file says how to make it again.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "starnav/terrain/terrain_generator.hpp"

namespace starnav {

// kind "hills", seed, amplitude and the hills' settings, then the map's.
nlohmann::ordered_json hills_metadata(const HillsOptions& h, const ElevationMap& map);
// kind "road", seed, class, method, the spectrum and its band, then the map's.
nlohmann::ordered_json road_metadata(const RoadOptions& r, const RoadTerrain& t);

}  // namespace starnav
