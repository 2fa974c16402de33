#include "starnav/io/point_cloud_io.hpp"

#include <cstdio>
#include <fstream>

#include "starnav/core/error.hpp"

namespace starnav {

std::string format_point_cloud(std::span<const Vec3> points, PointCloudFormat format) {
  std::string out;
  out.reserve(64 + points.size() * 36);
  const std::string n = std::to_string(points.size());
  if (format == PointCloudFormat::Ply) {
    out += "ply\nformat ascii 1.0\ncomment starnav point cloud, world frame, metres\nelement vertex " + n +
           "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  } else {
    out += "# .PCD v0.7 - starnav point cloud, world frame, metres\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
           "COUNT 1 1 1\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA ascii\n";
  }
  char buf[96];
  for (const Vec3& p : points) {
    const int len = std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f\n", p.x(), p.y(), p.z());
    out.append(buf, static_cast<std::size_t>(len));
  }
  return out;
}

void write_point_cloud(const std::string& path, std::span<const Vec3> points, PointCloudFormat format) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw Error("cannot write the point cloud", path);
  const std::string text = format_point_cloud(points, format);
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!f) throw Error("cannot write the point cloud", path);
}

}  // namespace starnav
