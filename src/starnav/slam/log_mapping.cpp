#include "starnav/slam/log_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/text_lines.hpp"

namespace starnav {

namespace {

LogMapResult map_with(const RobotLog& log, const OccupancyMappingParams& params,
                      const std::function<std::optional<Pose2>(std::size_t, bool& sensor_pose)>& pose_of,
                      const MapScanObserver& observer) {
  OccupancyMapper mapper(params);
  mapper.track_changes(static_cast<bool>(observer));
  LogMapResult r;
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    const LogScan& scan = log.scans[k];
    bool is_sensor_pose = false;
    const std::optional<Pose2> p = pose_of(k, is_sensor_pose);
    if (!p) {
      ++r.scans_without_pose;
      continue;
    }
    const Pose2 sensor = is_sensor_pose ? *p : laser_pose(log, *p);
    const Pose2 base = is_sensor_pose ? sensor.compose(log.laser_in_base.value_or(Pose2()).inverse()) : *p;
    try {
      mapper.add_scan(sensor, scan);
    } catch (const Error& e) {
      throw error_at_scan(log, scan, e);
    }
    if (observer) observer(scan, base, sensor, mapper.last_changes());
    r.base_poses.push_back({scan.stamp_us, base});
    ++r.scans_mapped;
  }
  r.grid = mapper.grid();
  return r;
}

}  // namespace

std::vector<LogOdometry> truth_readings(const RobotLog& log) {
  std::vector<LogOdometry> out;
  for (const LogTruePose& t : log.truth) out.push_back({t.stamp_us, t.pose, 0.0, 0.0});
  return sort_by_time(std::move(out));
}

Pose2 laser_pose(const RobotLog& log, const Pose2& base) { return base.compose(log.laser_in_base.value_or(Pose2())); }

LogMapResult map_log(const RobotLog& log, LogPoseSource source, const OccupancyMappingParams& params,
                     const MapScanObserver& observer) {
  const std::vector<std::optional<Pose2>> odometry = scan_odometry(log);
  const std::vector<LogOdometry> truth = truth_readings(log);
  if (source == LogPoseSource::Truth && truth.empty()) throw Error("holds no ground truth (TRUEPOS lines)", log.path, 0, "--poses");
  return map_with(log, params, [&](std::size_t k, bool& sensor_pose) -> std::optional<Pose2> {
    const LogScan& scan = log.scans[k];
    if (source == LogPoseSource::Truth) return odometry_at(truth, scan.stamp_us);
    if (source == LogPoseSource::Log && scan.laser_pose) {
      sensor_pose = true;
      return scan.laser_pose;
    }
    return odometry[k];
  }, observer);
}

std::vector<TrajectoryPose> odometry_trajectory(const RobotLog& log) {
  std::vector<TrajectoryPose> out;
  for_each_scan_with_odometry(log, [&](const LogScan& scan, const Pose2& odometry) { out.push_back({scan.stamp_us, odometry}); });
  return out;
}

LogMapResult map_log(const RobotLog& log, const std::vector<TrajectoryPose>& trajectory, const OccupancyMappingParams& params,
                     const MapScanObserver& observer) {
  std::map<std::int64_t, Pose2> by_stamp;
  for (const TrajectoryPose& p : trajectory) by_stamp.emplace(p.stamp_us, p.pose);
  return map_with(log, params, [&](std::size_t k, bool&) -> std::optional<Pose2> {
    const LogScan& scan = log.scans[k];
    const auto it = by_stamp.find(scan.stamp_us);
    if (it == by_stamp.end()) return std::nullopt;
    return it->second;
  }, observer);
}

namespace {

// The poses of `text`'s lines; `whole`: the whole file (not only its head), which must hold one.
std::vector<TrajectoryPose> parse_trajectory_csv(std::string_view text, const std::string& path, bool whole) {
  std::vector<TrajectoryPose> out;
  for_each_line(text, [&](std::string_view line, int line_no) {
    if (line.empty()) return;
    if (line_no == 1) {
      if (line != "t_s,x_m,y_m,yaw_rad") throw Error("expected the header t_s,x_m,y_m,yaw_rad", path, 1);
      return;
    }
    std::vector<std::string_view> cols;
    std::string_view rest = line;
    for (std::size_t comma; (comma = rest.find(',')) != std::string_view::npos; rest.remove_prefix(comma + 1))
      cols.push_back(rest.substr(0, comma));
    cols.push_back(rest);
    if (cols.size() != 4) throw Error("expected 4 columns t_s,x_m,y_m,yaw_rad, got " + std::to_string(cols.size()), path, line_no);
    TrajectoryPose p;
    if (!parse_stamp_us(cols[0], p.stamp_us))
      throw Error("expected a time in seconds, got '" + printable(cols[0], 40) + "'", path, line_no, "t_s");
    double v[3];
    const char* names[3] = {"x_m", "y_m", "yaw_rad"};
    for (int k = 0; k < 3; ++k) {
      const std::string_view c = cols[k + 1];
      if (!parse_finite_number(c, v[k]))
        throw Error("expected a finite number, got '" + printable(c, 40) + "'", path, line_no, names[k]);
      if (k < 2 && !plausible_coordinate(v[k]))
        throw Error(format_number(v[k]) + " m lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position",
                    path, line_no, names[k]);
    }
    p.pose = Pose2(v[0], v[1], wrap_angle(v[2]));
    out.push_back(p);
  });
  if (whole && out.empty()) throw Error("holds no pose", path);
  return out;
}

}  // namespace

std::vector<TrajectoryPose> read_trajectory_csv(const std::string& path) {
  const std::string text = read_text_lines_file(path, kMaxInputFileBytes, "a trajectory CSV (t_s,x_m,y_m,yaw_rad)",
                                                [&](std::string_view head) { parse_trajectory_csv(head, path, false); });
  return parse_trajectory_csv(text, path, true);
}

std::string trajectory_csv(const std::vector<TrajectoryPose>& poses) {
  std::string s = "t_s,x_m,y_m,yaw_rad\n";
  for (const TrajectoryPose& p : poses)
    s += format_stamp_us(p.stamp_us) + "," + format_number(p.pose.x) + "," + format_number(p.pose.y) + "," +
         format_number(p.pose.yaw) + "\n";
  return s;
}

}  // namespace starnav
