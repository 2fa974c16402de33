#pragma once
// A SLAM method run over a recording: the one driver of `starnav slam run`, `starnav slam3d` and
// `starnav bench slam`. The method is built by name from the registry (its factory composes it
// with the scan matcher it names); the recording's SensorSource (logs/robot_log_source.hpp,
// cloud/lidar_recording_source.hpp) gives odometry, IMU samples and the scans or the clouds
// (whichever the method's SlamSpace takes) to the Slam role in the recording's order; then
// finish(). What the run is judged by and the files it writes: harness/slam_report.hpp (a log:
// relations, truth, map, pose graph) and harness/slam3d_run.hpp (a LiDAR recording).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/sense/sensor_source.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav {

// The streams a SLAM run listens to (the recording sources publish on these by default).
struct SlamStreams {
  std::string scan = "lidar";
  std::string cloud = "lidar";
  std::string odometry = "odom";
  std::string imu = "imu";
};

// A SLAM method by name with its settings, and the scan matcher to compose it with.
struct SlamChoice {
  std::string method = "graph";
  std::vector<ParamSetting> settings;
  SlamMatcherChoice matcher;  // name "": the method's own
  std::string file;           // where the settings came from (their errors name it)
  std::string field = "--method";  // where the method was named
  std::uint64_t seed = 0;
};
// Errors name the method's field, a setting or the matcher's field.
std::unique_ptr<Slam> make_slam(const SlamChoice& choice);

struct SlamDriveTimes {
  double cpu_s = 0.0;   // thread CPU of the whole drive (the source's reading included)
  double wall_s = 0.0;  // wall time of the same
  double slam_wall_s = 0.0;  // wall time inside the role's calls (messages and finish): the method's own cost
};
using SlamProgress = std::function<void(std::size_t done, std::size_t total)>;

// Plays `source` into `slam` (messages on other streams are not the run's), then finish().
// `progress(done, total)` before the first reading, every 100 and after the last. Errors from the
// role name the reading's place (as its source locates them) or, from finish(), the recording.
SlamDriveTimes drive_slam(Slam& slam, SensorSource& source, const SlamStreams& streams = {}, const SlamProgress& progress = {});

}  // namespace starnav
