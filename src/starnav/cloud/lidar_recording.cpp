#include "starnav/cloud/lidar_recording.hpp"

#include "starnav/logs/ros2_bag.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/kitti_dataset.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/logs/log_file.hpp"

namespace starnav {

namespace fs = std::filesystem;

void LidarRecordingOptions::validate() const {
  require(std::isfinite(rate_hz) && rate_hz > 0 && rate_hz <= 10000, "rate_hz", "must be in (0, 10000] Hz");
  if (mount) require(mount->position.allFinite() && mount->orientation.coeffs().allFinite(), "mount", "must be finite");
}

namespace {

// The poses of `text`'s lines; `whole`: the whole file (not only its head), which must hold one.
std::vector<PoseFileEntry> parse_pose_file(std::string_view text, const std::string& path, bool whole) {
  std::vector<PoseFileEntry> out;
  std::size_t columns = 0;
  for_each_line(text, [&](std::string_view line, int line_no) {
    const std::vector<std::string_view> f = split_fields(line);
    if (f.empty() || f[0].starts_with("#")) return;
    if (columns == 0) {
      if (f.size() != 8 && f.size() != 12 && f.size() != 13)
        throw Error(std::to_string(f.size()) + " values: expected KITTI's 12 (13 with a time) or TUM's 8", path, line_no, "pose");
      columns = f.size();
    }
    if (f.size() != columns)
      throw Error(std::to_string(f.size()) + " values, the first line has " + std::to_string(columns), path, line_no, "pose");
    double v[13];
    for (std::size_t k = 0; k < columns; ++k)
      if (!parse_finite_number(f[k], v[k]))
        throw Error("'" + printable(f[k], 30) + "' is not a finite number", path, line_no, "pose");
    PoseFileEntry e;
    if (columns == 8) {
      e.t_s = v[0];
      const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
      if (!(std::abs(q.norm() - 1.0) < 1e-3)) throw Error("the quaternion is not of unit length", path, line_no, "pose");
      e.pose.linear() = q.normalized().toRotationMatrix();
      e.pose.translation() = Vec3(v[1], v[2], v[3]);
    } else {
      double m[12];
      std::copy(v + (columns == 13 ? 1 : 0), v + columns, m);
      if (columns == 13) e.t_s = v[0];
      e.pose = rigid_from_kitti_3x4(m, path, line_no, "pose");
    }
    if (!(plausible_coordinate(e.pose.translation().x()) && plausible_coordinate(e.pose.translation().y()) &&
          plausible_coordinate(e.pose.translation().z())))
      throw Error("the position lies farther than " + format_number(kMaxCoordinateM) + " m from the origin", path, line_no, "pose");
    if (e.t_s && !out.empty() && out.back().t_s && !(*e.t_s > *out.back().t_s))
      throw Error("times must increase", path, line_no, "t");
    out.push_back(e);
  });
  if (whole && out.empty()) throw Error("no poses", path, 0, "pose");
  return out;
}

}  // namespace

std::vector<PoseFileEntry> read_pose_file(const std::string& path) {
  const InputFileScope reading_path(path);
  const std::string text = read_text_lines_file(path, kMaxInputFileBytes, "a pose file (KITTI or TUM lines)",
                                                [&](std::string_view head) { parse_pose_file(head, path, false); });
  return parse_pose_file(text, path, true);
}

namespace {

bool is_cloud_file(const fs::path& p) {
  const std::string name = p.filename().string();
  for (const char* ext : {".pcd", ".ply", ".bin", ".bin.gz"})
    if (name.size() > std::string_view(ext).size() && name.ends_with(ext)) return true;
  return false;
}

// The number a frame file is named by ("000123.bin.gz" -> 123), if it is all digits.
std::optional<std::size_t> frame_number(const std::string& name) {
  const std::size_t dot = name.find('.');
  const std::string stem = name.substr(0, dot);
  if (stem.empty() || stem.size() > 9 || !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return static_cast<std::size_t>(std::stoul(stem));
}

// KITTI's calib.txt "Tr:" line (p_cam0 = Tr p_velo), when present.
std::optional<Rigid3> calib_tr(const std::string& path) {
  const std::string text = read_text_lines_file(path, kMaxInputFileBytes, "a KITTI calib.txt", [](std::string_view) {});
  std::optional<Rigid3> tr;
  for_each_line(text, [&](std::string_view line, int line_no) {
    if (!line.starts_with("Tr:")) return;
    const std::vector<std::string_view> f = split_fields(line.substr(3));
    if (f.size() != 12) throw Error(std::to_string(f.size()) + " values, expected 12", path, line_no, "Tr");
    double v[12];
    for (std::size_t k = 0; k < 12; ++k)
      if (!parse_finite_number(f[k], v[k])) throw Error("'" + printable(f[k], 30) + "' is not a finite number", path, line_no, "Tr");
    tr = rigid_from_kitti_3x4(v, path, line_no, "Tr");
  });
  return tr;
}

// The base's truth from sensor poses in any frame: the motion relative to the first, with the
// mount above the origin.
void set_truth_from_sensor_poses(LidarFrameFolder& folder, const std::vector<Rigid3>& sensor) {
  const Rigid3 mount = to_rigid(folder.mount);
  const Rigid3 first_inv = sensor.front().inverse();
  for (std::size_t i = 0; i < folder.frames.size(); ++i)
    folder.frames[i].truth = to_pose3(mount * first_inv * sensor[i] * mount.inverse());
}

// The clouds of a folder's frames, read one at a time from the files they name.
std::function<void(std::size_t, const std::function<void(std::size_t, PointCloud&&)>&)> folder_cloud_stream(
    const LidarFrameFolder& folder) {
  const auto frames = std::make_shared<const LidarFrameFolder>(folder);
  return [frames](std::size_t count, const std::function<void(std::size_t, PointCloud&&)>& visit) {
    const std::size_t n = count == 0 ? frames->frames.size() : std::min(count, frames->frames.size());
    for (std::size_t i = 0; i < n; ++i) visit(i, read_point_cloud(frames->cloud_path(frames->frames[i])).points);
  };
}

LidarRecording open_frames_folder(const std::string& dir, const LidarRecordingOptions& o) {
  LidarRecording rec;
  rec.path = dir;
  rec.kind = "frames folder";
  rec.frames = read_lidar_frame_folder(dir);
  if (o.mount) rec.frames.mount = *o.mount;
  rec.for_each_cloud = folder_cloud_stream(rec.frames);
  return rec;
}

LidarRecording open_cloud_files(const std::string& input, const LidarRecordingOptions& o) {
  // KITTI's layout: the clouds in SEQUENCE/velodyne/, poses.txt, times.txt and calib.txt in SEQUENCE.
  fs::path dir(input);
  fs::path sequence = dir;
  if (fs::is_directory(dir / "velodyne")) {
    dir /= "velodyne";
  } else {
    fs::path norm = fs::absolute(dir).lexically_normal();
    if (!norm.has_filename()) norm = norm.parent_path();
    if (norm.filename() == "velodyne") sequence = norm.parent_path();
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_cloud_file(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw Error("holds no frames.csv, no cloud files (.pcd, .ply, .bin, .bin.gz) and no velodyne/ folder", input);
  LidarRecording rec;
  rec.path = input;
  rec.kind = "cloud files";
  LidarFrameFolder& f = rec.frames;
  f.dir = dir.string();
  f.model = "unknown";
  f.rate_hz = o.rate_hz;
  if (o.mount) f.mount = *o.mount;
  // Pose rows: by the file's number when every file is named by one, else by position.
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto number = frame_number(files[i].filename().string());
    if (!number) {
      rows.clear();
      break;
    }
    rows.push_back(*number);
  }
  if (rows.empty())
    for (std::size_t i = 0; i < files.size(); ++i) rows.push_back(i);
  // Times.
  std::vector<double> times;
  const fs::path times_file = fs::path(sequence) / "times.txt";
  if (fs::exists(times_file)) {
    const std::string text = read_text_lines_file(times_file.string(), kMaxInputFileBytes, "a KITTI times.txt", [](std::string_view) {});
    for_each_line(text, [&](std::string_view line, int line_no) {
      const std::vector<std::string_view> v = split_fields(line);
      if (v.empty()) return;
      double t = 0.0;
      if (v.size() != 1 || !parse_finite_number(v[0], t))
        throw Error("'" + printable(line, 30) + "' is not one finite number", times_file.string(), line_no, "t");
      times.push_back(t);
    });
  }
  // Poses.
  std::string poses_file = o.poses;
  if (poses_file.empty() && fs::exists(fs::path(sequence) / "poses.txt")) poses_file = (fs::path(sequence) / "poses.txt").string();
  std::vector<PoseFileEntry> poses;
  if (!poses_file.empty()) poses = read_pose_file(poses_file);
  for (std::size_t i = 0; i < files.size(); ++i) {
    LidarFrameRecord r;
    r.frame = static_cast<int>(i);
    r.cloud = files[i].filename().string();
    const std::size_t row = rows[i];
    if (!times.empty()) {
      if (row >= times.size())
        throw Error("has " + std::to_string(times.size()) + " times, frame " + r.cloud + " needs row " + std::to_string(row + 1),
                    times_file.string(), 0, "t");
      r.t_s = times[row];
    } else if (!poses.empty() && row < poses.size() && poses[row].t_s) {
      r.t_s = *poses[row].t_s;
    } else {
      r.t_s = static_cast<double>(row) / o.rate_hz;
    }
    if (!f.frames.empty() && !(r.t_s > f.frames.back().t_s))
      throw Error("frame " + r.cloud + ": times must increase", times.empty() ? poses_file : times_file.string(), 0, "t");
    f.frames.push_back(r);
  }
  if (!poses.empty()) {
    // KITTI's sequence layout: camera poses, the LiDAR's through Tr.
    std::optional<Rigid3> tr;
    const fs::path calib = fs::path(poses_file).parent_path() / "calib.txt";
    if (fs::exists(calib)) {
      tr = calib_tr(calib.string());
      if (!tr) {
        const std::string name = fs::path(poses_file).parent_path().filename().string();
        try {
          tr = kitti_velodyne_to_camera(name);
        } catch (const Error&) {
          throw Error("has no Tr line, so the camera poses of " + poses_file +
                          " cannot be turned into the LiDAR's (and the folder is not a KITTI sequence 00-10)",
                      calib.string(), 0, "Tr");
        }
      }
    }
    std::vector<Rigid3> sensor;
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (rows[i] >= poses.size())
        throw Error("has " + std::to_string(poses.size()) + " poses, frame " + f.frames[i].cloud + " needs row " +
                        std::to_string(rows[i] + 1),
                    poses_file, 0, "pose");
      sensor.push_back(tr ? kitti_lidar_pose(poses[rows[i]].pose, *tr) : poses[rows[i]].pose);
    }
    set_truth_from_sensor_poses(f, sensor);
  }
  rec.for_each_cloud = folder_cloud_stream(f);
  return rec;
}

// Linear interpolation of stamped samples at `t_us` (held within `hold_us` beyond either end).
template <class Sample, class Lerp>
std::optional<decltype(std::declval<Lerp>()(std::declval<const Sample&>(), std::declval<const Sample&>(), 0.0))> interpolate(
    const std::vector<Sample>& s, std::int64_t t_us, std::int64_t hold_us, Lerp lerp) {
  if (s.empty() || t_us < s.front().stamp_us - hold_us || t_us > s.back().stamp_us + hold_us) return std::nullopt;
  const auto after = std::lower_bound(s.begin(), s.end(), t_us, [](const Sample& a, std::int64_t t) { return a.stamp_us < t; });
  if (after == s.begin()) return lerp(s.front(), s.front(), 0.0);
  if (after == s.end()) return lerp(s.back(), s.back(), 0.0);
  const Sample& a = *(after - 1);
  const Sample& b = *after;
  const double u = b.stamp_us == a.stamp_us ? 1.0 : static_cast<double>(t_us - a.stamp_us) / static_cast<double>(b.stamp_us - a.stamp_us);
  return lerp(a, b, u);
}

// A ROS 1 bag (its bytes kept for the clouds' pass; a bag is a robot log whatever it records: the
// log's size limit holds for it) or a ROS 2 recording (read again).
LidarRecording open_bag(const std::string& path, const LidarRecordingOptions& o, bool ros2) {
  std::shared_ptr<const std::string> bytes;
  std::shared_ptr<const PointCloudBagIndex> index;
  if (ros2) {
    index = std::make_shared<const PointCloudBagIndex>(index_ros2_point_cloud_bag(path, o.bag));
  } else {
    bytes = std::make_shared<const std::string>(read_input_file(path, kMaxLogFileBytes));
    index = std::make_shared<const PointCloudBagIndex>(index_point_cloud_bag(*bytes, path, o.bag));
  }
  LidarRecording rec;
  rec.path = path;
  rec.kind = ros2 ? "ROS 2 bag" : "ROS 1 bag";
  LidarFrameFolder& f = rec.frames;
  f.dir = path;
  f.model = "unknown";
  f.mount = o.mount ? *o.mount : index->sensor_in_base.value_or(Pose3());
  if (index->cloud_stamps_us.empty()) throw Error("has no messages on " + index->cloud_topic, path, 0, "--cloud-topic");
  // Odometry and truth: sorted by stamp (a bag is in receipt order).
  std::vector<LogOdometry> odom = index->odometry;
  std::stable_sort(odom.begin(), odom.end(), [](const LogOdometry& a, const LogOdometry& b) { return a.stamp_us < b.stamp_us; });
  std::vector<StampedPose3> truth = index->truth;
  std::stable_sort(truth.begin(), truth.end(), [](const StampedPose3& a, const StampedPose3& b) { return a.stamp_us < b.stamp_us; });
  constexpr std::int64_t kHoldUs = 50'000;  // half a 10 Hz period: a cloud stamped just outside the odometry's span
  const std::int64_t t0 = index->cloud_stamps_us.front();
  for (std::size_t i = 0; i < index->cloud_stamps_us.size(); ++i) {
    const std::int64_t t = index->cloud_stamps_us[i];
    if (i > 0 && t <= index->cloud_stamps_us[i - 1])
      throw Error("cloud " + std::to_string(i + 1) + " is not stamped after the one before", path, 0, index->cloud_topic);
    LidarFrameRecord r;
    r.frame = static_cast<int>(i);
    r.t_s = static_cast<double>(t - t0) * 1e-6;
    r.cloud = index->cloud_topic + " #" + std::to_string(i + 1);
    r.odometry = interpolate(odom, t, kHoldUs, [](const LogOdometry& a, const LogOdometry& b, double u) {
      return Pose2(a.pose.x + u * (b.pose.x - a.pose.x), a.pose.y + u * (b.pose.y - a.pose.y),
                   wrap_angle(a.pose.yaw + u * wrap_angle(b.pose.yaw - a.pose.yaw)));
    });
    r.truth = interpolate(truth, t, kHoldUs, [](const StampedPose3& a, const StampedPose3& b, double u) {
      Pose3 p;
      p.position = a.pose.position + u * (b.pose.position - a.pose.position);
      p.orientation = a.pose.orientation.slerp(u, b.pose.orientation);
      return p;
    });
    f.frames.push_back(r);
  }
  if (f.frames.size() > 1)
    f.rate_hz = static_cast<double>(f.frames.size() - 1) / (f.frames.back().t_s - f.frames.front().t_s);
  // A truth topic's frame is its own (a motion-capture room, UTM with the altitude): only its motion
  // is compared, as a poses file's.
  if (std::all_of(f.frames.begin(), f.frames.end(), [](const LidarFrameRecord& r) { return r.truth.has_value(); })) {
    const Rigid3 mount = to_rigid(f.mount);
    std::vector<Rigid3> sensor;
    for (const LidarFrameRecord& r : f.frames) sensor.push_back(to_rigid(*r.truth) * mount);
    set_truth_from_sensor_poses(f, sensor);
  }
  rec.for_each_cloud = [bytes, index, path, ros2](std::size_t count, const std::function<void(std::size_t, PointCloud&&)>& visit) {
    std::size_t i = 0;
    const std::size_t n = count == 0 ? index->cloud_stamps_us.size() : std::min(count, index->cloud_stamps_us.size());
    const auto each = [&](BagPointCloud&& c) {
      if (i >= n) throw std::out_of_range("enough");  // stops the walk early
      visit(i++, std::move(c.points));
    };
    try {
      if (ros2) for_each_ros2_point_cloud(path, *index, each);
      else for_each_bag_point_cloud(*bytes, path, *index, each);
    } catch (const std::out_of_range&) {
    }
  };
  return rec;
}

}  // namespace

LidarRecording open_lidar_recording(const std::string& input, const LidarRecordingOptions& options) {
  options.validate();
  const fs::path p(input);
  if (fs::is_directory(p)) {
    if (is_ros2_bag_folder(input)) return open_bag(input, options, true);
    if (fs::exists(p / "frames.csv")) return open_frames_folder(input, options);
    if (fs::exists(p / "lidar" / "frames.csv")) return open_frames_folder((p / "lidar").string(), options);
    return open_cloud_files(input, options);
  }
  if (!fs::exists(p)) throw Error("does not exist", input);
  if (fs::is_regular_file(p)) {
    std::ifstream in(input, std::ios::binary);
    char head[16] = {};
    in.read(head, sizeof head);
    const std::string_view start(head, static_cast<std::size_t>(in.gcount()));
    if (is_ros1_bag(start)) return open_bag(input, options, false);
    if (is_ros2_bag_bytes(start)) return open_bag(input, options, true);
  }
  throw Error("is neither a folder of LiDAR frames or cloud files nor a ROS 1 or ROS 2 bag", input);
}

}  // namespace starnav
