#pragma once
// ROS map_server maps: YAML + PGM/PNG, trinary, scale and raw modes, negate, thresholds, origin
// with yaw; the occupancy values are those map_server (ROS 2 nav2_map_server) gives.
#include <string>
#include <string_view>

#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

enum class RosMapMode { Trinary, Scale, Raw };

struct RosMapMetadata {
  std::string image;  // as written in the YAML (relative to the YAML's folder unless absolute)
  double resolution = 0.05;
  Pose2 origin;
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  RosMapMode mode = RosMapMode::Trinary;
};

// Parses the YAML text; `source` names the file in errors. Checks every required key and value.
RosMapMetadata parse_ros_map_yaml(std::string_view yaml_text, const std::string& source);

// Loads YAML + image. `metadata_out`, when given, receives the parsed metadata.
OccupancyGrid read_ros_map(const std::string& yaml_path, RosMapMetadata* metadata_out = nullptr);

// Writes YAML + image as map_saver does: trinary PGM (0 occupied -> 0, free -> 254,
// unknown -> 205) unless mode is Scale or Raw. The image file name is taken from
// metadata.image when set, else the YAML name with .pgm.
void write_ros_map(const OccupancyGrid& grid, const std::string& yaml_path, RosMapMetadata metadata = {});

}  // namespace starnav
