#include "starnav/logs/ros2_bag.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <system_error>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/logs/bag_log.hpp"
#include "starnav/logs/cdr.hpp"
#include "starnav/logs/decompress.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/logs/rosbag2_sqlite.hpp"
#include "starnav/logs/zstd_codec.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMaxMetadataBytes = std::uint64_t{16} << 20;

// ---- CDR messages ---------------------------------------------------------------------------------

struct CdrHeader {
  std::int64_t stamp_us = 0;
  std::string frame_id;
};

CdrHeader read_cdr_header(CdrReader& r) {
  CdrHeader h;
  const auto sec = r.get<std::int32_t>("header.stamp.sec");
  const std::uint32_t nsec = r.u32("header.stamp.nanosec");
  if (nsec >= 1'000'000'000u) r.fail("header.stamp.nanosec", "nanoseconds above 999999999");
  h.stamp_us = static_cast<std::int64_t>(sec) * 1'000'000 + (static_cast<std::int64_t>(nsec) + 500) / 1000;
  h.frame_id = printable(r.string("header.frame_id"), 200);
  return h;
}

// Positions as every reader bounds them (kMaxCoordinateM).
bool plausible_position(const Vec3& p) { return plausible_coordinate(p.x()) && plausible_coordinate(p.y()) && plausible_coordinate(p.z()); }
std::string far_position() { return "lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position"; }

struct CdrQuaternion {
  double x, y, z, w;
};

Vec3 read_vec3(CdrReader& r, const char* field) {
  Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = r.f64(field);
  return v;
}

CdrQuaternion read_quaternion(CdrReader& r, const char* field) {
  CdrQuaternion q{};
  q.x = r.f64(field);
  q.y = r.f64(field);
  q.z = r.f64(field);
  q.w = r.f64(field);
  return q;
}

struct CdrScan {
  LogScan scan;
  std::string frame_id;
};

CdrScan cdr_scan(CdrReader& r) {
  CdrScan d;
  const CdrHeader h = read_cdr_header(r);
  d.frame_id = h.frame_id;
  LogScan& s = d.scan;
  s.stamp_us = h.stamp_us;
  s.angle_min_rad = r.f32("angle_min");
  r.f32("angle_max");
  s.angle_increment_rad = r.f32("angle_increment");
  r.f32("time_increment");
  r.f32("scan_time");
  s.range_min_m = r.f32("range_min");
  s.range_max_m = r.f32("range_max");
  const std::uint32_t n = r.u32("ranges");
  if (const ScanCheck c = check_scan_beams(n); !c) r.fail(c.field, c.what);
  r.align(4, "ranges");
  if (n > r.remaining() / 4) r.fail("ranges", std::to_string(n) + " ranges do not fit the message");
  const std::string_view raw = r.take(std::size_t{n} * 4, "ranges");
  s.ranges_m.resize(n);
  if (n > 0) std::memcpy(s.ranges_m.data(), raw.data(), raw.size());
  if (r.big_endian())
    for (float& v : s.ranges_m) {
      char b[4];
      std::memcpy(b, &v, 4);
      std::reverse(b, b + 4);
      std::memcpy(&v, b, 4);
    }
  const std::uint32_t intensities = r.sequence("intensities", 4);
  r.skip<float>(intensities, "intensities");
  if (const ScanCheck c = check_scan_fields(s); !c) r.fail(c.field, c.what);
  return d;
}

struct CdrOdometry {
  LogOdometry odometry;
  Pose3 pose3;
  std::string child_frame_id;
};

CdrOdometry cdr_odometry(CdrReader& r) {
  CdrOdometry d;
  d.odometry.stamp_us = read_cdr_header(r).stamp_us;
  d.child_frame_id = printable(r.string("child_frame_id"), 200);
  const Vec3 p = read_vec3(r, "pose.pose.position");
  const CdrQuaternion q = read_quaternion(r, "pose.pose.orientation");
  r.skip<double>(36, "pose.covariance");
  d.odometry.tv_mps = r.f64("twist.twist.linear.x");
  r.f64("twist.twist.linear.y");
  r.f64("twist.twist.linear.z");
  r.f64("twist.twist.angular.x");
  r.f64("twist.twist.angular.y");
  d.odometry.rv_radps = r.f64("twist.twist.angular.z");
  r.skip<double>(36, "twist.covariance");
  d.odometry.pose = Pose2(p.x(), p.y(), yaw_of_quaternion(q.x, q.y, q.z, q.w));
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(d.odometry.pose.yaw)) r.fail("pose", "not finite");
  if (!plausible_position(p)) r.fail("pose.pose.position", far_position());
  d.pose3 = pose3_of(p.x(), p.y(), p.z(), q.x, q.y, q.z, q.w);
  return d;
}

LogImu cdr_imu(CdrReader& r) {
  LogImu m;
  m.stamp_us = read_cdr_header(r).stamp_us;
  const CdrQuaternion q = read_quaternion(r, "orientation");
  const double c0 = r.f64("orientation_covariance");
  r.skip<double>(8, "orientation_covariance");
  m.angular_velocity_radps = read_vec3(r, "angular_velocity");
  r.skip<double>(9, "angular_velocity_covariance");
  m.linear_acceleration_mps2 = read_vec3(r, "linear_acceleration");
  r.skip<double>(9, "linear_acceleration_covariance");
  if (c0 != -1.0 && std::isfinite(q.x + q.y + q.z + q.w) && q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w > 1e-9)
    m.yaw_rad = yaw_of_quaternion(q.x, q.y, q.z, q.w);
  return m;
}

void cdr_tf(CdrReader& r, std::vector<FrameTransform>& out) {
  // A transform takes at least 4 + 4 + 4 (stamp, empty frame) + 4 (empty child) + 56 bytes.
  const std::uint32_t n = r.sequence("transforms", 72);
  for (std::uint32_t i = 0; i < n; ++i) {
    FrameTransform t;
    const CdrHeader h = read_cdr_header(r);
    t.stamp_us = h.stamp_us;
    t.parent = frame_name(h.frame_id);
    t.child = frame_name(printable(r.string("child_frame_id"), 200));
    const Vec3 p = read_vec3(r, "transform.translation");
    const CdrQuaternion q = read_quaternion(r, "transform.rotation");
    t.pose = Pose2(p.x(), p.y(), yaw_of_quaternion(q.x, q.y, q.z, q.w));
    t.pose3 = pose3_of(p.x(), p.y(), p.z(), q.x, q.y, q.z, q.w);
    if (!p.allFinite() || !std::isfinite(t.pose.yaw)) r.fail("transforms", "not finite");
    if (!plausible_position(p)) r.fail("transforms", "a translation " + far_position());
    out.push_back(std::move(t));
  }
}

std::pair<std::int64_t, Pose2> cdr_pose_stamped(CdrReader& r, bool with_covariance) {
  const std::int64_t stamp = read_cdr_header(r).stamp_us;
  const Vec3 p = read_vec3(r, "pose.position");
  const CdrQuaternion q = read_quaternion(r, "pose.orientation");
  if (with_covariance) r.skip<double>(36, "pose.covariance");
  const Pose2 pose(p.x(), p.y(), yaw_of_quaternion(q.x, q.y, q.z, q.w));
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(pose.yaw)) r.fail("pose", "not finite");
  if (!plausible_position(p)) r.fail("pose.position", far_position());
  return {stamp, pose};
}

BagPointCloud cdr_point_cloud(CdrReader& r, bool header_only) {
  BagPointCloud c;
  const CdrHeader h = read_cdr_header(r);
  c.stamp_us = h.stamp_us;
  c.frame_id = h.frame_id;
  if (header_only) return c;
  CloudLayout layout;
  layout.height = r.u32("height");
  layout.width = r.u32("width");
  // A field takes at least 4 (empty name) + 4 + 1 + 4 bytes.
  const std::uint32_t nfields = r.sequence("fields", 13);
  for (std::uint32_t i = 0; i < nfields; ++i) {
    const std::string_view name = r.string("fields.name");
    const std::uint32_t offset = r.u32("fields.offset");
    const std::uint8_t datatype = r.u8("fields.datatype");
    r.u32("fields.count");
    if (const ScanCheck e = add_cloud_field(layout, name, offset, datatype); !e) r.fail(e.field, e.what);
  }
  layout.big_endian = r.u8("is_bigendian") != 0;
  layout.point_step = r.u32("point_step");
  layout.row_step = r.u32("row_step");
  const std::uint32_t size = r.sequence("data", 1);
  const std::string_view data = r.take(size, "data");
  r.u8("is_dense");
  if (const ScanCheck e = check_cloud_layout(layout, size); !e) r.fail(e.field, e.what);
  cloud_points(layout, data, c.points, c.dropped);
  return c;
}

std::string where_of(const McapMessageView& m) {
  return std::string(m.in_chunk ? "chunk" : "record") + " at file byte " + std::to_string(m.file_offset);
}

}  // namespace

// ---- Files and folders ----------------------------------------------------------------------------

struct Ros2Bag::File {
  std::string path;
  bool from_disk = true;
  bool compressed = false;  // compression_mode FILE
  std::string bytes;
  std::string_view view;
  std::unique_ptr<McapReader> mcap;
  std::unique_ptr<Rosbag2Sqlite> sqlite;
  bool warned = false;

  void release() {
    if (!from_disk) return;
    mcap.reset();
    sqlite.reset();
    bytes.clear();
    bytes.shrink_to_fit();
    view = {};
  }
};

bool is_ros2_bag_folder(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::is_regular_file(fs::path(path) / "metadata.yaml", ec);
}

bool is_ros2_bag_bytes(std::string_view bytes) { return is_mcap(bytes) || is_sqlite3(bytes); }

namespace {

std::string yaml_string(const YAML::Node& node, const std::string& file, const char* field) {
  if (!node) return {};
  if (!node.IsScalar()) throw Error("expected a string", file, node.Mark().line + 1, field);
  return node.Scalar();
}

}  // namespace

Ros2Bag::Ros2Bag(const std::string& path) : path_(path) {
  if (!is_ros2_bag_folder(path)) {
    auto f = std::make_unique<File>();
    f->path = path;
    files_.push_back(std::move(f));
  } else {
    const std::string meta = (fs::path(path) / "metadata.yaml").string();
    const std::string text = read_input_file(meta, kMaxMetadataBytes);
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw Error("not YAML: " + one_line(e.msg, 200), meta, e.mark.line + 1);
    }
    const YAML::Node info = root.IsMap() ? root["rosbag2_bagfile_information"] : YAML::Node();
    if (!info || !info.IsMap()) throw Error("has no rosbag2_bagfile_information map", meta, 0, "rosbag2_bagfile_information");
    const std::string storage = yaml_string(info["storage_identifier"], meta, "storage_identifier");
    if (!storage.empty() && storage != "mcap" && storage != "sqlite3")
      throw Error("storage '" + printable(storage, 40) + "' is not read (mcap, sqlite3)", meta, 0, "storage_identifier");
    const std::string compression = yaml_string(info["compression_format"], meta, "compression_format");
    std::string mode = yaml_string(info["compression_mode"], meta, "compression_mode");
    std::transform(mode.begin(), mode.end(), mode.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    if (!compression.empty() && compression != "zstd")
      throw Error("compression '" + printable(compression, 40) + "' is not read (zstd)", meta, 0, "compression_format");
    if (!compression.empty() && mode != "FILE" && mode != "MESSAGE")
      throw Error("expected FILE or MESSAGE with compression_format zstd", meta, 0, "compression_mode");
    compressed_messages_ = !compression.empty() && mode == "MESSAGE";
    const YAML::Node paths = info["relative_file_paths"];
    if (!paths || !paths.IsSequence() || paths.size() == 0)
      throw Error("expected a list of the bag's files", meta, 0, "relative_file_paths");
    if (paths.size() > 100000) throw Error("more than 100000 files", meta, 0, "relative_file_paths");
    for (const YAML::Node& p : paths) {
      const std::string rel = yaml_string(p, meta, "relative_file_paths");
      const fs::path rp(rel);
      if (rel.empty() || rp.is_absolute() || std::any_of(rp.begin(), rp.end(), [](const fs::path& c) { return c == ".."; }))
        throw Error("'" + printable(rel, 200) + "' is not a file inside the bag's folder", meta, p.Mark().line + 1, "relative_file_paths");
      fs::path file = fs::path(path) / rp;
      std::error_code ec;
      // Older rosbag2 versions wrote the paths relative to the folder's parent.
      if (!fs::exists(file, ec) && fs::exists(fs::path(path) / rp.filename(), ec)) file = fs::path(path) / rp.filename();
      auto f = std::make_unique<File>();
      f->path = file.string();
      f->compressed = !compression.empty() && mode == "FILE";
      files_.push_back(std::move(f));
    }
    format_ = storage.empty() ? std::string() : "ros2_" + storage;
  }
  for (auto& f : files_) {
    open_file(*f);
    add_topics(*f);
    add_source_bytes(*f);
    if (files_.size() > 1) f->release();
  }
}

void Ros2Bag::add_source_bytes(const File& f) {
  source_bytes_ += f.view.size();
  if (f.mcap) source_bytes_ += f.mcap->chunk_bytes();
}

Ros2Bag::Ros2Bag(std::string_view bytes, const std::string& path) : path_(path) {
  auto f = std::make_unique<File>();
  f->path = path;
  f->from_disk = false;
  f->view = bytes;
  files_.push_back(std::move(f));
  open_file(*files_.front());
  add_topics(*files_.front());
  add_source_bytes(*files_.front());
}

Ros2Bag::~Ros2Bag() = default;

void Ros2Bag::open_file(File& f) {
  if (f.mcap || f.sqlite) return;
  const InputFileScope reading(f.path);
  if (f.from_disk) {
    std::error_code ec;
    if (!fs::exists(f.path, ec)) throw Error("no such file (named by the bag's metadata.yaml)", f.path);
    f.bytes = read_input_file(f.path, kMaxLogFileBytes);
    if (f.compressed) f.bytes = zstd_decompress_any(f.bytes, f.path, 0, kMaxDecompressedBytes);
    f.view = f.bytes;
  }
  if (is_mcap(f.view)) {
    f.mcap = std::make_unique<McapReader>(f.view, f.path);
    if (format_.empty()) format_ = "ros2_mcap";
    if (!f.warned)
      for (const std::string& w : f.mcap->warnings()) warnings_.push_back(f.path + ": " + w);
  } else if (is_sqlite3(f.view)) {
    f.sqlite = std::make_unique<Rosbag2Sqlite>(f.view, f.path);
    if (format_.empty()) format_ = "ros2_sqlite3";
    std::error_code ec;
    if (!f.warned && f.from_disk && fs::file_size(f.path + "-wal", ec) > 0 && !ec)
      warnings_.push_back(f.path + ": its write-ahead log " + f.path + "-wal is not read (messages the recorder had not checkpointed)");
  } else {
    throw Error("neither an MCAP file nor an SQLite3 database", f.path, 0, "magic");
  }
  f.warned = true;
}

void Ros2Bag::add_topics(const File& f) {
  const auto add = [&](const std::string& name, const std::string& type, bool cdr, std::uint64_t n) {
    const auto it = std::find_if(topics_.begin(), topics_.end(), [&](const Ros2Topic& t) { return t.name == name; });
    if (it == topics_.end()) topics_.push_back({name, type, cdr, n});
    else it->messages += n;
  };
  if (f.mcap) {
    for (const auto& [id, c] : f.mcap->channels()) {
      const std::string schema = c.schema ? c.schema->name : std::string();
      const bool cdr = c.message_encoding == "cdr";
      const auto n = f.mcap->message_counts().find(id);
      add(printable(c.topic, 200), cdr ? printable(schema, 200) : printable(schema, 200) + " (" + printable(c.message_encoding, 40) + ")",
          cdr, n == f.mcap->message_counts().end() ? 0 : n->second);
    }
  } else {
    for (const Rosbag2SqliteTopic& t : f.sqlite->topics()) {
      const bool cdr = t.serialization_format == "cdr";
      add(t.name, cdr ? t.type : t.type + " (" + t.serialization_format + ")", cdr, t.messages);
    }
  }
  std::sort(topics_.begin(), topics_.end(), [](const Ros2Topic& a, const Ros2Topic& b) { return a.name < b.name; });
}

void Ros2Bag::for_each_message(const std::function<bool(const Ros2Topic&)>& wanted, const std::function<void(const Ros2Message&)>& visit) {
  std::map<std::string, const Ros2Topic*> by_name;
  for (const Ros2Topic& t : topics_)
    if (t.cdr && wanted(t)) by_name[t.name] = &t;
  if (by_name.empty()) return;
  std::string decompressed;
  const auto deliver = [&](Ros2Message& m) {
    if (compressed_messages_) {
      decompressed = zstd_decompress_any(m.data, *m.file, 0, kMaxDecompressedBytes);
      m.inflated = decompressed.size();
      m.data = decompressed;
    }
    visit(m);
  };
  for (auto& f : files_) {
    open_file(*f);
    const InputFileScope reading(f->path);
    if (f->mcap) {
      std::map<std::uint16_t, const Ros2Topic*> channel_topic;
      for (const auto& [id, c] : f->mcap->channels()) {
        const auto it = by_name.find(printable(c.topic, 200));
        if (it != by_name.end() && c.message_encoding == "cdr") channel_topic[id] = it->second;
      }
      f->mcap->for_each_message([&](const McapChannel& c) { return channel_topic.count(c.id) > 0; },
                                [&](const McapMessageView& v) {
                                  Ros2Message m;
                                  m.topic = channel_topic.at(v.channel->id);
                                  m.time_ns = static_cast<std::int64_t>(std::min<std::uint64_t>(v.log_time_ns, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())));
                                  m.data = v.data;
                                  m.where = where_of(v);
                                  m.file = &f->path;
                                  deliver(m);
                                });
    } else {
      f->sqlite->for_each_message(
          [&](const Rosbag2SqliteTopic& t) { return by_name.count(t.name) > 0 && t.serialization_format == "cdr"; },
          [&](const Rosbag2SqliteMessage& s) {
            Ros2Message m;
            m.topic = by_name.at(s.topic->name);
            m.time_ns = s.timestamp_ns;
            m.data = s.data;
            m.where = "row " + std::to_string(s.row);
            m.file = &f->path;
            deliver(m);
          });
    }
    if (files_.size() > 1) f->release();
  }
}

// ---- Robot logs -----------------------------------------------------------------------------------

namespace {

// ROS 2's (CDR) decoders, for assemble_bag_message.
struct CdrDecode {
  static CdrScan scan(CdrReader& r) { return cdr_scan(r); }
  static CdrOdometry odometry(CdrReader& r) { return cdr_odometry(r); }
  static std::pair<std::int64_t, Pose2> pose_stamped(CdrReader& r, bool with_covariance) { return cdr_pose_stamped(r, with_covariance); }
  static LogImu imu(CdrReader& r) { return cdr_imu(r); }
  static void tf(CdrReader& r, std::vector<FrameTransform>& out) { cdr_tf(r, out); }
};

RobotLog assemble(Ros2Bag& bag, const LogReadOptions& o) {
  std::vector<BagTopic> topics;
  for (const Ros2Topic& t : bag.topics()) topics.push_back({t.name, t.type});
  BagLogAssembler log(topics, o, bag.path(), bag.format());
  for (const Ros2Topic& t : bag.topics()) log.count(t.name, t.messages);
  log.begin(bag.source_bytes());
  std::size_t index = 0;
  std::vector<FrameTransform> transforms;
  bag.for_each_message([&](const Ros2Topic& t) { return log.use(t.name) != BagTopicUse::Skip; },
                       [&](const Ros2Message& m) {
                         ++index;
                         log.add_source_bytes(m.inflated);
                         const std::string& topic = m.topic->name;
                         CdrReader r(m.data, *m.file, topic + " message " + std::to_string(index) + " (" + m.where + "),");
                         const BagTopicUse use = log.use(topic);
                         assemble_bag_message<CdrDecode>(log, use, m.topic->type, r, index, transforms);
                       });
  for (const std::string& w : bag.warnings()) log.warn(w);
  return log.finish();
}

}  // namespace

RobotLog read_ros2_bag(const std::string& path, const LogReadOptions& o) {
  Ros2Bag bag(path);
  return assemble(bag, o);
}

RobotLog read_ros2_bag_bytes(std::string_view bytes, const std::string& path, const LogReadOptions& o) {
  Ros2Bag bag(bytes, path);
  return assemble(bag, o);
}

// ---- Point clouds ---------------------------------------------------------------------------------

PointCloudBagIndex index_ros2_point_cloud_bag(const std::string& path, const PointCloudBagOptions& o) {
  Ros2Bag bag(path);
  std::vector<BagTopic> topics;
  for (const Ros2Topic& t : bag.topics()) topics.push_back({t.name, t.type});
  PointCloudBagIndex ix;
  choose_point_cloud_topics(topics, o, path, ix);
  std::vector<FrameTransform> statics;
  LogRecordBudget budget(path, bag.source_bytes());
  const auto charge = [&](std::size_t bytes) {
    budget.charge(bytes, [&] {
      return std::to_string(ix.cloud_stamps_us.size()) + " cloud stamps, " + std::to_string(ix.odometry.size()) + " odometry, " +
             std::to_string(ix.truth.size()) + " ground-truth and " + std::to_string(statics.size()) + " static transform records";
    });
  };
  std::size_t index = 0;
  bag.for_each_message(
      [&](const Ros2Topic& t) {
        return t.name == ix.cloud_topic || t.name == ix.odom_topic || t.name == ix.truth_topic ||
               (ros1_type_name(t.type) == "tf2_msgs/TFMessage" && frame_name(t.name) == "tf_static");
      },
      [&](const Ros2Message& m) {
        ++index;
        budget.add_source(m.inflated);
        const std::string& topic = m.topic->name;
        CdrReader r(m.data, *m.file, topic + " message " + std::to_string(index) + " (" + m.where + "),");
        if (topic == ix.cloud_topic) {
          const BagPointCloud h = cdr_point_cloud(r, true);
          if (ix.cloud_frame.empty()) ix.cloud_frame = frame_name(h.frame_id);
          charge(sizeof(std::int64_t));
          ix.cloud_stamps_us.push_back(h.stamp_us);
        } else if (topic == ix.odom_topic) {
          CdrOdometry d = cdr_odometry(r);
          if (ix.base_frame.empty()) ix.base_frame = frame_name(d.child_frame_id);
          d.odometry.source_index = index;
          charge(sizeof(LogOdometry));
          ix.odometry.push_back(d.odometry);
        } else if (topic == ix.truth_topic) {
          const CdrOdometry d = cdr_odometry(r);
          charge(sizeof(StampedPose3));
          ix.truth.push_back({d.odometry.stamp_us, d.pose3});
        } else {
          const std::size_t before = statics.size();
          cdr_tf(r, statics);
          charge((statics.size() - before) * sizeof(FrameTransform));
        }
      });
  if (ix.base_frame.empty()) ix.base_frame = "base_link";
  if (!ix.cloud_frame.empty() && !statics.empty()) ix.sensor_in_base = transform_chain(statics, ix.base_frame, ix.cloud_frame);
  return ix;
}

void for_each_ros2_point_cloud(const std::string& path, const PointCloudBagIndex& ix, const std::function<void(BagPointCloud&&)>& visit) {
  Ros2Bag bag(path);
  std::size_t index = 0;
  bag.for_each_message([&](const Ros2Topic& t) { return t.name == ix.cloud_topic; },
                       [&](const Ros2Message& m) {
                         ++index;
                         CdrReader r(m.data, *m.file, m.topic->name + " message " + std::to_string(index) + " (" + m.where + "),");
                         BagPointCloud c = cdr_point_cloud(r, false);
                         c.source_index = index;
                         visit(std::move(c));
                       });
}

bool decode_ros2_message(std::string_view type_name, std::string_view data, const std::string& path, const std::string& where) {
  static const std::set<std::string, std::less<>> decoded = {"sensor_msgs/LaserScan",   "nav_msgs/Odometry",          "sensor_msgs/Imu",
                                                             "tf2_msgs/TFMessage",      "geometry_msgs/PoseStamped",
                                                             "geometry_msgs/PoseWithCovarianceStamped", "sensor_msgs/PointCloud2"};
  const std::string type = ros1_type_name(type_name);
  if (!decoded.count(type)) return false;
  CdrReader r(data, path, where);
  std::vector<FrameTransform> transforms;
  if (type == "sensor_msgs/LaserScan") cdr_scan(r);
  else if (type == "nav_msgs/Odometry") cdr_odometry(r);
  else if (type == "sensor_msgs/Imu") cdr_imu(r);
  else if (type == "tf2_msgs/TFMessage") cdr_tf(r, transforms);
  else if (type == "geometry_msgs/PoseStamped") cdr_pose_stamped(r, false);
  else if (type == "geometry_msgs/PoseWithCovarianceStamped") cdr_pose_stamped(r, true);
  else cdr_point_cloud(r, false);
  return true;
}

}  // namespace starnav
