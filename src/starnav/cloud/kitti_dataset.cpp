#include "starnav/cloud/kitti_dataset.hpp"

#include <algorithm>
#include <cstring>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/logs/decompress.hpp"

namespace starnav {

Rigid3 rigid_from_kitti_3x4(const double (&m)[12], const std::string& path, int line, const std::string& field) {
  Eigen::Matrix3d r;
  r << m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10];
  if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-3) || !(r.determinant() > 0))
    throw Error("the rotation part is not a rotation", path, line, field);
  Rigid3 t = Rigid3::Identity();
  t.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  t.translation() = Vec3(m[3], m[7], m[11]);
  return t;
}

namespace {

// The poses of `text`'s lines; `whole`: the whole file (not only its head), which must hold one.
std::vector<Rigid3> parse_kitti_poses(std::string_view text, const std::string& path, bool time_column, bool whole) {
  std::vector<Rigid3> poses;
  const std::size_t expected = time_column ? 13 : 12;
  for_each_line(text, [&](std::string_view line, int line_no) {
    const std::vector<std::string_view> f = split_fields(line);
    if (f.empty()) return;
    if (f.size() != expected)
      throw Error(std::to_string(f.size()) + " values, expected " + std::to_string(expected), path, line_no, "pose");
    double v[12];
    for (std::size_t k = 0; k < 12; ++k)
      if (!parse_finite_number(f[k + expected - 12], v[k]))
        throw Error("'" + printable(f[k + expected - 12], 30) + "' is not a finite number", path, line_no, "pose");
    poses.push_back(rigid_from_kitti_3x4(v, path, line_no, "pose"));
  });
  if (whole && poses.empty()) throw Error("no poses", path, 0, "pose");
  return poses;
}

}  // namespace

std::vector<Rigid3> read_kitti_poses(const std::string& path, bool time_column) {
  const InputFileScope reading_path(path);
  const std::string text = read_text_lines_file(path, kMaxInputFileBytes, "a KITTI pose file (12 values a line)", [&](std::string_view head) {
    parse_kitti_poses(head, path, time_column, false);
  });
  return parse_kitti_poses(text, path, time_column, true);
}

Rigid3 kitti_velodyne_to_camera(const std::string& sequence) {
  // KITTI data_odometry_calib, calib.txt "Tr:" (transcribed in ../shared/datasets/lidar3d/SOURCES.md).
  static const double kDay0930[12] = {-1.857739385241e-03, -9.999659513510e-01, -8.039975204516e-03, -4.784029760483e-03,
                                      -6.481465826011e-03, 8.051860151134e-03,  -9.999466081774e-01, -7.337429464231e-02,
                                      9.999773098287e-01,  -1.805528627661e-03, -6.496203536139e-03, -3.339968064433e-01};
  static const double kDay1003[12] = {4.276802385584e-04,  -9.999672484946e-01, -8.084491683471e-03, -1.198459927713e-02,
                                      -7.210626507497e-03, 8.081198471645e-03,  -9.999413164504e-01, -5.403984729748e-02,
                                      9.999738645903e-01,  4.859485810390e-04,  -7.206933692422e-03, -2.921968648686e-01};
  const double* v = nullptr;
  if (sequence == "00" || sequence == "01" || sequence == "02") v = kDay1003;
  for (const char* s : {"04", "05", "06", "07", "08", "09", "10"})
    if (sequence == s) v = kDay0930;
  if (!v) throw Error("no Velodyne-to-camera calibration known for KITTI sequence '" + printable(sequence, 10) + "'", "", 0, "sequence");
  double m[12];
  std::copy(v, v + 12, m);
  return rigid_from_kitti_3x4(m, "", 0, "sequence");
}

Rigid3 kitti_lidar_pose(const Rigid3& camera_pose, const Rigid3& velodyne_to_camera) { return camera_pose * velodyne_to_camera; }

std::vector<std::uint16_t> read_kitti_labels(const std::string& path) {
  // One label per point: a file of more labels than a cloud may have points is refused from its size.
  const auto check_head = [&](std::string_view head, std::uint64_t size) {
    if (!is_gzip(head) && size / 4 > kMaxCloudPoints)
      throw Error(std::to_string(size / 4) + " labels, more than the " + std::to_string(kMaxCloudPoints) +
                      " points a cloud may have",
                  path, 0, "size");
  };
  std::string bytes = read_input_file(path, kMaxInputFileBytes, 4, check_head);
  if (is_gzip(bytes)) bytes = gunzip(bytes, path);
  if (bytes.size() % 4 != 0) throw Error(std::to_string(bytes.size()) + " bytes is not a whole number of uint32 labels", path, 0, "size");
  std::vector<std::uint16_t> out(bytes.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + 4 * i, 4);
    out[i] = static_cast<std::uint16_t>(v & 0xffffU);
  }
  return out;
}

bool is_kitti_ground_class(std::uint16_t label) {
  return label == 40 || label == 44 || label == 48 || label == 49 || label == 60 || label == 72;
}

}  // namespace starnav
