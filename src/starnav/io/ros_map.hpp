#pragma once
// ROS map_server maps: YAML + PGM/PNG, trinary, scale and raw modes, negate, thresholds, origin
// with yaw; the occupancy values are those map_server (ROS 2 nav2_map_server) gives.
#include <string>
#include <string_view>

#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

struct RasterImage;

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

// The image path a YAML's `image` names: absolute as is, otherwise relative to the YAML's folder.
std::string ros_map_image_path(const std::string& yaml_path, const std::string& image);

// Occupancy from decoded image samples exactly as nav2_map_server's loadMapFromFile computes it
// (GraphicsMagick Q16 quanta, channel average, alpha averaged in trinary mode only, scale mode
// unknown where not opaque, raw mode ignores negate); image row 0 becomes iy = height - 1.
// `source` names the image in errors.
OccupancyGrid ros_map_from_image(const RasterImage& image, const RosMapMetadata& metadata, const std::string& source);

// The 8-bit image map_saver writes for `grid` (1 channel; 4 channels RGBA for scale mode).
// With metadata.negate (not map_saver's behaviour, it always writes negate 0) grey levels are
// inverted so that reading with negate gives the same cells; raw mode ignores negate.
RasterImage ros_map_to_image(const OccupancyGrid& grid, const RosMapMetadata& metadata);

// Writes YAML + image as map_saver does: trinary PGM (0 occupied -> 0, free -> 254,
// unknown -> 205) unless mode is Scale or Raw. The image file name is taken from
// metadata.image when set, else the YAML name with .pgm (.png for scale mode, which needs alpha).
// Resolution and origin come from the grid (written in full precision); the thresholds, mode and
// negate from `metadata`.
void write_ros_map(const OccupancyGrid& grid, const std::string& yaml_path, RosMapMetadata metadata = {});

}  // namespace starnav
