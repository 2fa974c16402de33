#pragma once
// The scenario runner: a fixed-step clock that drives the robot through the scenario's command
// script and samples its sensors at their rates, recording ground truth, sensor summaries and
// events (docs/simulator.md, "Running scenarios").
//
// Step k takes the clock from t_k = k dt to t_{k+1} (times are k * dt, never accumulated):
//   1. the command at t_k from the script (zero after its end);
//   2. Vehicle::step(command, dt);
//   3. events at t_{k+1}: the vehicle's (it reports each episode once, when it starts), obstacles appearing/disappearing within
//      (t_k, t_{k+1}], bumper contact changes, command segment changes;
//   4. sensors whose next sample time is <= t_{k+1} sample the state at t_{k+1} (LiDAR scan n is
//      due at n / rate_hz, so scans fall on steps when the period is a multiple of dt);
//   5. the trajectory is recorded every `trajectory_every_n_steps` steps and at the end.
// At t = 0 the initial state is recorded; the first step() first lets the LiDAR scan at t = 0 and
// the encoders take their zero (so a feed subscribed after construction sees that scan too).
// All randomness flows from the scenario seed: Rng(seed).fork(1) for the vehicle's slip, 2 for
// the LiDAR, 3 for the IMU, 4 for the encoders.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/core/polyline.hpp"
#include "starnav/sense/bumper.hpp"
#include "starnav/sense/imu.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sense/wheel_encoders.hpp"
#include "starnav/sim/sample_feed.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {

struct TrajectorySample {
  double t_s = 0.0;
  Vec3 position = Vec3::Zero();
  Vec3 rpy = Vec3::Zero();  // roll, pitch, yaw (rad)
  BodyTwist twist;          // achieved body twist (base_link)
};

struct SimEvent {
  double t_s = 0.0;
  std::string kind;    // vehicle kinds (collision, step, slide, off_terrain), bumper, appear, disappear, command
  std::string detail;
  Vec2 where = Vec2::Zero();
};

struct LidarScanSummary {
  double t_s = 0.0;
  Vec3 sensor_position = Vec3::Zero();
  std::size_t rays = 0;
  std::size_t returns = 0;
  std::size_t dropped = 0;
  std::size_t self_filtered = 0;
  double min_range_m = 0.0;  // +inf without returns
};

struct EncoderSample {
  double t_s = 0.0;
  std::vector<std::int64_t> ticks;
};

struct SimulationMetrics {
  double duration_s = 0.0;
  std::int64_t steps = 0;
  double distance_m = 0.0;     // XY path length over every step
  double distance_3d_m = 0.0;
  TrajectorySample final_state;
  double z_min_m = 0.0, z_max_m = 0.0;
  double roll_max_abs_rad = 0.0, pitch_max_abs_rad = 0.0;
  std::int64_t collisions = 0;  // collision episodes
  std::map<std::string, std::int64_t> events_by_kind;
  bool has_reference = false;
  double deviation_mean_m = 0.0, deviation_max_m = 0.0;  // distance from the reference line over every step
  std::int64_t lidar_scans = 0, lidar_rays = 0, lidar_returns = 0;
  std::int64_t imu_samples = 0, encoder_samples = 0;
};

class Simulation {
 public:
  // Builds the world from the scenario (build_world) and places the robot at its start.
  explicit Simulation(const ScenarioSpec& spec);
  Simulation(const ScenarioSpec& spec, const WorldDescription& world);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The samples of each sensor as they are taken, at the sensor's own rate (what a real robot's
  // drivers publish): LiDAR scans per stream ("lidar" for sensors.lidar, "lidar/NAME" for
  // sensors.lidars.NAME; in that order within a step), IMU readings, cumulative encoder ticks, and
  // the bumper's state after every step (with a bumper). Subscribe before run.
  SampleFeed<LidarScan>& lidar_feed(const std::string& stream);
  // The LiDAR streams this scenario has, first LiDAR first.
  std::vector<std::string> lidar_streams() const;
  SampleFeed<ImuModel::ImuReading> imu_feed;
  SampleFeed<EncoderSample> encoder_feed;
  SampleFeed<BumperReading> bumper_feed;
  // When set, replaces the command script: called at every step with t_k and the vehicle in its
  // state at t_k; returns the body twist to apply over the step (navigation drives through it).
  std::function<BodyTwist(double t)> command_source;
  // Called after every step, the vehicle at its new state (a live viewer's feed of the pose).
  std::function<void()> on_step;

  const ScenarioSpec& spec() const { return spec_; }
  const World& world() const { return world_; }
  // The terrain the world was built from (for pictures), if any.
  const std::optional<ElevationMap>& terrain_map() const { return terrain_map_; }
  const Vehicle& vehicle() const { return *vehicle_; }
  double time() const { return static_cast<double>(step_) * spec_.dt_s; }
  std::int64_t step_count() const { return step_; }
  std::int64_t total_steps() const { return total_steps_; }
  bool finished() const { return stopped_ || step_ >= total_steps_; }
  // Ends the run now (navigation: goal reached, or no path); the current state is recorded as the
  // trajectory's last sample. May be called from a sample's subscriber or command_source.
  void stop();
  // Moves the robot to `to` now without its wheels turning (the kidnapped robot; also what the
  // scenario's teleport events do), with an event. Throws Error (field "teleport") where it cannot stand.
  void teleport(const Pose2& to);
  bool stopped() const { return stopped_; }

  void step();
  // Runs to the end; `progress(fraction)` is called about every 1% of the steps.
  void run(const std::function<void(double)>& progress = {});

  const std::vector<TrajectorySample>& trajectory() const { return trajectory_; }
  const std::vector<SimEvent>& events() const { return events_; }
  const std::vector<LidarScanSummary>& scans() const { return scans_; }
  const std::vector<ImuModel::ImuReading>& imu_readings() const { return imu_; }
  const std::vector<EncoderSample>& encoder_samples() const { return encoder_samples_; }
  SimulationMetrics metrics() const;

 private:
  void init();
  TrajectorySample sample_now() const;
  void sample_sensors(bool initial);
  void scan_lidars(double t);
  void add_event(double t, std::string kind, std::string detail, const Vec2& where);
  void track_step();

  ScenarioSpec spec_;
  World world_;
  std::optional<ElevationMap> terrain_map_;
  std::unique_ptr<Vehicle> vehicle_;
  // Every LiDAR with its stream, its feed, its next sample index and its scan's buffer (first
  // LiDAR first).
  struct LidarSlot {
    std::string stream;
    Lidar lidar;
    SampleFeed<LidarScan> feed;
    std::int64_t next = 0;
    LidarScan scan;
  };
  std::vector<LidarSlot> lidars_;
  bool first_lidar_ = false;  // lidars_[0] is sensors.lidar (its scans are summarised in lidar.csv)
  std::optional<ImuModel> imu_model_;
  std::optional<WheelEncoders> encoders_;
  std::int64_t step_ = 0;
  std::int64_t total_steps_ = 0;
  std::int64_t next_imu_ = 1, next_encoder_ = 0;  // sample indices n (time n / rate)
  double last_imu_t_ = 0.0;
  int segment_ = -1;
  std::size_t next_teleport_ = 0;
  bool started_ = false;  // the t = 0 sensor samples are taken
  bool stopped_ = false;
  bool bumper_ = false;
  std::vector<VehicleEvent> vehicle_events_;

  std::vector<TrajectorySample> trajectory_;
  std::vector<SimEvent> events_;
  std::vector<LidarScanSummary> scans_;
  std::vector<ImuModel::ImuReading> imu_;
  std::vector<EncoderSample> encoder_samples_;

  // Running metrics over every step.
  TrajectorySample last_;
  double distance_ = 0.0, distance_3d_ = 0.0, z_min_ = 0.0, z_max_ = 0.0, roll_max_ = 0.0, pitch_max_ = 0.0;
  double deviation_sum_ = 0.0, deviation_max_ = 0.0;
  std::int64_t deviation_n_ = 0;
  std::int64_t rays_ = 0, returns_ = 0;
};


// The recorder: deterministic files (fixed number formats) in `dir`:
//   trajectory.csv  t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,wz_radps
//   events.csv      t_s,kind,detail,x_m,y_m
//   metrics.json    see docs/scenarios.md
//   lidar.csv       (with a LiDAR) t_s,x_m,y_m,z_m,rays,returns,dropped,self_filtered,min_range_m
//   imu.csv         (with an IMU) t_s,yaw_rate_radps,yaw_rad
//   encoders.csv    (with encoders) t_s,ticks_0,...
// Throws Error naming the file when one cannot be written.
void write_simulation_records(const Simulation& sim, const std::string& dir);
std::string trajectory_csv(const Simulation& sim);
std::string events_csv(const Simulation& sim);
std::string metrics_json(const Simulation& sim);

// timing.json (wall-clock figures, kept apart from the deterministic records).
struct SimulationTiming {
  double wall_s = 0.0;   // the stepping loop
  double setup_s = 0.0;  // building the world and the robot
  double sim_s = 0.0;
  std::int64_t steps = 0;
  std::int64_t lidar_rays = 0;
};
void write_timing_json(const SimulationTiming& timing, const std::string& path);

}  // namespace starnav
