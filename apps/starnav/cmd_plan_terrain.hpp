#pragma once
// starnav plan on an elevation map (Liu et al. 2024, docs/terrain.md): called by cmd_plan.cpp when --map
// is an elevation map. See cmd_plan_terrain.cpp.
#include <string>
#include <vector>

#include "commands.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/plan/plan_result.hpp"
#include "terrain_cli.hpp"

namespace starnav::cli {

struct TerrainPlanRequest {
  std::string map_path;
  const ElevationMap* map = nullptr;
  Cell start{};  // cells of the map (outside it: a result, not an error)
  Cell goal{};
  std::string planner = "ia";  // oa, aoea, ia
  bool json = false;
  std::string out;  // CSV of the path
  std::string svg;
  std::vector<ParamSetting> settings;  // of terrain_plan_params(), each naming its flag
};

// Plans, prints the result (text or --json) and writes --out / --svg; exit code 0 found, 1 no path.
void run_plan_terrain(const TerrainPlanRequest& request, Context& ctx);

}  // namespace starnav::cli
