#pragma once
// The localization chain of a simulated run (scenario section `localization`): wheel odometry
// from the encoders, optionally fused with the IMU by the EKF (`odometry: ekf`), feeding the
// localizer the run reads its pose from (ground_truth, ekf, amcl, ...), which also gets the IMU and
// the scans. It subscribes to the simulation's sensor feeds as an estimator, publishes their
// samples as sensor messages on a SensorBus, to which its parts are subscribed as on a robot (a
// recording drives the same roles from the same messages: starnav localize, slam run), and records
// the estimate beside the truth at every odometry message and every scan (estimate.csv).
//
//   Simulation sim(spec);
//   LocalizationChain chain(sim, localization_config(spec));
//   sim.run();
//   write_text_file("estimate.csv", estimate_csv(chain.records()), "--out");
#include <memory>
#include <span>
#include <optional>
#include <string>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/estimate/localizer.hpp"
#include "starnav/estimate/wheel_odometry.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sense/sensor_bus.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

// The chain's choices: the odometry source (wheel: from the encoders, the default when the robot
// has them; ekf: wheel odometry fused with the IMU; none), the odometry filter's settings (section
// `ekf` when odometry is ekf) and the localizer with its settings.
struct LocalizationConfig {
  std::string odometry = "none";  // wheel or none (a filter below runs on the wheel odometry)
  ComponentChoice localizer{"ground_truth", {}, "localization.localizer", 0, {}};
  // `odometry: NAME`, a localizer with the filters_odometry capability: the wheel odometry filtered
  // with the IMU becomes the odometry the localizer reads.
  std::optional<ComponentChoice> odometry_filter;
  std::string map_file;                       // the localizer's known map (map_server YAML), if any
};
// Errors name the scenario file, line and field.
LocalizationConfig localization_config(const ScenarioSpec& spec);

// What a scenario tells its localizers: start, seed, file, the robot (pointing into `spec`, which
// must outlive the context) and the 2D LiDAR's mount and ranges; no map (the chain loads it).
LocalizerContext localizer_context(const ScenarioSpec& spec);

// The streams of a simulated robot's proprioceptive messages.
inline const std::string kEncoderStream = "encoders";
inline const std::string kImuStream = "imu";
inline const std::string kOdometryStream = "odom";
inline const std::string kFilteredOdometryStream = "odom/filtered";

// One row of estimate.csv.
struct EstimateRecord {
  double t_s = 0.0;
  Pose2 truth;
  PoseEstimate estimate;
  bool scan = false;  // recorded after a scan (else after an odometry sample)
};

class LocalizationChain {
 public:
  // Builds the odometry, the filter and the localizer and subscribes them to the simulation's
  // encoders, IMU and planar LiDARs as estimators (SampleStage::Estimate: whatever navigates or
  // records sees a sample after them, whenever it subscribed). `sim` must outlive the chain and
  // the chain the run. Throws Error naming the scenario file and field.
  LocalizationChain(Simulation& sim, const LocalizationConfig& config);
  ~LocalizationChain();
  LocalizationChain(const LocalizationChain&) = delete;
  LocalizationChain& operator=(const LocalizationChain&) = delete;

  // The localizer's pose at time t (it sees the truth first: simulation only).
  Pose2 pose(double t_s);
  // Another localizer fed exactly what the chain's own is fed (to compare localizers on one run:
  // the same noise for all); its estimates are recorded as records(index). Returns the index (1..).
  std::size_t add_localizer(const std::string& name, std::span<const ParamSetting> settings);
  std::size_t localizers() const { return localizers_.size(); }
  const Localizer& localizer(std::size_t index = 0) const { return *localizers_.at(index); }
  const LocalizationConfig& config() const { return config_; }
  // Wheel odometry (odometry: wheel or ekf), else null.
  const WheelOdometry* odometry() const { return odometry_.get(); }
  const std::vector<EstimateRecord>& records(std::size_t index = 0) const { return records_.at(index); }
  // The known map (when the localizer needs one), else null.
  const OccupancyGrid* map() const { return map_.get(); }
  // The bus the chain's parts are subscribed to: the simulation's samples as sensor messages on
  // kEncoderStream, kImuStream and the LiDARs' streams, the wheel odometry on kOdometryStream and
  // the filtered one on kFilteredOdometryStream. Another consumer may subscribe (it is called after
  // the chain's parts for the same message).
  SensorBus& bus() { return bus_; }
  // What the chain's localizers are built from (its map included).
  LocalizerContext context() const;

 private:
  void record(double t_s, bool scan);

  Simulation* sim_;
  LocalizationConfig config_;
  std::unique_ptr<OccupancyGrid> map_;
  OccupancyThresholds thresholds_;
  std::unique_ptr<Localizer> filter_;  // odometry: ekf
  std::vector<std::unique_ptr<Localizer>> localizers_;
  std::unique_ptr<RobotModel> odometry_model_;
  std::unique_ptr<WheelOdometry> odometry_;
  SensorBus bus_;
  OdometryMessage last_odometry_;
  std::vector<std::vector<EstimateRecord>> records_;
};

// t_s,source,true_x_m,true_y_m,true_yaw_rad,x_m,y_m,yaw_rad,cov_xx,cov_xy,cov_yy,cov_yawyaw,particles,updates,converged
std::string estimate_csv(const std::vector<EstimateRecord>& records);

}  // namespace starnav
