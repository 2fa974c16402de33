#pragma once
// A SLAM method run over a recording: the one driver of `starnav slam run`, `starnav slam3d` and
// `starnav bench slam`. The method is built by name from the registry (its factory composes it
// with the scan matcher it names); a SensorBus fed by the recording's SensorSource
// (logs/robot_log_source.hpp, cloud/lidar_recording_source.hpp) delivers odometry, IMU samples and
// the scans or the clouds (whichever the method's SlamSpace takes) to the Slam role, reading by
// reading; then finish(). What the run is judged by (relations, the truth) and the files it
// writes are the experiment layer's (harness/slam_report.hpp, harness/slam3d_run.hpp).
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

// Plays `source` onto a bus, delivering after each reading, then finish(). `progress(done, total)`
// before the first reading and after each.
SlamDriveTimes drive_slam(Slam& slam, SensorSource& source, const SlamStreams& streams = {}, const SlamProgress& progress = {});

}  // namespace starnav
