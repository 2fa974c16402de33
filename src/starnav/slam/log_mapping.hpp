#pragma once
// Maps a robot log with known poses (`starnav map build`): the poses the log holds, its odometry,
// its ground truth, or a trajectory file (t_s,x_m,y_m,yaw_rad per scan, matched by stamp to the
// microsecond), each scan drawn from its laser's pose into an OccupancyMapper.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "starnav/logs/robot_log.hpp"
#include "starnav/slam/occupancy_mapping.hpp"

namespace starnav {

// Where a scan's pose comes from.
enum class LogPoseSource : std::uint8_t {
  Log,       // the laser pose its line carries (FLASER, ROBOTLASER1), else as Odometry
  Odometry,  // odometry interpolated at the scan's stamp (or the line's own odometry pose), with the mount
  Truth,     // ground truth (TRUEPOS) interpolated at the scan's stamp, with the mount
};

// One base_link pose per scan (map frame).
struct TrajectoryPose {
  std::int64_t stamp_us = 0;
  Pose2 pose;
};

// trajectory.csv: header t_s,x_m,y_m,yaw_rad, t with 6 decimals as the log prints it. Throws
// Error naming the file, line and column for anything else.
std::vector<TrajectoryPose> read_trajectory_csv(const std::string& path);
std::string trajectory_csv(const std::vector<TrajectoryPose>& poses);

struct LogMapResult {
  OccupancyGrid grid;
  std::size_t scans_mapped = 0;
  std::size_t scans_without_pose = 0;  // a trajectory without the scan's stamp; no odometry or truth
  std::vector<TrajectoryPose> base_poses;  // of the mapped scans
};

// One base pose per scan from odometry alone: the odometry pose the scan's line carries, else the
// odometry interpolated at its stamp; scans without either are left out. The odometry-only
// baseline of the SLAM benchmark.
std::vector<TrajectoryPose> odometry_trajectory(const RobotLog& log);

// The log's ground truth (TRUEPOS) as time-sorted readings, for odometry_at.
std::vector<LogOdometry> truth_readings(const RobotLog& log);

// The laser's pose for `scan` from a base pose: base * mount (the log's laser_in_base, else 0).
Pose2 laser_pose(const RobotLog& log, const Pose2& base);

// Called after each mapped scan with its base and laser poses and the cells whose class it
// changed (OccupancyMapper::last_changes: a viewer's map updates). Given, it turns tracking on.
using MapScanObserver =
    std::function<void(const LogScan& scan, const Pose2& base, const Pose2& sensor, const std::vector<MapCellChange>& changes)>;

LogMapResult map_log(const RobotLog& log, LogPoseSource source, const OccupancyMappingParams& params,
                     const MapScanObserver& observer = {});
LogMapResult map_log(const RobotLog& log, const std::vector<TrajectoryPose>& trajectory, const OccupancyMappingParams& params,
                     const MapScanObserver& observer = {});

}  // namespace starnav
