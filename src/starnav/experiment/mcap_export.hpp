#pragma once
// `starnav export mcap RUN_FOLDER OUT.mcap`: a run record (docs/run-records.md: simulation,
// navigation, SLAM, localization) as an MCAP file that Foxglove opens and plays over the run's clock
// (docs/ros2.md), zstd-compressed chunks with a summary and message indexes.
//
// Foxglove's schemas, JSON-encoded (schema encoding jsonschema; the schemas are Foxglove's own,
// mcap_export_schemas.inc):
//   /world        foxglove.SceneUpdate     the obstacles (boxes, cylinders, spheres, prisms as triangles)
//                                          and the robot's body in base_link; moving obstacles again at
//                                          every step
//   /terrain      foxglove.Grid            the elevation samples (FLOAT32 "height", NaN unobserved)
//   /map          foxglove.Grid            the occupancy (INT8 "occupancy", -1 unknown, 0..100) at the
//                                          start (world.json's nav_map) and at the end (map.yaml)
//   /tf           foxglove.FrameTransform  map -> base_link, from trajectory.csv (at most 50 a second)
//   /trajectory   foxglove.PosesInFrame    the whole trajectory, once at the start
//   /hits         foxglove.PointCloud      each step's LiDAR hits (map frame)
//   /scan         foxglove.LaserScan       the same hits as ranges in base_link, binned to 1 degree
//                                          from -180 degrees (0: no hit in that degree)
//   /plan         foxglove.PosesInFrame    each new plan
//   /particles    foxglove.PosesInFrame    the particle set, /estimate and /reference the estimate and
//                                          the reference pose where the run has them
// With `ros2`, ROS 2 messages instead (CDR, ros2msg schemas of ROS 2 Jazzy), for replaying into a
// ROS 2 stack: /map nav_msgs/msg/OccupancyGrid, /tf tf2_msgs/msg/TFMessage (map -> base_link),
// /scan sensor_msgs/msg/LaserScan (binned as above; +inf where no hit), /trajectory and /plan
// nav_msgs/msg/Path. The world's solids have no ROS 2 message and are left out.
// Times: the run's clock (a log's own stamps) in nanoseconds; a negative time is written as 0.
#include <cstddef>
#include <map>
#include <string>

namespace starnav {

struct McapExportOptions {
  bool ros2 = false;
};

struct McapExportSummary {
  std::size_t messages = 0;
  std::map<std::string, std::size_t> per_topic;
  double first_s = 0.0, last_s = 0.0;
};

// Reads the run folder (Error naming the file and field for anything it cannot read) and writes
// `out_path`.
McapExportSummary export_run_mcap(const std::string& run_dir, const std::string& out_path, const McapExportOptions& options = {});

}  // namespace starnav
