#pragma once
// A robot log played into a Slam through the role alone: its source's messages on a SensorBus,
// delivered reading by reading, then finish() (what harness/slam_run.hpp's driver does).
#include "starnav/logs/robot_log_source.hpp"
#include "starnav/sense/sensor_bus.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav::test {

inline void play_log(Slam& slam, const RobotLog& log) {
  SensorBus bus(SensorBus::Order::Receipt);
  bus.subscribe<OdometryMessage>("odom", [&](const OdometryMessage& m) { slam.on_odometry(m); });
  bus.subscribe<ScanMessage>("lidar", [&](const ScanMessage& m) { slam.on_scan(m); });
  RobotLogSource source(log);
  play_onto_bus(source, bus);
  slam.finish();
}

}  // namespace starnav::test
