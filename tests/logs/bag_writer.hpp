#pragma once
// A small ROS 1 bag 2.0 writer for test fixtures (the record layout of wiki.ros.org/Bags/Format/2.0;
// no index records, which the reader does not need): connections and messages in chunks stored
// plain, bzip2- or LZ4-compressed, and the serialised LaserScan, PointCloud2, Odometry and
// TFMessage of ROS 1. Written from the format description, independently of the reader under test.
#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace starnav::test {

class Bytes {
 public:
  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  Bytes& u32(std::uint32_t v) { return put(v); }
  Bytes& str(const std::string& v) {
    u32(static_cast<std::uint32_t>(v.size()));
    s += v;
    return *this;
  }
  std::string s;
};

inline std::string header_field(const std::string& name, const std::string& value) {
  Bytes b;
  b.u32(static_cast<std::uint32_t>(name.size() + 1 + value.size()));
  b.s += name + "=" + value;
  return b.s;
}
template <class T>
std::string binary(T v) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &v, sizeof(T));
  return s;
}
inline std::string record(const std::string& header, const std::string& data) {
  Bytes b;
  b.str(header).str(data);
  return b.s;
}

struct BagConnectionSpec {
  std::uint32_t id;
  std::string topic, type;
};

class BagWriter {
 public:
  explicit BagWriter(std::string compression = "none") : compression_(std::move(compression)) {}

  void connection(const BagConnectionSpec& c) {
    const std::string header = header_field("op", std::string(1, '\x07')) + header_field("conn", binary(c.id)) +
                               header_field("topic", c.topic);
    const std::string data = header_field("topic", c.topic) + header_field("type", c.type) +
                             header_field("md5sum", std::string(32, '0')) + header_field("message_definition", "");
    chunk_ += record(header, data);
  }
  void message(std::uint32_t conn, std::uint32_t sec, std::uint32_t nsec, const std::string& data) {
    const std::uint64_t time = static_cast<std::uint64_t>(nsec) << 32 | sec;
    const std::string header = header_field("op", std::string(1, '\x02')) + header_field("conn", binary(conn)) +
                               header_field("time", binary(time));
    chunk_ += record(header, data);
  }
  // Closes the current chunk (a bag may have several).
  void flush_chunk() {
    if (chunk_.empty()) return;
    const std::string stored = compress(chunk_);
    const std::string header = header_field("op", std::string(1, '\x05')) + header_field("compression", compression_) +
                               header_field("size", binary(static_cast<std::uint32_t>(chunk_.size())));
    chunks_ += record(header, stored);
    chunk_.clear();
  }
  std::string bytes() {
    flush_chunk();
    // The bag header record (index_pos 0: no index), padded to 4096 bytes as rosbag does.
    const std::string header = header_field("op", std::string(1, '\x03')) + header_field("index_pos", binary<std::uint64_t>(0)) +
                               header_field("conn_count", binary<std::uint32_t>(0)) +
                               header_field("chunk_count", binary<std::uint32_t>(0));
    std::string bag_header = record(header, std::string(4096 - header.size() - 8 - 4, ' '));
    return "#ROSBAG V2.0\n" + bag_header + chunks_;
  }

 private:
  std::string compress(const std::string& raw) const {
    if (compression_ == "bz2") {
      std::string out(raw.size() + raw.size() / 100 + 600, '\0');
      unsigned len = static_cast<unsigned>(out.size());
      if (BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(raw.data()), static_cast<unsigned>(raw.size()), 9, 0,
                                   0) != BZ_OK)
        throw std::runtime_error("bz2");
      out.resize(len);
      return out;
    }
    if (compression_ == "lz4") {
      std::string out(LZ4F_compressFrameBound(raw.size(), nullptr), '\0');
      const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), raw.data(), raw.size(), nullptr);
      if (LZ4F_isError(n)) throw std::runtime_error("lz4");
      out.resize(n);
      return out;
    }
    return raw;
  }
  std::string compression_;
  std::string chunk_, chunks_;
};

// ROS 1 serialisations.
inline void ros_header(Bytes& b, std::uint32_t sec, std::uint32_t nsec, const std::string& frame) {
  b.u32(0).u32(sec).u32(nsec).str(frame);
}
inline std::string laser_scan(std::uint32_t sec, std::uint32_t nsec, const std::string& frame, float angle_min,
                              float increment, float range_max, const std::vector<float>& ranges) {
  Bytes b;
  ros_header(b, sec, nsec, frame);
  b.put(angle_min).put(static_cast<float>(angle_min + increment * static_cast<float>(ranges.size() - 1))).put(increment);
  b.put(0.0f).put(0.0f).put(0.1f).put(range_max);
  b.u32(static_cast<std::uint32_t>(ranges.size()));
  for (float r : ranges) b.put(r);
  b.u32(0);  // no intensities
  return b.s;
}
// A LaserScan with every layout field given (fixtures of faulty scans).
inline std::string laser_scan_fields(float angle_min, float angle_max, float increment, float range_min, float range_max,
                                     const std::vector<float>& ranges) {
  Bytes b;
  ros_header(b, 1, 0, "laser");
  b.put(angle_min).put(angle_max).put(increment).put(0.0f).put(0.0f).put(range_min).put(range_max);
  b.u32(static_cast<std::uint32_t>(ranges.size()));
  for (float r : ranges) b.put(r);
  b.u32(0);
  return b.s;
}
inline std::string odometry(std::uint32_t sec, std::uint32_t nsec, const std::string& child, double x, double y, double yaw,
                            double tv, double rv) {
  Bytes b;
  ros_header(b, sec, nsec, "odom");
  b.str(child);
  b.put(x).put(y).put(0.0);
  b.put(0.0).put(0.0).put(std::sin(yaw / 2)).put(std::cos(yaw / 2));
  for (int i = 0; i < 36; ++i) b.put(0.0);
  b.put(tv).put(0.0).put(0.0).put(0.0).put(0.0).put(rv);
  for (int i = 0; i < 36; ++i) b.put(0.0);
  return b.s;
}
struct TransformSpec {
  std::string parent, child;
  double x, y, yaw;
};
inline std::string tf_message(const std::vector<TransformSpec>& transforms) {
  Bytes b;
  b.u32(static_cast<std::uint32_t>(transforms.size()));
  for (const TransformSpec& t : transforms) {
    ros_header(b, 0, 0, t.parent);
    b.str(t.child);
    b.put(t.x).put(t.y).put(0.0);
    b.put(0.0).put(0.0).put(std::sin(t.yaw / 2)).put(std::cos(t.yaw / 2));
  }
  return b.s;
}

// A 3D transform (tf2_msgs/TFMessage with one geometry_msgs/TransformStamped per entry).
struct Transform3Spec {
  std::string parent, child;
  double x, y, z, qx, qy, qz, qw;
};
inline std::string tf_message3(const std::vector<Transform3Spec>& transforms) {
  Bytes b;
  b.u32(static_cast<std::uint32_t>(transforms.size()));
  for (const Transform3Spec& t : transforms) {
    ros_header(b, 0, 0, t.parent);
    b.str(t.child);
    b.put(t.x).put(t.y).put(t.z);
    b.put(t.qx).put(t.qy).put(t.qz).put(t.qw);
  }
  return b.s;
}
// nav_msgs/Odometry with a full 3D pose.
inline std::string odometry3(std::uint32_t sec, std::uint32_t nsec, const std::string& child, double x, double y, double z,
                             double qx, double qy, double qz, double qw) {
  Bytes b;
  ros_header(b, sec, nsec, "map");
  b.str(child);
  b.put(x).put(y).put(z);
  b.put(qx).put(qy).put(qz).put(qw);
  for (int i = 0; i < 36; ++i) b.put(0.0);
  for (int i = 0; i < 6; ++i) b.put(0.0);
  for (int i = 0; i < 36; ++i) b.put(0.0);
  return b.s;
}

// sensor_msgs/PointCloud2 of xyz points with a leading intensity field (so x is not at offset 0),
// as `height` rows of `points.size() / height`, each row padded by `row_padding` bytes; coordinates
// as FLOAT32 or FLOAT64 (`double_precision`), in either byte order.
struct PointXyz {
  double x, y, z;
};
inline std::string point_cloud2(std::uint32_t sec, std::uint32_t nsec, const std::string& frame, const std::vector<PointXyz>& points,
                                bool double_precision = false, bool big_endian = false, std::uint32_t height = 1,
                                std::uint32_t row_padding = 0, bool with_z = true) {
  const std::uint32_t size = double_precision ? 8 : 4;
  const std::uint8_t datatype = double_precision ? 8 : 7;
  const std::uint32_t width = static_cast<std::uint32_t>(points.size()) / height;
  const std::uint32_t point_step = 4 + 3 * size;
  const std::uint32_t row_step = width * point_step + row_padding;
  Bytes b;
  ros_header(b, sec, nsec, frame);
  b.u32(height).u32(width);
  b.u32(with_z ? 4 : 3);
  b.str("intensity").u32(0).put<std::uint8_t>(7).u32(1);
  b.str("x").u32(4).put<std::uint8_t>(datatype).u32(1);
  b.str("y").u32(4 + size).put<std::uint8_t>(datatype).u32(1);
  if (with_z) b.str("z").u32(4 + 2 * size).put<std::uint8_t>(datatype).u32(1);
  b.put<std::uint8_t>(big_endian ? 1 : 0).u32(point_step).u32(row_step);
  std::string data;
  auto append = [&](const void* v, std::size_t n) {
    std::string bytes(static_cast<const char*>(v), n);
    if (big_endian) std::reverse(bytes.begin(), bytes.end());
    data += bytes;
  };
  for (std::uint32_t row = 0; row < height; ++row) {
    for (std::uint32_t col = 0; col < width; ++col) {
      const PointXyz& p = points[row * width + col];
      const float intensity = 1.0f;
      append(&intensity, 4);
      for (double c : {p.x, p.y, p.z}) {
        if (double_precision) {
          append(&c, 8);
        } else {
          const float f = static_cast<float>(c);
          append(&f, 4);
        }
      }
    }
    data += std::string(row_padding, '\0');
  }
  b.str(data);
  b.put<std::uint8_t>(0);  // is_dense
  return b.s;
}

}  // namespace starnav::test
