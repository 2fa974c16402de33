#pragma once
// What a real robot's logger records, from a simulation: each scan of a 2D LiDAR in its sensor
// frame (beams in increasing angle, no-returns at range_max), the wheel odometry integrated from
// the encoders (their slip included) at the encoder rate, the true pose at each scan, and the
// LiDAR's mount; `starnav sim` writes it as OUT/log.clf (a CARMEN log: ROBOTLASER1 or FLASER,
// ODOM, TRUEPOS; logs/carmen_log.hpp), which `starnav slam run` and `starnav map build` read.
// Stamps are the simulation times in microseconds.
#include <memory>

#include "starnav/logs/robot_log.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

class RobotLogRecorder {
 public:
  // True when the scenario can be recorded: a one-line (2D) LiDAR and wheel encoders.
  static bool can_record(const ScenarioSpec& spec);
  // Subscribes to the first LiDAR's scans (a recorder) and the encoders (their odometry). `sim`
  // must outlive the subscriptions; the recorder must outlive the run. Throws Error when !can_record.
  explicit RobotLogRecorder(Simulation& sim);
  const RobotLog& log() const { return *log_; }

 private:
  std::shared_ptr<RobotLog> log_;
};

}  // namespace starnav
