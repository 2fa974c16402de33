#include "starnav/logs/bag_log.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <set>
#include <type_traits>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

constexpr std::string_view kLaserScan = "sensor_msgs/LaserScan", kOdometry = "nav_msgs/Odometry", kImu = "sensor_msgs/Imu",
                           kTf = "tf2_msgs/TFMessage", kPoseStamped = "geometry_msgs/PoseStamped",
                           kPoseWithCovariance = "geometry_msgs/PoseWithCovarianceStamped";

std::string topic_list(const std::set<std::string>& topics) {
  std::string list;
  for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + printable(t, 200);
  return list;
}

template <class Pose>
std::optional<Pose> chain(const std::vector<FrameTransform>& tfs, const std::string& from, const std::string& to) {
  const auto of = [](const FrameTransform& t) -> const Pose& {
    if constexpr (std::is_same_v<Pose, Pose2>) return t.pose;
    else return t.pose3;
  };
  // Each frame's transforms in file order, so that a breadth-first walk visits each transform at
  // most twice (a bag's many frames cost their number, not its square).
  std::map<std::string_view, std::vector<std::size_t>> touching;
  for (std::size_t i = 0; i < tfs.size(); ++i) {
    touching[tfs[i].parent].push_back(i);
    if (tfs[i].child != tfs[i].parent) touching[tfs[i].child].push_back(i);
  }
  std::map<std::string, Pose> reached{{from, Pose()}};
  std::deque<std::string> queue{from};
  while (!queue.empty()) {
    const std::string f = queue.front();
    queue.pop_front();
    if (f == to) return reached[f];
    const auto links = touching.find(f);
    if (links == touching.end()) continue;
    for (const std::size_t i : links->second) {
      const FrameTransform& t = tfs[i];
      if (t.parent == f && !reached.count(t.child)) {
        reached[t.child] = reached[f].compose(of(t));
        queue.push_back(t.child);
      } else if (t.child == f && !reached.count(t.parent)) {
        reached[t.parent] = reached[f].compose(of(t).inverse());
        queue.push_back(t.parent);
      }
    }
  }
  return std::nullopt;
}

const char* use_name(BagTopicUse use) {
  switch (use) {
    case BagTopicUse::Scan: return "scan";
    case BagTopicUse::Odometry: return "odometry";
    case BagTopicUse::OdometryTf: return "odometry (tf)";
    case BagTopicUse::Truth: return "truth";
    case BagTopicUse::Imu: return "imu";
    case BagTopicUse::TfStatic: return "tf_static";
    case BagTopicUse::Skip: break;
  }
  return "";
}

}  // namespace

std::string ros1_type_name(std::string_view type) {
  const std::size_t slash = type.find("/msg/");
  if (slash == std::string_view::npos) return std::string(type);
  return std::string(type.substr(0, slash)) + "/" + std::string(type.substr(slash + 5));
}

std::string frame_name(std::string_view frame) {
  while (!frame.empty() && frame.front() == '/') frame.remove_prefix(1);
  return std::string(frame);
}

double yaw_of_quaternion(double x, double y, double z, double w) {
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

Pose3 pose3_of(double x, double y, double z, double qx, double qy, double qz, double qw) {
  Pose3 p;
  p.position = Vec3(x, y, z);
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  const double n = q.norm();
  p.orientation = n > 1e-9 && std::isfinite(n) ? q.normalized() : Eigen::Quaterniond::Identity();
  return p;
}

std::optional<Pose2> planar_transform_chain(const std::vector<FrameTransform>& transforms, const std::string& from,
                                            const std::string& to) {
  return chain<Pose2>(transforms, from, to);
}

std::optional<Pose3> transform_chain(const std::vector<FrameTransform>& transforms, const std::string& from,
                                     const std::string& to) {
  return chain<Pose3>(transforms, from, to);
}

std::string choose_bag_topic(const std::vector<BagTopic>& topics, const std::string& type, const std::string& wanted,
                             const std::string& path, const char* flag) {
  std::set<std::string> of_type;
  for (const BagTopic& t : topics)
    if (ros1_type_name(t.type) == type) of_type.insert(t.name);
  if (!wanted.empty()) {
    if (!of_type.count(wanted))
      throw Error("no " + type + " topic '" + printable(wanted, 200) + "' in the bag" +
                      (of_type.empty() ? "" : " (it has " + topic_list(of_type) + ")"),
                  path, 0, flag);
    return wanted;
  }
  if (of_type.size() > 1) throw Error("several " + type + " topics (" + topic_list(of_type) + "): name one", path, 0, flag);
  return of_type.empty() ? std::string() : *of_type.begin();
}

void choose_point_cloud_topics(const std::vector<BagTopic>& topics, const PointCloudBagOptions& o, const std::string& path,
                               PointCloudBagIndex& ix) {
  ix.cloud_topic = choose_bag_topic(topics, "sensor_msgs/PointCloud2", o.cloud_topic, path, "--cloud-topic");
  if (ix.cloud_topic.empty()) throw Error("has no sensor_msgs/PointCloud2 topic", path, 0, "--cloud-topic");
  if (!o.truth_topic.empty()) ix.truth_topic = choose_bag_topic(topics, std::string(kOdometry), o.truth_topic, path, "--truth-topic");
  if (o.odom_topic.empty() && !ix.truth_topic.empty()) {
    // The truth's topic is not the odometry's: the other Odometry topic, if exactly one.
    std::set<std::string> others;
    for (const BagTopic& t : topics)
      if (ros1_type_name(t.type) == kOdometry && t.name != ix.truth_topic) others.insert(t.name);
    if (others.size() > 1) throw Error("several nav_msgs/Odometry topics besides the truth: name one", path, 0, "--odom-topic");
    if (!others.empty()) ix.odom_topic = *others.begin();
  } else {
    ix.odom_topic = choose_bag_topic(topics, std::string(kOdometry), o.odom_topic, path, "--odom-topic");
  }
  if (!ix.truth_topic.empty() && ix.truth_topic == ix.odom_topic)
    throw Error("the truth topic is also the odometry topic", path, 0, "--truth-topic");
}

ScanCheck check_scan_beams(std::uint64_t beams) {
  if (beams > kMaxScanBeams)
    return {"ranges", std::to_string(beams) + " readings, more than the " + std::to_string(kMaxScanBeams) + " a scan may have"};
  return {};
}

ScanCheck check_scan_fields(const LogScan& s) {
  if (const std::optional<ScanFault> f = scan_fault(s)) return {f->field, f->what};
  return {};
}

ScanCheck add_cloud_field(CloudLayout& layout, std::string_view name, std::uint32_t offset, std::uint8_t datatype) {
  constexpr std::uint8_t kFloat32 = 7, kFloat64 = 8;
  const int axis = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
  if (axis < 0 || layout.xyz[axis].found) return {};
  if (datatype != kFloat32 && datatype != kFloat64)
    return {"fields." + std::string(name), "datatype " + std::to_string(datatype) + ", expected FLOAT32 (7) or FLOAT64 (8)"};
  layout.xyz[axis] = {offset, datatype, true};
  return {};
}

ScanCheck check_cloud_layout(const CloudLayout& c, std::size_t size) {
  for (int a = 0; a < 3; ++a)
    if (!c.xyz[a].found) return {"fields", std::string("no '") + "xyz"[a] + "' field"};
  for (const CloudLayout::Field& f : c.xyz)
    if (std::uint64_t{f.offset} + (f.datatype == 7 ? 4u : 8u) > c.point_step)
      return {"point_step", "a coordinate field lies beyond point_step " + std::to_string(c.point_step)};
  if (c.height > 0 && c.width > 0) {
    if (c.width > size / c.point_step) return {"data", std::to_string(size) + " bytes hold fewer than width points"};
    if (c.row_step < c.width * c.point_step) return {"row_step", "smaller than width x point_step"};
    if (c.height > size / c.row_step || (c.height - 1) * c.row_step + c.width * c.point_step > size)
      return {"data", std::to_string(size) + " bytes hold fewer than height x width points"};
  }
  return {};
}

void cloud_points(const CloudLayout& c, std::string_view data, std::vector<Vec3>& points, std::size_t& dropped) {
  const auto coordinate = [&](const char* p, const CloudLayout::Field& f) {
    char b[8];
    const std::size_t n = f.datatype == 7 ? 4 : 8;
    std::memcpy(b, p + f.offset, n);
    if (c.big_endian) std::reverse(b, b + n);
    if (n == 4) {
      float v;
      std::memcpy(&v, b, 4);
      return static_cast<double>(v);
    }
    double v;
    std::memcpy(&v, b, 8);
    return v;
  };
  points.reserve(points.size() + static_cast<std::size_t>(c.height * c.width));
  for (std::uint64_t row = 0; row < c.height; ++row)
    for (std::uint64_t col = 0; col < c.width; ++col) {
      const char* p = data.data() + row * c.row_step + col * c.point_step;
      const Vec3 v(coordinate(p, c.xyz[0]), coordinate(p, c.xyz[1]), coordinate(p, c.xyz[2]));
      if (v.allFinite()) points.push_back(v);
      else ++dropped;
    }
}

BagLogAssembler::BagLogAssembler(const std::vector<BagTopic>& topics, const LogReadOptions& o, std::string path,
                                 std::string format)
    : options_(o) {
  log_.path = std::move(path);
  log_.format = std::move(format);
  const std::string& p = log_.path;
  for (const BagTopic& t : topics) types_.emplace(t.name, t.type);
  const auto type_of_name = [&](const std::string& name) {
    const auto it = types_.find(name);
    return it == types_.end() ? std::string() : ros1_type_name(it->second);
  };

  const std::string scan = choose_bag_topic(topics, std::string(kLaserScan), o.scan_topic, p, "--scan-topic");
  if (scan.empty() && !o.allow_no_scans) throw Error("has no sensor_msgs/LaserScan topic", p, 0, "--scan-topic");
  if (!scan.empty()) uses_[scan] = BagTopicUse::Scan, log_.params["scan_topic"] = scan;

  std::string odom;
  if (!o.odom_topic.empty() && type_of_name(o.odom_topic) == kTf) {
    odom = o.odom_topic;
    uses_[odom] = BagTopicUse::OdometryTf;
  } else {
    odom = choose_bag_topic(topics, std::string(kOdometry), o.odom_topic, p, "--odom-topic");
    if (!odom.empty()) {
      uses_[odom] = BagTopicUse::Odometry;
      log_.params["odom_topic"] = odom;
    } else {
      for (const BagTopic& t : topics)
        if (frame_name(t.name) == "tf" && ros1_type_name(t.type) == kTf) odom = t.name, uses_[odom] = BagTopicUse::OdometryTf;
    }
  }

  std::string imu;
  if (!o.imu_topic.empty()) {
    imu = choose_bag_topic(topics, std::string(kImu), o.imu_topic, p, "--imu-topic");
  } else {
    std::set<std::string> imus;
    for (const BagTopic& t : topics)
      if (ros1_type_name(t.type) == kImu) imus.insert(t.name);
    if (imus.size() == 1) imu = *imus.begin();
    else if (imus.size() > 1) warn("several sensor_msgs/Imu topics (" + topic_list(imus) + "): none read; --imu-topic names one");
  }
  if (!imu.empty()) uses_[imu] = BagTopicUse::Imu, log_.params["imu_topic"] = imu;

  if (!o.truth_topic.empty()) {
    const std::string type = type_of_name(o.truth_topic);
    if (type != kOdometry && type != kPoseStamped && type != kPoseWithCovariance)
      throw Error("'" + printable(o.truth_topic, 200) + "' is " + (type.empty() ? "not a topic of the bag" : "of type " + printable(type, 200)) +
                      "; the truth is a nav_msgs/Odometry, geometry_msgs/PoseStamped or PoseWithCovarianceStamped topic",
                  p, 0, "--truth-topic");
    if (o.truth_topic == odom) throw Error("the truth topic is also the odometry topic", p, 0, "--truth-topic");
    uses_[o.truth_topic] = BagTopicUse::Truth;
    log_.params["truth_topic"] = o.truth_topic;
  }
  for (const BagTopic& t : topics)
    if (frame_name(t.name) == "tf_static" && ros1_type_name(t.type) == kTf && !uses_.count(t.name))
      uses_[t.name] = BagTopicUse::TfStatic;
}

BagTopicUse BagLogAssembler::use(const std::string& topic) const {
  const auto it = uses_.find(topic);
  return it == uses_.end() ? BagTopicUse::Skip : it->second;
}

const std::string& BagLogAssembler::type_of(const std::string& topic) const {
  static const std::string none;
  const auto it = types_.find(topic);
  return it == types_.end() ? none : it->second;
}

void BagLogAssembler::count(const std::string& topic, std::size_t messages) {
  counts_[topic] += messages;
  if (use(topic) == BagTopicUse::Skip) log_.skipped[topic + " (" + type_of(topic) + ")"] += messages;
}

void BagLogAssembler::begin(std::uint64_t source_bytes) {
  budget_.emplace(log_.path, source_bytes, options_.record_limit_bytes);
  std::size_t scans = 0, odometry = 0, truth = 0, imu = 0;
  std::string scan_topic;
  for (const auto& [topic, u] : uses_) {
    const std::size_t n = counts_[topic];
    if (u == BagTopicUse::Scan) scans += n, scan_topic = topic;
    else if (u == BagTopicUse::Odometry) odometry += n;
    else if (u == BagTopicUse::Truth) truth += n;
    else if (u == BagTopicUse::Imu) imu += n;
  }
  if (!options_.allow_no_scans && !scan_topic.empty() && scans == 0)
    throw Error("holds no message on its sensor_msgs/LaserScan topic " + printable(scan_topic, 200) + ": nothing to map or localize with",
                log_.path, 0, "--scan-topic");
  // The messages' records, judged from their counts before any is stored (the scans' readings and
  // the transforms are charged as they come).
  budget_->check(scans * sizeof(LogScan) + odometry * sizeof(LogOdometry) + truth * sizeof(LogTruePose) + imu * sizeof(LogImu), [&] {
    return std::to_string(scans) + " scan, " + std::to_string(odometry) + " odometry, " + std::to_string(truth) + " ground-truth and " +
           std::to_string(imu) + " IMU messages";
  });
}

void BagLogAssembler::add_source_bytes(std::uint64_t bytes) {
  if (budget_) budget_->add_source(bytes);
}

std::string BagLogAssembler::stored() const {
  return std::to_string(log_.scans.size()) + " scan, " + std::to_string(log_.odometry.size() + tf_odometry_count_) + " odometry, " +
         std::to_string(log_.truth.size()) + " ground-truth, " + std::to_string(log_.imu.size()) + " IMU and " +
         std::to_string(statics_.size()) + " static transform records";
}

void BagLogAssembler::charge(std::uint64_t bytes) {
  if (!budget_) throw Error("records added before the bag's messages were counted", log_.path);
  budget_->charge(bytes, [&] { return stored(); });
}

void BagLogAssembler::add_scan(LogScan scan, std::string_view frame_id) {
  charge(sizeof(LogScan) + scan.ranges_m.size() * sizeof(float));
  if (laser_frame_.empty()) laser_frame_ = frame_name(frame_id);
  if (options_.range_max_m) scan.range_max_m = *options_.range_max_m;
  if (options_.flaser_beam_angles) set_flaser_beam_angles(scan, scan.ranges_m.size());
  log_.scans.push_back(std::move(scan));
}

void BagLogAssembler::add_odometry(LogOdometry odometry, std::string_view child_frame_id) {
  charge(sizeof(LogOdometry));
  if (base_frame_.empty()) base_frame_ = frame_name(child_frame_id);
  log_.odometry.push_back(odometry);
}

void BagLogAssembler::add_transforms(const std::vector<FrameTransform>& transforms, BagTopicUse use, std::size_t source_index) {
  for (const FrameTransform& t : transforms) {
    if (use == BagTopicUse::TfStatic) {
      // /tf_static is latched: recorders repeat it. One transform per pair of frames is kept (the
      // first, which the chain would take).
      if (static_pairs_.count({t.parent, t.child})) continue;
      charge(sizeof(FrameTransform) + 2 * (t.parent.size() + t.child.size()));
      static_pairs_.emplace(t.parent, t.child);
      statics_.push_back(t);
    } else if (use == BagTopicUse::OdometryTf && t.parent == "odom") {
      charge(sizeof(LogOdometry));
      LogOdometry o;
      o.stamp_us = t.stamp_us;
      o.pose = t.pose;
      o.source_index = source_index;
      tf_odometry_[t.child].push_back(o);
      ++tf_odometry_count_;
    }
  }
}

void BagLogAssembler::add_truth(std::int64_t stamp_us, const Pose2& pose) {
  charge(sizeof(LogTruePose));
  LogTruePose t;
  t.stamp_us = stamp_us;
  t.pose = pose;
  log_.truth.push_back(t);
}

void BagLogAssembler::add_imu(LogImu imu) {
  charge(sizeof(LogImu));
  log_.imu.push_back(std::move(imu));
}

RobotLog BagLogAssembler::finish() {
  for (const auto& [topic, use] : uses_) {
    if (use != BagTopicUse::OdometryTf) continue;
    std::string child;
    if (tf_odometry_.count("base_link")) child = "base_link";
    else if (tf_odometry_.count("base_footprint")) child = "base_footprint";
    else if (tf_odometry_.size() == 1) child = tf_odometry_.begin()->first;
    if (!child.empty()) {
      log_.odometry = std::move(tf_odometry_[child]);
      base_frame_ = child;
      log_.params["odom_topic"] = topic + " (odom -> " + child + ")";
    } else if (!tf_odometry_.empty()) {
      std::set<std::string> children;
      for (const auto& [c, readings] : tf_odometry_) children.insert(c);
      warn(topic + ": several frames below odom (" + topic_list(children) + ") and none is base_link or base_footprint: no odometry read");
    } else if (!options_.odom_topic.empty()) {
      warn(topic + ": no transform from the frame odom: no odometry read");
    }
  }
  if (base_frame_.empty()) base_frame_ = "base_link";
  if (!laser_frame_.empty() && !statics_.empty()) {
    log_.laser_in_base = planar_transform_chain(statics_, base_frame_, laser_frame_);
    if (log_.laser_in_base) log_.params["laser_frame"] = base_frame_ + " -> " + laser_frame_;
  }
  if (!log_.truth.empty()) {
    const std::vector<LogOdometry> sorted = sort_by_time(log_.odometry);
    for (LogTruePose& t : log_.truth) t.odometry = odometry_at(sorted, t.stamp_us).value_or(Pose2());
  }
  for (const auto& [name, type] : types_) log_.topics.push_back({name, type, counts_[name], use_name(use(name))});
  return std::move(log_);
}

}  // namespace starnav
