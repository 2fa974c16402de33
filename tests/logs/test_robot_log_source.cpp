// A robot log played as sensor messages: per scan, in file order, the odometry at its stamp (the
// pose scan_odometry gives it, interpolated or carried by the line) just before the scan itself,
// in the laser's frame with its mount; a scan without odometry alone; the scan's beams as read; a
// consumer's error located at the scan's line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/logs/robot_log_source.hpp"

namespace starnav {
namespace {

LogScan scan_at(std::int64_t stamp_us, std::size_t line) {
  LogScan s;
  s.stamp_us = stamp_us;
  s.angle_min_rad = -1.5;
  s.angle_increment_rad = 0.01;
  s.range_min_m = 0.05;
  s.range_max_m = 20.0;
  s.ranges_m = {1.0f, 2.5f, 25.0f, 0.25f};
  s.source_index = line;
  return s;
}

// Every message of a played source, in the order given, and the readings counted after each.
std::vector<SensorMessage> played(SensorSource& source, std::vector<std::size_t>* messages_at_reading = nullptr) {
  std::vector<SensorMessage> out;
  std::size_t readings = 0;
  source.play([&](const SensorMessage& m) { out.push_back(m); },
              [&](std::size_t k) {
                readings = k;
                if (messages_at_reading) messages_at_reading->push_back(out.size());
              });
  EXPECT_EQ(readings, source.readings());
  return out;
}

TEST(RobotLogSource, OdometryAtEachScansStampJustBeforeTheScan) {
  RobotLog log;
  log.laser_in_base = Pose2(0.1, -0.02, 0.5);
  log.odometry = {{1'000'000, Pose2(0, 0, 0), 0, 0, 1}, {2'000'000, Pose2(1, 0, 0.2), 0, 0, 3}};
  log.scans = {scan_at(1'250'000, 2), scan_at(1'750'000, 4)};
  log.scans[1].odometry = Pose2(5, 6, 0.7);  // carried by its line: wins over the interpolation
  RobotLogSource source(log);
  const std::vector<SensorMessage> m = played(source);
  ASSERT_EQ(m.size(), 4u);
  const auto& o0 = std::get<OdometryMessage>(m[0]);
  const auto& s0 = std::get<ScanMessage>(m[1]);
  const auto& o1 = std::get<OdometryMessage>(m[2]);
  EXPECT_EQ(o0.header.stream, "odom");
  EXPECT_EQ(s0.header.stream, "lidar");
  EXPECT_EQ(o0.header.t_s, 1.25);
  EXPECT_EQ(s0.header.t_s, 1.25);
  // A quarter of the way from the first reading to the second.
  EXPECT_DOUBLE_EQ(o0.pose.x, 0.25);
  EXPECT_DOUBLE_EQ(o0.pose.yaw, 0.05);
  EXPECT_EQ(o1.pose.x, 5.0);
  EXPECT_EQ(o1.pose.yaw, 0.7);
  // The scan as the log holds it, in its sensor frame, with the mount at z = 0.
  EXPECT_EQ(s0.angle_min_rad, -1.5);
  EXPECT_EQ(s0.angle_increment_rad, 0.01);
  EXPECT_EQ(s0.range_max_m, 20.0);
  ASSERT_EQ(s0.ranges_m.size(), 4u);
  EXPECT_EQ(s0.ranges_m[3], 0.25);
  EXPECT_TRUE(s0.returned(0));
  EXPECT_FALSE(s0.returned(2));  // beyond range_max: no return, as the log's reading says
  EXPECT_NEAR(s0.mount.position.x(), 0.1, 1e-15);
  EXPECT_EQ(s0.mount.position.z(), 0.0);
  EXPECT_EQ(s0.mount.to_pose2().yaw, 0.5);
}

TEST(RobotLogSource, ScansInFileOrderEvenWhenStampsGoBackAndWithoutOdometryAlone) {
  RobotLog log;
  log.scans = {scan_at(3'000'000, 1), scan_at(1'000'000, 2), scan_at(3'000'000, 3)};
  log.scans[2].ranges_m = {7.0f};
  log.scans[0].odometry = Pose2(1, 1, 0);  // the others have none: no odometry in the log
  RobotLogSource source(log);
  std::vector<std::size_t> at;
  const std::vector<SensorMessage> m = played(source, &at);
  ASSERT_EQ(m.size(), 4u);
  // As received (rosbag play's order), the stamp that goes back included.
  EXPECT_EQ(std::get<OdometryMessage>(m[0]).pose.x, 1.0);
  EXPECT_EQ(std::get<ScanMessage>(m[1]).header.t_s, 3.0);
  EXPECT_EQ(std::get<ScanMessage>(m[2]).header.t_s, 1.0);  // alone: it has no odometry
  EXPECT_EQ(std::get<ScanMessage>(m[3]).ranges_m.size(), 1u);
  // Each reading counted once its messages were given.
  EXPECT_EQ(at, (std::vector<std::size_t>{2, 3, 4}));
  // Played onto a bus in time order (a simulation's), the stamp that goes back is refused; onto
  // one in receipt order (a recording's) it is delivered as received.
  SensorBus timed;
  EXPECT_THROW(play_onto_bus(source, timed), Error);
  SensorBus received(SensorBus::Order::Receipt);
  std::vector<double> scans;
  received.subscribe<ScanMessage>("lidar", [&](const ScanMessage& s) { scans.push_back(s.header.t_s); });
  std::vector<std::size_t> after;
  play_onto_bus(source, received, [&](std::size_t k) {
    after.push_back(k);
    EXPECT_EQ(received.queued(), 0u);  // each reading delivered before it is counted
  });
  EXPECT_EQ(scans, (std::vector<double>{3.0, 1.0, std::get<ScanMessage>(m[3]).header.t_s}));
  EXPECT_EQ(after, (std::vector<std::size_t>{1, 2, 3}));
}

TEST(RobotLogSource, AConsumersErrorNamesTheScansLine) {
  RobotLog log;
  log.path = "run.clf";
  log.format = "carmen";
  log.scans = {scan_at(1'000'000, 4), scan_at(2'000'000, 9)};
  RobotLogSource source(log);
  try {
    source.play(
        [&](const SensorMessage& m) {
          if (header_of(m).t_s == 2.0) throw Error("cannot place it", {}, 0, "scan");
        },
        {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "run.clf");
    EXPECT_EQ(e.line(), 9);
    EXPECT_EQ(e.field(), "scan");
  }
}

}  // namespace
}  // namespace starnav
