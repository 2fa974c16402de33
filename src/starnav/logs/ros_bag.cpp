#include "starnav/logs/ros_bag.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <set>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/logs/bag_log.hpp"
#include "starnav/logs/decompress.hpp"

namespace starnav {

namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint8_t kOpMessage = 0x02, kOpBagHeader = 0x03, kOpIndex = 0x04, kOpChunk = 0x05, kOpChunkInfo = 0x06,
                       kOpConnection = 0x07;

// Little-endian reads over a byte range, failing with the byte offset and the field.
class ByteReader {
 public:
  ByteReader(std::string_view bytes, const std::string& path, std::size_t base, std::string where)
      : bytes_(bytes), path_(path), base_(base), where_(std::move(where)) {}

  bool done() const { return at_ >= bytes_.size(); }
  std::size_t offset() const { return at_; }
  std::size_t remaining() const { return bytes_.size() - at_; }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(what + " (" + where_ + " byte " + std::to_string(base_ + at_) + ")", path_, 0, field);
  }
  std::string_view take(std::size_t n, const char* field) {
    if (n > remaining()) fail(field, "needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
    const std::string_view v = bytes_.substr(at_, n);
    at_ += n;
    return v;
  }
  template <class T>
  T get(const char* field) {
    const std::string_view b = take(sizeof(T), field);
    T v;
    std::memcpy(&v, b.data(), sizeof(T));  // the bag format and every supported host are little-endian
    return v;
  }
  std::uint32_t u32(const char* field) { return get<std::uint32_t>(field); }
  std::string_view string(const char* field) { return take(u32(field), field); }

 private:
  std::string_view bytes_;
  const std::string& path_;
  std::size_t base_;
  std::string where_;
  std::size_t at_ = 0;
};

// A record header's fields (name=value pairs).
struct RecordHeader {
  std::map<std::string, std::string_view, std::less<>> fields;

  std::optional<std::string_view> find(std::string_view name) const {
    const auto it = fields.find(name);
    if (it == fields.end()) return std::nullopt;
    return it->second;
  }
  template <class T>
  T value(std::string_view name, const ByteReader& r) const {
    const auto v = find(name);
    if (!v) r.fail(std::string(name), "record header lacks the field");
    if (v->size() != sizeof(T)) r.fail(std::string(name), "expected " + std::to_string(sizeof(T)) + " bytes");
    T out;
    std::memcpy(&out, v->data(), sizeof(T));
    return out;
  }
};

RecordHeader parse_header(std::string_view bytes, const ByteReader& outer) {
  RecordHeader h;
  std::size_t i = 0;
  while (i < bytes.size()) {
    if (bytes.size() - i < 4) outer.fail("header", "truncated record header field");
    std::uint32_t len = 0;
    std::memcpy(&len, bytes.data() + i, 4);
    i += 4;
    if (len > bytes.size() - i) outer.fail("header", "record header field longer than its header");
    const std::string_view field = bytes.substr(i, len);
    i += len;
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) outer.fail("header", "record header field without '='");
    h.fields[std::string(field.substr(0, eq))] = field.substr(eq + 1);
  }
  return h;
}

struct Record {
  std::uint8_t op = 0;
  RecordHeader header;
  std::string_view data;
  std::size_t offset = 0;  // where the record starts
};

// Reads the records of `bytes` in order.
template <class Visit>
void for_each_record(ByteReader& r, Visit&& visit) {
  while (!r.done()) {
    Record rec;
    rec.offset = r.offset();
    const std::string_view header = r.string("header_len");
    rec.header = parse_header(header, r);
    const auto op = rec.header.find("op");
    if (!op || op->size() != 1) r.fail("op", "record header lacks a one-byte op");
    rec.op = static_cast<std::uint8_t>((*op)[0]);
    rec.data = r.string("data_len");
    visit(rec, r);
  }
}

std::string header_string(const RecordHeader& h, std::string_view name) {
  const auto v = h.find(name);
  return v ? std::string(*v) : std::string();
}

class BagWalker {
 public:
  BagWalker(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {
    if (!is_ros1_bag(bytes)) throw Error("not a ROS bag 2.0 file (no '#ROSBAG V2.0' line)", path, 0, "magic");
  }

  void walk(const std::function<void(const BagMessageView&)>* visit) {
    ByteReader top(bytes_.substr(kMagic.size()), path_, kMagic.size(), "file");
    for_each_record(top, [&](const Record& rec, ByteReader& r) {
      switch (rec.op) {
        case kOpChunk: chunk(rec, r, visit); break;
        case kOpConnection: connection(rec, r); break;
        case kOpMessage: message(rec, r, visit, kMagic.size() + rec.offset); break;
        case kOpBagHeader:
        case kOpIndex:
        case kOpChunkInfo: break;
        default: r.fail("op", "unknown record op " + std::to_string(rec.op));
      }
    });
  }

  std::vector<BagConnection> connections() const {
    std::vector<BagConnection> out;
    for (const auto& [id, c] : connections_) out.push_back(*c);
    return out;
  }
  // The bag's bytes with its chunks' decompressed data added (after a walk).
  std::uint64_t decompressed_bytes() const { return bytes_.size() + chunk_bytes_; }

 private:
  void connection(const Record& rec, const ByteReader& r) {
    const std::uint32_t id = rec.header.value<std::uint32_t>("conn", r);
    // The data is the connection header: topic, type, md5sum, message_definition, ...
    const RecordHeader h = parse_header(rec.data, r);
    auto c = std::make_unique<BagConnection>();
    c->id = id;
    // Names from the file are kept printable: they reach messages and reports.
    c->topic = printable(header_string(rec.header, "topic"), 200);
    c->type = printable(header_string(h, "type"), 200);
    c->md5sum = printable(header_string(h, "md5sum"), 64);
    if (c->topic.empty()) c->topic = printable(header_string(h, "topic"), 200);
    auto& slot = connections_[id];
    if (!slot) slot = std::move(c);
  }

  void message(const Record& rec, const ByteReader& r, const std::function<void(const BagMessageView&)>* visit,
               std::size_t file_offset) {
    const std::uint32_t id = rec.header.value<std::uint32_t>("conn", r);
    const std::uint64_t time = rec.header.value<std::uint64_t>("time", r);
    const auto it = connections_.find(id);
    if (it == connections_.end()) r.fail("conn", "message on connection " + std::to_string(id) + " before its connection record");
    if (!visit) {
      ++it->second->messages;
      return;
    }
    BagMessageView m;
    m.connection = it->second.get();
    m.record_time_ns = static_cast<std::uint64_t>(time & 0xffffffffu) * 1'000'000'000ull + (time >> 32);
    m.data = rec.data;
    m.file_offset = file_offset;
    (*visit)(m);
  }

  void chunk(const Record& rec, const ByteReader& r, const std::function<void(const BagMessageView&)>* visit) {
    const std::string compression = header_string(rec.header, "compression");
    const std::uint32_t size = rec.header.value<std::uint32_t>("size", r);
    const std::size_t at = kMagic.size() + rec.offset;
    std::string storage;
    std::string_view inner;
    if (compression == "none") {
      if (rec.data.size() != size) r.fail("size", "chunk size differs from its data");
      inner = rec.data;
    } else if (compression == "bz2") {
      storage = bunzip2(rec.data, size, path_, at);
      inner = storage;
    } else if (compression == "lz4") {
      storage = lz4_frame_decompress(rec.data, size, path_, at);
      inner = storage;
    } else {
      r.fail("compression", "unknown chunk compression '" + printable(compression, 20) + "' (none, bz2, lz4)");
    }
    if (compression != "none") chunk_bytes_ += inner.size();
    ByteReader in(inner, path_, 0, "chunk at file byte " + std::to_string(at) + ", decompressed");
    for_each_record(in, [&](const Record& inner_rec, ByteReader& ir) {
      if (inner_rec.op == kOpConnection) connection(inner_rec, ir);
      else if (inner_rec.op == kOpMessage) message(inner_rec, ir, visit, at);
      else ir.fail("op", "record op " + std::to_string(inner_rec.op) + " inside a chunk");
    });
  }

  std::string_view bytes_;
  const std::string& path_;
  std::map<std::uint32_t, std::unique_ptr<BagConnection>> connections_;
  std::uint64_t chunk_bytes_ = 0;
};

// ---- Messages -------------------------------------------------------------------------------------

struct StampedHeader {
  std::int64_t stamp_us = 0;
  std::string frame_id;
};

StampedHeader read_header(ByteReader& r) {
  StampedHeader h;
  r.u32("header.seq");
  const std::uint32_t sec = r.u32("header.stamp.sec");
  const std::uint32_t nsec = r.u32("header.stamp.nsec");
  if (nsec >= 1'000'000'000u) r.fail("header.stamp.nsec", "nanoseconds above 999999999");
  h.stamp_us = static_cast<std::int64_t>(sec) * 1'000'000 + (static_cast<std::int64_t>(nsec) + 500) / 1000;
  h.frame_id = printable(r.string("header.frame_id"), 200);
  return h;
}

struct DecodedScan {
  LogScan scan;
  std::string frame_id;
};

DecodedScan decode_laser_scan(ByteReader& r) {
  DecodedScan d;
  const StampedHeader h = read_header(r);
  d.frame_id = h.frame_id;
  LogScan& s = d.scan;
  s.stamp_us = h.stamp_us;
  s.angle_min_rad = r.get<float>("angle_min");
  const double angle_max = r.get<float>("angle_max");
  s.angle_increment_rad = r.get<float>("angle_increment");
  r.get<float>("time_increment");
  r.get<float>("scan_time");
  s.range_min_m = r.get<float>("range_min");
  s.range_max_m = r.get<float>("range_max");
  const std::uint32_t n = r.u32("ranges");
  if (const ScanCheck c = check_scan_beams(n); !c) r.fail(c.field, c.what);
  if (n > r.remaining() / 4) r.fail("ranges", std::to_string(n) + " ranges do not fit the message");
  // The beams run from angle_min towards angle_max: the increment's sign says which way.
  if (!std::isfinite(angle_max)) r.fail("angle_max", "not a finite angle");
  if (n > 1 && (angle_max - s.angle_min_rad) * s.angle_increment_rad < 0)
    r.fail("angle_max", "angle_min " + format_number(s.angle_min_rad) + " to angle_max " + format_number(angle_max) +
                            " runs against angle_increment " + format_number(s.angle_increment_rad));
  s.ranges_m.resize(n);
  const std::string_view raw = r.take(std::size_t{n} * 4, "ranges");
  if (n > 0) std::memcpy(s.ranges_m.data(), raw.data(), raw.size());  // an empty vector's data() may be null
  if (const ScanCheck c = check_scan_fields(s); !c) r.fail(c.field, c.what);
  return d;
}

struct DecodedOdometry {
  LogOdometry odometry;
  Pose3 pose3;
  std::string child_frame_id;
};

DecodedOdometry decode_odometry(ByteReader& r) {
  DecodedOdometry d;
  const StampedHeader h = read_header(r);
  d.odometry.stamp_us = h.stamp_us;
  d.child_frame_id = printable(r.string("child_frame_id"), 200);
  const double x = r.get<double>("pose.position.x"), y = r.get<double>("pose.position.y");
  const double z = r.get<double>("pose.position.z");
  const double qx = r.get<double>("pose.orientation.x"), qy = r.get<double>("pose.orientation.y");
  const double qz = r.get<double>("pose.orientation.z"), qw = r.get<double>("pose.orientation.w");
  r.take(36 * 8, "pose.covariance");
  d.odometry.tv_mps = r.get<double>("twist.linear.x");
  r.get<double>("twist.linear.y");
  r.get<double>("twist.linear.z");
  r.get<double>("twist.angular.x");
  r.get<double>("twist.angular.y");
  d.odometry.rv_radps = r.get<double>("twist.angular.z");
  r.take(36 * 8, "twist.covariance");
  d.odometry.pose = Pose2(x, y, yaw_of_quaternion(qx, qy, qz, qw));
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(d.odometry.pose.yaw))
    r.fail("pose", "not finite");
  if (!plausible_coordinate(x) || !plausible_coordinate(y) || !plausible_coordinate(z))
    r.fail("pose.position", "lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position");
  d.pose3 = pose3_of(x, y, z, qx, qy, qz, qw);
  return d;
}

void decode_tf(ByteReader& r, std::vector<FrameTransform>& out) {
  const std::uint32_t n = r.u32("transforms");
  if (n > r.remaining() / 16) r.fail("transforms", "more transforms than the message holds");
  for (std::uint32_t i = 0; i < n; ++i) {
    FrameTransform t;
    const StampedHeader h = read_header(r);
    t.stamp_us = h.stamp_us;
    t.parent = frame_name(h.frame_id);
    t.child = frame_name(printable(r.string("child_frame_id"), 200));
    const double x = r.get<double>("translation.x"), y = r.get<double>("translation.y");
    const double z = r.get<double>("translation.z");
    const double qx = r.get<double>("rotation.x"), qy = r.get<double>("rotation.y");
    const double qz = r.get<double>("rotation.z"), qw = r.get<double>("rotation.w");
    t.pose = Pose2(x, y, yaw_of_quaternion(qx, qy, qz, qw));
    t.pose3 = pose3_of(x, y, z, qx, qy, qz, qw);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(t.pose.yaw))
      r.fail("transforms", "not finite");
    if (!plausible_coordinate(x) || !plausible_coordinate(y) || !plausible_coordinate(z))
      r.fail("transforms", "a translation lies farther than " + format_number(kMaxCoordinateM) + " m: not a position");
    out.push_back(std::move(t));
  }
}

// sensor_msgs/Imu: the orientation's yaw (unless its covariance says there is none), the rates and
// accelerations.
LogImu decode_imu(ByteReader& r) {
  LogImu m;
  m.stamp_us = read_header(r).stamp_us;
  const double qx = r.get<double>("orientation.x"), qy = r.get<double>("orientation.y");
  const double qz = r.get<double>("orientation.z"), qw = r.get<double>("orientation.w");
  const double c0 = r.get<double>("orientation_covariance");
  r.take(8 * 8, "orientation_covariance");
  for (int k = 0; k < 3; ++k) m.angular_velocity_radps[k] = r.get<double>("angular_velocity");
  r.take(9 * 8, "angular_velocity_covariance");
  for (int k = 0; k < 3; ++k) m.linear_acceleration_mps2[k] = r.get<double>("linear_acceleration");
  r.take(9 * 8, "linear_acceleration_covariance");
  if (c0 != -1.0 && std::isfinite(qx + qy + qz + qw) && qx * qx + qy * qy + qz * qz + qw * qw > 1e-9)
    m.yaw_rad = yaw_of_quaternion(qx, qy, qz, qw);
  return m;
}

// geometry_msgs/PoseStamped and PoseWithCovarianceStamped: the stamp and the planar pose.
std::pair<std::int64_t, Pose2> decode_pose_stamped(ByteReader& r, bool with_covariance) {
  const std::int64_t stamp = read_header(r).stamp_us;
  const double x = r.get<double>("pose.position.x"), y = r.get<double>("pose.position.y");
  r.get<double>("pose.position.z");
  const double qx = r.get<double>("pose.orientation.x"), qy = r.get<double>("pose.orientation.y");
  const double qz = r.get<double>("pose.orientation.z"), qw = r.get<double>("pose.orientation.w");
  if (with_covariance) r.take(36 * 8, "pose.covariance");
  const Pose2 pose(x, y, yaw_of_quaternion(qx, qy, qz, qw));
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(pose.yaw)) r.fail("pose", "not finite");
  if (!plausible_coordinate(x) || !plausible_coordinate(y))
    r.fail("pose.position", "lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position");
  return {stamp, pose};
}

// sensor_msgs/PointCloud2: the x, y, z fields of every point, the points with a non-finite
// coordinate dropped (is_dense false marks their presence, but is not trusted either way).
BagPointCloud decode_point_cloud2(ByteReader& r) {
  BagPointCloud c;
  const StampedHeader h = read_header(r);
  c.stamp_us = h.stamp_us;
  c.frame_id = h.frame_id;
  const std::uint64_t height = r.u32("height"), width = r.u32("width");
  if (height * width > kMaxCloudPoints)
    r.fail("width", std::to_string(height) + " x " + std::to_string(width) + " points, more than the " +
                        std::to_string(kMaxCloudPoints) + " a cloud may have");
  const std::uint32_t nfields = r.u32("fields");
  if (nfields > r.remaining() / 13) r.fail("fields", std::to_string(nfields) + " fields do not fit the message");
  CloudLayout layout;
  layout.height = height;
  layout.width = width;
  for (std::uint32_t i = 0; i < nfields; ++i) {
    const std::string_view name = r.string("fields.name");
    const std::uint32_t offset = r.u32("fields.offset");
    const auto datatype = r.get<std::uint8_t>("fields.datatype");
    r.u32("fields.count");
    if (const ScanCheck e = add_cloud_field(layout, name, offset, datatype); !e) r.fail(e.field, e.what);
  }
  layout.big_endian = r.get<std::uint8_t>("is_bigendian") != 0;
  layout.point_step = r.u32("point_step");
  layout.row_step = r.u32("row_step");
  const std::uint32_t size = r.u32("data");
  const std::string_view data = r.take(size, "data");
  r.get<std::uint8_t>("is_dense");
  if (const ScanCheck e = check_cloud_layout(layout, size); !e) r.fail(e.field, e.what);
  cloud_points(layout, data, c.points, c.dropped);
  return c;
}

std::vector<BagTopic> bag_topics(const std::vector<BagConnection>& conns) {
  std::vector<BagTopic> topics;
  for (const BagConnection& c : conns) topics.push_back({c.topic, c.type});
  return topics;
}


}  // namespace

bool is_ros1_bag(std::string_view bytes) { return bytes.substr(0, kMagic.size()) == kMagic; }

void for_each_bag_message(std::string_view bytes, const std::string& path,
                          const std::function<void(const BagMessageView&)>& visit) {
  BagWalker w(bytes, path);
  w.walk(&visit);
}

BagContents bag_contents(std::string_view bytes, const std::string& path) {
  BagWalker w(bytes, path);
  w.walk(nullptr);
  return {w.connections(), w.decompressed_bytes()};
}

// ROS 1's decoders, for assemble_bag_message.
struct Ros1Decode {
  static DecodedScan scan(ByteReader& r) { return decode_laser_scan(r); }
  static DecodedOdometry odometry(ByteReader& r) { return decode_odometry(r); }
  static std::pair<std::int64_t, Pose2> pose_stamped(ByteReader& r, bool with_covariance) { return decode_pose_stamped(r, with_covariance); }
  static LogImu imu(ByteReader& r) { return decode_imu(r); }
  static void tf(ByteReader& r, std::vector<FrameTransform>& out) { decode_tf(r, out); }
};

RobotLog read_ros1_bag(std::string_view bytes, const std::string& path, const LogReadOptions& o) {
  // The first pass counts every topic's messages, so that the records are judged before any is stored.
  const BagContents contents = bag_contents(bytes, path);
  BagLogAssembler log(bag_topics(contents.connections), o, path, "ros1_bag");
  for (const BagConnection& c : contents.connections) log.count(c.topic, c.messages);
  log.begin(contents.decompressed_bytes);
  std::size_t index = 0;
  std::vector<FrameTransform> transforms;
  for_each_bag_message(bytes, path, [&](const BagMessageView& m) {
    ++index;
    const BagConnection& c = *m.connection;
    const BagTopicUse use = log.use(c.topic);
    if (use == BagTopicUse::Skip) return;
    ByteReader r(m.data, path, 0, c.topic + " message " + std::to_string(index) + " (record at file byte " +
                                      std::to_string(m.file_offset) + "),");
    assemble_bag_message<Ros1Decode>(log, use, c.type, r, index, transforms);
  });
  return log.finish();
}

PointCloudBagIndex index_point_cloud_bag(std::string_view bytes, const std::string& path, const PointCloudBagOptions& o) {
  const BagContents contents = bag_contents(bytes, path);
  const std::vector<BagConnection>& conns = contents.connections;
  PointCloudBagIndex ix;
  choose_point_cloud_topics(bag_topics(conns), o, path, ix);
  std::vector<FrameTransform> statics;
  LogRecordBudget budget(path, contents.decompressed_bytes);
  const auto charge = [&](std::size_t bytes) {
    budget.charge(bytes, [&] {
      return std::to_string(ix.cloud_stamps_us.size()) + " cloud stamps, " + std::to_string(ix.odometry.size()) + " odometry, " +
             std::to_string(ix.truth.size()) + " ground-truth and " + std::to_string(statics.size()) + " static transform records";
    });
  };
  std::size_t index = 0;
  for_each_bag_message(bytes, path, [&](const BagMessageView& m) {
    ++index;
    const BagConnection& c = *m.connection;
    if (c.topic != ix.cloud_topic && c.topic != ix.odom_topic && c.topic != ix.truth_topic &&
        !(c.type == "tf2_msgs/TFMessage" && frame_name(c.topic) == "tf_static"))
      return;
    ByteReader r(m.data, path, 0, c.topic + " message " + std::to_string(index) + " (record at file byte " +
                                      std::to_string(m.file_offset) + "),");
    if (c.topic == ix.cloud_topic) {
      // Only the header: the points are decoded when streamed.
      const StampedHeader h = read_header(r);
      if (ix.cloud_frame.empty()) ix.cloud_frame = frame_name(h.frame_id);
      charge(sizeof(std::int64_t));
      ix.cloud_stamps_us.push_back(h.stamp_us);
    } else if (c.topic == ix.odom_topic) {
      DecodedOdometry d = decode_odometry(r);
      if (ix.base_frame.empty()) ix.base_frame = frame_name(d.child_frame_id);
      d.odometry.source_index = index;
      charge(sizeof(LogOdometry));
      ix.odometry.push_back(d.odometry);
    } else if (c.topic == ix.truth_topic) {
      const DecodedOdometry d = decode_odometry(r);
      charge(sizeof(StampedPose3));
      ix.truth.push_back({d.odometry.stamp_us, d.pose3});
    } else {
      const std::size_t before = statics.size();
      decode_tf(r, statics);
      charge((statics.size() - before) * sizeof(FrameTransform));
    }
  });
  if (ix.base_frame.empty()) ix.base_frame = "base_link";
  if (!ix.cloud_frame.empty() && !statics.empty()) ix.sensor_in_base = transform_chain(statics, ix.base_frame, ix.cloud_frame);
  return ix;
}

void for_each_bag_point_cloud(std::string_view bytes, const std::string& path, const PointCloudBagIndex& ix,
                              const std::function<void(BagPointCloud&&)>& visit) {
  std::size_t index = 0;
  for_each_bag_message(bytes, path, [&](const BagMessageView& m) {
    ++index;
    if (m.connection->topic != ix.cloud_topic) return;
    ByteReader r(m.data, path, 0, m.connection->topic + " message " + std::to_string(index) + " (record at file byte " +
                                      std::to_string(m.file_offset) + "),");
    BagPointCloud c = decode_point_cloud2(r);
    c.source_index = index;
    visit(std::move(c));
  });
}

}  // namespace starnav
