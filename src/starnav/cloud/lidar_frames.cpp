#include "starnav/cloud/lidar_frames.hpp"

#include <cmath>
#include <filesystem>

#include <yaml-cpp/yaml.h>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/io/yaml_document.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

constexpr const char* kLidarFrameColumns[] = {"frame",         "t_s",         "cloud",        "odom_x_m",      "odom_y_m",
                                              "odom_yaw_rad",  "imu_yaw_rate_radps", "true_x_m", "true_y_m",  "true_z_m",
                                              "true_roll_rad", "true_pitch_rad", "true_yaw_rad"};
constexpr std::size_t kLidarFrameColumnCount = std::size(kLidarFrameColumns);

std::string cell(const std::optional<double>& v) { return v ? format_fixed6(*v) : std::string(); }

}  // namespace

std::string LidarFrameFolder::cloud_path(const LidarFrameRecord& f) const { return (fs::path(dir) / f.cloud).string(); }

std::string lidar_frames_header() {
  std::string s;
  for (const char* c : kLidarFrameColumns) {
    if (!s.empty()) s += ',';
    s += c;
  }
  s += '\n';
  return s;
}

std::string lidar_frame_row(const LidarFrameRecord& r) {
  std::string s = std::to_string(r.frame) + "," + format_fixed6(r.t_s) + "," + r.cloud + ",";
  if (r.odometry) {
    s += format_fixed6(r.odometry->x) + "," + format_fixed6(r.odometry->y) + "," + format_fixed6(r.odometry->yaw) + ",";
  } else {
    s += ",,,";
  }
  s += cell(r.imu_yaw_rate_radps) + ",";
  if (r.truth) {
    const Vec3 rpy = r.truth->rpy();
    s += format_fixed6(r.truth->position.x()) + "," + format_fixed6(r.truth->position.y()) + "," +
         format_fixed6(r.truth->position.z()) + "," + format_fixed6(rpy.x()) + "," + format_fixed6(rpy.y()) + "," +
         format_fixed6(rpy.z());
  } else {
    s += ",,,,,";
  }
  return s + "\n";
}

std::string lidar_sensor_yaml(const std::string& model, int lines, int beams, double rate_hz, double range_min_m,
                              double range_max_m, const Pose3& mount) {
  const Vec3 rpy = mount.rpy() * (180.0 / kPi);
  return "# The LiDAR of these frames (docs/mapping3d.md)\nmodel: " + model + "\nlines: " + std::to_string(lines) +
         "\nbeams: " + std::to_string(beams) + "\nrate_hz: " + format_fixed6(rate_hz) + "\nrange_min_m: " +
         format_fixed6(range_min_m) + "\nrange_max_m: " + format_fixed6(range_max_m) + "\nmount: {x_m: " +
         format_fixed6(mount.position.x()) + ", y_m: " + format_fixed6(mount.position.y()) + ", z_m: " +
         format_fixed6(mount.position.z()) + ", roll_deg: " + format_fixed6(rpy.x()) + ", pitch_deg: " +
         format_fixed6(rpy.y()) + ", yaw_deg: " + format_fixed6(rpy.z()) + "}\n";
}

LidarFrameFolder read_lidar_frame_folder(const std::string& dir) {
  LidarFrameFolder out;
  out.dir = dir;
  if (!fs::is_directory(dir)) throw Error("is not a folder of LiDAR frames", dir);
  const std::string sensor = (fs::path(dir) / "sensor.yaml").string();
  {
    const YAML::Node y = load_yaml_document(read_yaml_file(sensor), sensor);
    auto number = [&](const YAML::Node& n, const std::string& key) {
      if (!n || !n[key] || !n[key].IsScalar()) throw Error("missing", sensor, 0, key);
      double v = 0.0;
      if (!parse_finite_number(n[key].Scalar(), v)) throw Error("'" + printable(n[key].Scalar(), 30) + "' is not a finite number", sensor, 0, key);
      return v;
    };
    if (!y.IsMap()) throw Error("expected a mapping", sensor);
    out.model = y["model"] && y["model"].IsScalar() ? y["model"].Scalar() : "custom";
    out.lines = static_cast<int>(number(y, "lines"));
    out.beams = static_cast<int>(number(y, "beams"));
    out.rate_hz = number(y, "rate_hz");
    out.range_min_m = number(y, "range_min_m");
    out.range_max_m = number(y, "range_max_m");
    if (!(out.rate_hz > 0)) throw Error("must be > 0", sensor, 0, "rate_hz");
    const YAML::Node m = y["mount"];
    if (!m || !m.IsMap()) throw Error("missing", sensor, 0, "mount");
    out.mount = Pose3::from_rpy(Vec3(number(m, "x_m"), number(m, "y_m"), number(m, "z_m")), number(m, "roll_deg") * kPi / 180,
                                number(m, "pitch_deg") * kPi / 180, number(m, "yaw_deg") * kPi / 180);
  }
  const std::string csv = (fs::path(dir) / "frames.csv").string();
  const std::string text = read_text_lines_file(csv, kMaxInputFileBytes, "a frames.csv", [](std::string_view) {});
  bool header = true;
  for_each_line(text, [&](std::string_view line, int line_no) {
    if (line.empty()) return;
    std::vector<std::string_view> cells;
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = line.find(',', start);
      cells.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (cells.size() != kLidarFrameColumnCount)
      throw Error(std::to_string(cells.size()) + " columns, expected " + std::to_string(kLidarFrameColumnCount), csv, line_no);
    if (header) {
      for (std::size_t i = 0; i < kLidarFrameColumnCount; ++i)
        if (cells[i] != kLidarFrameColumns[i])
          throw Error("column " + std::to_string(i + 1) + " is '" + printable(cells[i], 30) + "', expected '" + kLidarFrameColumns[i] + "'",
                      csv, line_no, "header");
      header = false;
      return;
    }
    auto num = [&](std::size_t i) -> std::optional<double> {
      if (cells[i].empty()) return std::nullopt;
      double v = 0.0;
      if (!parse_finite_number(cells[i], v))
        throw Error("'" + printable(cells[i], 30) + "' is not a finite number", csv, line_no, kLidarFrameColumns[i]);
      return v;
    };
    auto required = [&](std::size_t i) {
      const auto v = num(i);
      if (!v) throw Error("missing", csv, line_no, kLidarFrameColumns[i]);
      return *v;
    };
    // Positions (odometry x, y; truth x, y, z) within kMaxCoordinateM of the origin.
    auto position = [&](std::size_t i) {
      const auto v = num(i);
      if (v && !plausible_coordinate(*v))
        throw Error(format_number(*v) + " m lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position",
                    csv, line_no, kLidarFrameColumns[i]);
      return v;
    };
    LidarFrameRecord r;
    const double frame = required(0);
    if (!(frame >= 0 && frame <= 1e9 && frame == std::floor(frame)))
      throw Error("'" + printable(cells[0], 30) + "' is not a frame number (a whole number 0..1000000000)", csv, line_no, "frame");
    r.frame = static_cast<int>(frame);
    r.t_s = required(1);
    r.cloud = std::string(cells[2]);
    if (r.cloud.empty() || r.cloud.find('/') != std::string::npos || r.cloud == "." || r.cloud == "..")
      throw Error("must be a file name beside frames.csv", csv, line_no, "cloud");
    if (!out.frames.empty() && !(r.t_s > out.frames.back().t_s)) throw Error("times must increase", csv, line_no, "t_s");
    const auto ox = position(3), oy = position(4), oyaw = num(5);
    if (ox && oy && oyaw) r.odometry = Pose2(*ox, *oy, *oyaw);
    else if (ox || oy || oyaw) throw Error("odometry needs x, y and yaw, or none", csv, line_no, "odom_x_m");
    r.imu_yaw_rate_radps = num(6);
    std::optional<double> t[6];
    int given = 0;
    for (int k = 0; k < 6; ++k) given += (t[k] = k < 3 ? position(static_cast<std::size_t>(7 + k)) : num(static_cast<std::size_t>(7 + k))).has_value();
    if (given == 6) r.truth = Pose3::from_rpy(Vec3(*t[0], *t[1], *t[2]), *t[3], *t[4], *t[5]);
    else if (given != 0) throw Error("the true pose needs all six values, or none", csv, line_no, "true_x_m");
    out.frames.push_back(r);
  });
  if (header) throw Error("empty: no header", csv);
  return out;
}

}  // namespace starnav
