#include "starnav/experiment/limits_docs.hpp"

#include <cstdint>
#include <sstream>
#include <vector>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/io/yaml_document.hpp"
#include "starnav/logs/decompress.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/map/clearance_window.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sim/occupancy_world.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/slam/correlative_scan_matcher.hpp"
#include "starnav/slam/graph_slam.hpp"
#include "starnav/slam/occupancy_mapping.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

namespace {

struct Limit {
  std::string what;
  std::string bound;
  std::string applies_to;  // flags and YAML fields
  std::string why;
};

std::string count(double v) { return format_number(v); }
std::string bytes(double v) { return format_number(v / (1024.0 * 1024.0 * 1024.0)) + " GiB"; }
std::string bytes_mib(double v) { return format_number(v / (1024.0 * 1024.0)) + " MiB"; }

// The navigation components' parameters of `type`, as a scenario writes them ("`navigation.keepout.zones`").
std::string navigation_params_of_type(ParamType type) {
  std::string s;
  for (const ComponentInfo& c : all_components()) {
    if (c.role == Role::Slam || c.role == Role::ScanMatcher || c.role == Role::ScanMatcher3d) continue;
    for (const ParamSpec& p : c.params)
      if (p.type == type)
        s.append(s.empty() ? "" : ", ").append("`").append(c.role == Role::Localizer ? "localization." : "navigation.")
            .append(c.section).append(".").append(p.key).append("`");
  }
  return s.empty() ? "none yet" : s;
}

}  // namespace

std::string limits_markdown() {
  const std::vector<std::pair<std::string, std::vector<Limit>>> sections = {
      {"Input files",
       {
           {"any file read whole", bytes(static_cast<double>(kMaxInputFileBytes)), "every FILE argument",
            "checked from the file's size before reading; only regular files (no devices, FIFOs or sockets)"},
           {"a robot log", bytes(static_cast<double>(kMaxLogFileBytes)), "`log`, `slam`, `localize`, `map build` LOG, `slam3d` bags",
            "the size of the file"},
           {"readings of one laser scan", count(static_cast<double>(kMaxScanBeams)),
            "CARMEN lines, text extracts, ROS bags' LaserScan messages", "checked from the count before the readings are stored"},
           {"decompressed data", bytes(static_cast<double>(kMaxDecompressedBytes)), ".gz, bzip2 and LZ4 inputs, the pixels of a PNG map image",
            "a small archive that inflates without bound is refused while inflating; a PNG from its IHDR header before its pixels are read"},
           {"parsed records of a robot log",
            "its size (compressed parts counted decompressed), at most " + bytes(static_cast<double>(kMaxLogFileBytes)) + ", + " +
                bytes_mib(static_cast<double>(kLogRecordSlackBytes)),
            "CARMEN logs, text extracts, ROS 1 bags, MCAP and rosbag2 SQLite3 recordings (also `slam3d`'s bag index): scans with "
            "their readings, odometry, ground truth, IMU, transforms",
            "judged from the lines or each topic's message count before any record is stored, then charged as records are stored; "
            "a log for `slam`, `localize` or `map build` without any scan is refused there"},
           {"a file's head", "its format's header, in the first " + std::to_string(kTextHeadBytes / 1024) + " KiB",
            "MovingAI maps and scenarios, ESRI ASCII grids, PNG and PGM images, PCD, PLY and KITTI .bin clouds, elevation CSV, "
            "robot logs; the line formats (trajectory CSV, relations, pose files, frames.csv, KITTI times and calibration, "
            "query files): their whole lines there, no NUL byte, a first line that ends there",
            "read and checked before the rest of the file: a file of another kind, or larger than its header says (a cloud's "
            "points: binary exactly, text at most 64 characters a value, 1 MiB to spare), costs its first bytes"},
           {"cells of a grid", count(static_cast<double>(kMaxGridCells)), "every map format's width x height",
            "cell indices are 32-bit; checked from the header before the body is read"},
           {"points of a cloud file", count(static_cast<double>(kMaxCloudPoints)), "PCD, PLY and KITTI .bin clouds, PointCloud2 messages of bags",
            "checked from the header (or the file size) before reading"},
           {"a position read from a file", format_number(kMaxCoordinateM) + " m from the origin",
            "poses of robot logs (CARMEN, text extracts, ROS 1 and ROS 2 bags' odometry, transforms and truth), trajectory and pose files, "
            "frames.csv",
            "beyond any site; a farther value is corrupt (grids and pictures index what lies within it)"},
           {"a YAML document", bytes_mib(static_cast<double>(kMaxYamlBytes)) + " and " + count(static_cast<double>(kMaxYamlNodes)) + " nodes",
            "scenarios, `--set` values, map_server and elevation YAML, RAW sidecars, slam3d's sensor.yaml",
            "nodes counted with their aliases expanded, in one pass over the text before the document is built"},
           {"points of a polygons parameter", count(static_cast<double>(kMaxParamPolygonVertices)),
            navigation_params_of_type(ParamType::Polygons) + " (YAML or `--set`)", "counted while the text is read, before a point is stored"},
           {"numbers of a list-of-numbers parameter", count(static_cast<double>(kMaxParamListNumbers)),
            navigation_params_of_type(ParamType::Reals) + " (YAML or `--set`)", "counted while the text is read, before a number is stored"},
           {"more LiDARs", count(static_cast<double>(kMaxOtherLidars)), "`sensors.lidars`", "each scans every period it is due"},
       }},
      {"Simulation",
       {
           {"steps of a run", count(kMaxSimulationSteps), "`sim.duration_s` / `sim.dt_s`, `--duration`",
            "28 simulated hours at the default 0.01 s"},
           {"LiDAR rays of a run", count(kMaxSimulationLidarRays),
            "scans (`sim.duration_s` x `sensors.lidar.rate_hz`) x rays per scan", "about half an hour of ray casting"},
           {"rays of one scan", count(static_cast<double>(kMaxLidarRaysPerScan)), "`sensors.lidar` beams x lines", ""},
           {"sensor rate", "1 / `sim.dt_s`", "`sensors.*.rate_hz`",
            "a sensor samples at most once per step; a faster rate would repeat the same state"},
           {"terrain cells", count(static_cast<double>(kMaxTerrainCells)), "`world.terrain` size_m / resolution_m", ""},
           {"gravel pieces", count(static_cast<double>(kMaxGravelPieces)), "`world.obstacles` gravel fields", ""},
           {"cells of a navigation map", count(static_cast<double>(kMaxNavigationMapCells)),
            "the map's extent (`navigation.map.extent`: the world's, or the paper's) / `navigation.map.resolution_m`",
            "about " + std::to_string(kNavigationMapCellBytes) +
                " bytes a cell (layers, expansion, distance field, views, the planner's search); the distance field's windows "
                "(`navigation.map.clearance_range_m`, `barrier_distance_m` around a change) are clipped to the map"},
           {"clearance window cells", count(kMaxClearanceWindowCells),
            "a local window with its padding / `navigation.map.resolution_m`, squared: DWA's (`navigation.dwa.window_m`, or what "
            "its rollouts reach, padded by the footprint and `inflation_radius_m`), a recovery's look ahead (the footprint and "
            "0.5 s of its motion)",
            "rebuilt at every command, about 40 bytes a cell; DWA's is checked when the controller is made, every window before "
            "it is built"},
           {"wall boxes of an occupancy world", count(static_cast<double>(kMaxOccupancyWallBoxes)), "`world.occupancy_map`",
            "occupied runs merged into boxes"},
       }},
      {"Terrain generation",
       {
           {"planned operations", count(kMaxTerrainGenerationOperations),
            "road directional: cells x intervals x directions; road paper: cells x intervals + the blur; hills: hills x "
            "footprint + the roughness blur",
            "estimated before any work, about a minute on one core"},
           {"road intervals", "1.." + count(kMaxRoadIntervals), "`--intervals`, `generate.intervals`", ""},
           {"road directions", "1.." + count(kMaxRoadDirections), "`--directions`, `generate.directions` (method directional only)", ""},
           {"road blur sigma", "the map's larger side in cells", "`--blur-cells`, `generate.blur_sigma_cells` (method paper only)",
            "a wider blur is the map's mean; the kernel is clipped to the map"},
       }},
      {"Mapping, SLAM and pictures",
       {
           {"cells of a map built from scans", count(static_cast<double>(kMaxOccupancyMapCells)),
            "`slam`, `map build`; one scan's beams without a return (`no_return_clear_m`, cut to `max_range_m`, all round) / "
            "`resolution_m`, squared",
            "the map grows with the scans' extent, " + std::to_string(kOccupancyMapperCellBytes) +
                " bytes a cell while it is built (twice that while it grows); the parameters are checked before any cell exists"},
           {"cells of a likelihood field", count(static_cast<double>(kMaxCorrelativeFieldCells)),
            "the correlative matcher's: one scan all round (`local.max_range_m`, `loop_max_range_m`, plus the window and 3 "
            "sigma) / `local.matcher.resolution_m`, squared",
            "about 50 bytes a cell while built; checked when graph SLAM is made, and every field before it is built"},
           {"entries of a correlative search", count(static_cast<double>(kMaxCorrelativeSearchEntries)),
            "angles (the window's yaw in steps that move the farthest point one cell) x blocks of 2^depth translations "
            "(`window_linear_m` / `resolution_m`), squared; and angles x the scan's points",
            "24 and 8 bytes each; the local, loop and wide searches are checked when graph SLAM is made, every search before "
            "its tables are built"},
           {"submap fields kept built", bytes(static_cast<double>(kMaxFieldCacheBytes)), "graph SLAM's `field_cache`",
            "older fields beyond it are built again when searched (the same field)"},
           {"picture side", "below " + count(viz::kMaxPictureSidePixels) + " pixels", "every SVG and PNG", ""},
           {"PNG pixels", count(viz::kMaxPicturePixels), "every PNG picture", ""},
       }},
      {"Benchmarks",
       {
           {"repeats of one problem", "1.." + count(kMaxRepeats), "`bench movingai --repeat`, `bench ablation --repeat`", ""},
           {"random queries", "1.." + count(static_cast<double>(kMaxRandomQueries)), "`bench ablation --random`", ""},
           {"seeds of a sweep", "1.." + count(static_cast<double>(kMaxSeeds)), "`bench nav --seeds`", ""},
       }},
  };
  std::ostringstream out;
  out << "# Limits\n\n"
      << "<!-- Generated by `starnav limits --markdown` from the constants the code checks; a test keeps it current. -->\n\n"
      << "Every number starnav reads is bounded by what it costs, and the same bound holds on the command line and in "
         "YAML. Above a bound a command stops before any work with exit 2 and one line naming the flag or field. "
         "Numbers are decimal only (no hex, no octal; counts and seeds take no sign).\n";
  for (const auto& [title, limits] : sections) {
    out << "\n## " << title << "\n\n| limit | bound | applies to | why |\n|---|---|---|---|\n";
    for (const Limit& l : limits) out << "| " << l.what << " | " << l.bound << " | " << l.applies_to << " | " << l.why << " |\n";
  }
  return out.str();
}

}  // namespace starnav
