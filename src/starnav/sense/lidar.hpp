#pragma once
// Virtual 2D and 3D LiDAR (docs/papers/li2019.md).
//
// Beams. Beam i (i = 0 ... beams-1) points at azimuth +scan_angle/2 - i*delta in the sensor
// frame (x forward, y left, z up): the sweep starts at the left-most beam and proceeds right.
// delta = scan_angle / beams for a full 360 deg scan (no duplicate beam at +-180 deg) and
// scan_angle / (beams - 1) otherwise, so the first and last beams lie on the edges of the field
// of view. Line j has elevation elevations[j], top line first (phi_j = max_line - j*delta_line).
// Ray (j, i) has index j*beams + i and the unit direction (cos phi cos theta, cos phi sin theta,
// sin phi); a return at range L is the point L times that direction.
//
// Returns. A ray returns the distance to the first surface hit when it lies in
// [range_min, range_max], otherwise "no return" (+inf). With noise, each ray draws, in this
// order and whether or not it hit anything, a dropout uniform (when dropout > 0) and a standard
// normal (when noise_sigma > 0) from the LiDAR's own Rng: a return is dropped with probability
// `dropout`, and range noise N(0, noise_sigma^2) is added to the others (clamped at 0). Returns
// whose sensor-frame point falls inside the self-filter box are dropped too (the robot's own
// body; docs/simulator.md).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/sense/ray_caster.hpp"
#include "starnav/sense/sensor_messages.hpp"

namespace starnav {

// An axis-aligned box in the sensor frame (the paper's robotSize1/robotSize2 corners).
struct SelfFilterBox {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  bool contains(const Vec3& p_sensor) const {
    return p_sensor.x() >= min.x() && p_sensor.x() <= max.x() && p_sensor.y() >= min.y() && p_sensor.y() <= max.y() &&
           p_sensor.z() >= min.z() && p_sensor.z() <= max.z();
  }
  // The sensor-frame bounds of a body box given in base_link (corners body_min, body_max),
  // grown by `margin` on every side; `mount` is the sensor's pose in base_link.
  static SelfFilterBox around_body(const Vec3& body_min, const Vec3& body_max, const Pose3& mount, double margin);
};

// The most rays (beams x lines) one scan may have: 16 times the densest production sensors
// (128 lines x 2048 beams); a scan keeps about 60 bytes per ray, and ray indices are 32-bit.
inline constexpr std::size_t kMaxLidarRaysPerScan = std::size_t{1} << 22;

struct LidarConfig {
  std::string model = "custom";
  int beams = 360;                           // horizontal beams per line
  double scan_angle = 2.0 * kPi;             // horizontal field of view (rad)
  std::vector<double> elevations{0.0};       // per line, top first (rad); one line = 2D LiDAR
  double range_min = 0.15;                   // m
  double range_max = 12.0;                   // m
  double rate_hz = 10.0;                     // scans per second
  Pose3 mount;                               // sensor frame in base_link
  double noise_sigma = 0.0;                  // m, Gaussian range noise
  double dropout = 0.0;                      // probability that a return is lost
  std::optional<SelfFilterBox> self_filter;  // sensor frame

  int lines() const { return static_cast<int>(elevations.size()); }
  std::size_t ray_count() const { return static_cast<std::size_t>(beams) * elevations.size(); }
  bool full_circle() const;                  // scan_angle is 360 deg (to 1e-9 rad)
  double delta() const;                      // beam spacing (Li et al. 2019; docs/simulator.md)
  double azimuth(int beam) const { return 0.5 * scan_angle - beam * delta(); }
  double period() const { return 1.0 / rate_hz; }
  // Sets `lines` evenly spaced elevations from max_line down by delta_line.
  void set_lines(int lines, double max_line, double delta_line);
  // Throws Error naming the field: beams < 1 (< 2 for a partial scan), scan_angle outside
  // (0, 2 pi], no lines, elevations outside [-pi/2, pi/2], ranges not 0 <= min < max, rate <= 0,
  // sigma < 0, dropout outside [0, 1], an empty or inverted self-filter box; "beams" when beams x
  // lines exceeds kMaxLidarRaysPerScan.
  void validate() const;
};

// Presets from the manufacturers' data sheets (docs/simulator.md, the LiDAR):
//   2D: hokuyo_utm30lx, sick_lms151, generic_360
//   3D: ibeo_lux4, ibeo_lux8, vlp16, hdl32e, hdl64e (horizontal_resolution sets their beams;
//       default 0.2 deg, as the spec)
// Throws Error (field "model") for an unknown name.
LidarConfig lidar_preset(std::string_view name, double horizontal_resolution = deg_to_rad(0.2));
std::vector<std::string> lidar_preset_names();

struct LidarScan {
  double time = 0.0;
  int lines = 0;
  int beams = 0;
  Pose3 sensor_pose;                    // the sensor frame in the world at scan time
  std::vector<double> azimuths;         // per beam (rad)
  std::vector<double> elevations;       // per line (rad)
  std::vector<double> ranges;           // lines x beams, row-major by line; +inf = no return
  std::vector<Vec3> points_sensor;      // one per return, in ray order
  std::vector<Vec3> points_world;       // the same points in the world frame
  std::vector<std::uint32_t> point_ray; // ray index (line * beams + beam) of each point
  std::size_t dropped = 0;              // returns lost to dropout
  std::size_t self_filtered = 0;        // returns inside the self-filter box

  double range(int line, int beam) const {
    return ranges[static_cast<std::size_t>(line) * static_cast<std::size_t>(beams) + static_cast<std::size_t>(beam)];
  }
};

class Lidar {
 public:
  // Validates the configuration (throws Error). The Rng is the sensor's own noise stream.
  explicit Lidar(LidarConfig config, Rng rng = Rng(0));

  const LidarConfig& config() const { return config_; }
  // Unit ray directions in the sensor frame, in ray order.
  const std::vector<Vec3>& directions() const { return dirs_; }

  // One scan at `time` with the robot (base_link) at `robot_pose` in the world. All rays are cast
  // at the same instant (no motion distortion).
  LidarScan scan(const RayCaster& world, const Pose3& robot_pose, double time);
  void scan(const RayCaster& world, const Pose3& robot_pose, double time, LidarScan& out);

 private:
  LidarConfig config_;
  Rng rng_;
  std::vector<Vec3> dirs_;
  std::vector<Vec3> world_dirs_;
  std::vector<RayHit> hits_;
};

// A planar scan (one line) as its driver publishes it on `stream`: ranges by azimuth in the sensor
// frame, the sensor's mount and valid range; no pose (the simulator's truth stays with it).
ScanMessage planar_scan_message(const LidarScan& scan, const LidarConfig& config, const std::string& stream);

}  // namespace starnav
