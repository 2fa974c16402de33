// ROS 2 recordings (logs/ros2_bag.hpp): rosbag2's own test bags listed as their metadata.yaml
// states; the Freiburg ROS 1 bags converted to MCAP (zstd, lz4, plain, without summary, split) and
// SQLite3 by the independent JavaScript converter (tools/ros2-convert) read scan for scan and stamp
// for stamp as the ROS 1 originals; a recording cut short; odometry from /tf; CDR in both byte
// orders; and malformed recordings and messages refused in one line naming the file and field.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <set>

#include "logs/bag_writer.hpp"
#include "logs/cdr_writer.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/bag_log.hpp"
#include "starnav/logs/cdr.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/logs/ros2_bag.hpp"
#include "starnav/logs/zstd_codec.hpp"
#include "support/ros2_convert.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

// ---- rosbag2's test bags ------------------------------------------------------------------------

TEST(Ros2TestBags, ListTheTopicsTypesAndCountsTheirMetadataStates) {
  const fs::path root = test::test_data("rosbag2");
  int folders = 0;
  for (const char* storage : {"mcap", "sqlite3"}) {
    for (const auto& entry : fs::directory_iterator(root / storage)) {
      ++folders;
      const std::string folder = entry.path().string();
      const YAML::Node info = YAML::LoadFile(folder + "/metadata.yaml")["rosbag2_bagfile_information"];
      std::map<std::string, std::pair<std::string, std::uint64_t>> stated;
      for (const YAML::Node& t : info["topics_with_message_count"])
        stated[t["topic_metadata"]["name"].as<std::string>()] = {t["topic_metadata"]["type"].as<std::string>(), t["message_count"].as<std::uint64_t>()};
      LogReadOptions o;
      o.allow_no_scans = true;
      const RobotLog log = read_robot_log(folder, o);
      EXPECT_EQ(log.format, std::string("ros2_") + storage) << folder;
      std::map<std::string, std::pair<std::string, std::uint64_t>> listed;
      for (const LogTopic& t : log.topics) listed[t.name] = {t.type, t.messages};
      EXPECT_EQ(listed, stated) << folder;
      EXPECT_TRUE(log.warnings.empty()) << folder << ": " << (log.warnings.empty() ? "" : log.warnings.front());
      // A folder of one file: the file alone lists the same.
      const YAML::Node files = info["relative_file_paths"];
      if (files.size() == 1) {
        const RobotLog single = read_robot_log(folder + "/" + files[0].as<std::string>(), o);
        std::map<std::string, std::pair<std::string, std::uint64_t>> alone;
        for (const LogTopic& t : single.topics) alone[t.name] = {t.type, t.messages};
        EXPECT_EQ(alone, stated) << folder;
      }
    }
  }
  EXPECT_EQ(folders, 7);
}

TEST(Ros2TestBags, MalformedFoldersNameTheFileAndField) {
  const test::ScratchDir dir;
  const fs::path good = fs::path(test::test_data("rosbag2")) / "mcap" / "talker";
  const auto folder = [&](const std::string& name, const std::string& metadata) {
    const fs::path f = dir.path() / name;
    fs::create_directories(f);
    fs::copy_file(good / "talker.mcap", f / "talker.mcap");
    test::write_text((f / "metadata.yaml").string(), metadata);
    return f.string();
  };
  struct Row {
    std::string name, metadata, field;
  };
  const std::string head = "rosbag2_bagfile_information:\n  version: 4\n";
  for (const Row& r : {Row{"no_info", "other: 1\n", "rosbag2_bagfile_information"},
                       Row{"storage", head + "  storage_identifier: rosbag_v2\n  relative_file_paths: [talker.mcap]\n", "storage_identifier"},
                       Row{"no_files", head + "  storage_identifier: mcap\n", "relative_file_paths"},
                       Row{"escape", head + "  storage_identifier: mcap\n  relative_file_paths: [../../etc/passwd]\n", "relative_file_paths"},
                       Row{"compression", head + "  relative_file_paths: [talker.mcap]\n  compression_format: bz2\n  compression_mode: FILE\n",
                           "compression_format"},
                       Row{"not_yaml", "rosbag2_bagfile_information: [\n", ""}}) {
    const std::string f = folder(r.name, r.metadata);
    LogReadOptions o;
    o.allow_no_scans = true;
    try {
      read_robot_log(f, o);
      ADD_FAILURE() << r.name << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << r.name << ": " << e.what();
      EXPECT_NE(e.file().find("metadata.yaml"), std::string::npos) << e.what();
    }
  }
  // A listed file that is missing is named.
  const std::string missing = folder("missing", head + "  storage_identifier: mcap\n  relative_file_paths: [talker.mcap, gone.mcap]\n");
  LogReadOptions o;
  o.allow_no_scans = true;
  const std::string what = test::error_of([&] { read_robot_log(missing, o); });
  EXPECT_NE(what.find("gone.mcap"), std::string::npos) << what;
}

// ---- The Freiburg logs through the independent converter ---------------------------------------

// Messages of each ROS 1 bag converted: a prefix in CI; every message when STARNAV_ROS2_PREFIX=0
// (scripts/bench-ros2.sh, make bench).
std::size_t converted_prefix() {
  const char* env = std::getenv("STARNAV_ROS2_PREFIX");
  if (env && std::string(env) == "0") return std::numeric_limits<std::size_t>::max();
  return 3000;
}
const std::size_t kPrefix = converted_prefix();

std::string prefix_argument() { return kPrefix == std::numeric_limits<std::size_t>::max() ? "1000000000" : std::to_string(kPrefix); }

std::string freiburg_bag(const std::string& name) { return test::shared_path("datasets/carmen_raw/ros1_bags/" + name + ".orig.bag"); }

void convert(const std::string& bag, const std::string& out, std::vector<std::string> args) {
  args.insert(args.begin(), {bag, out});
  const test::CliResult c = test::run_ros2_tool("convert.mjs", args);
  ASSERT_EQ(c.exit_code, 0) << c.err;
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

// The scans, odometry and mount of `ros2` are those of the first `prefix` messages of `ros1`.
void expect_same_log(const RobotLog& ros1, const RobotLog& ros2, std::size_t prefix, const std::string& what, bool odometry_speeds = true) {
  std::vector<const LogScan*> scans;
  for (const LogScan& s : ros1.scans)
    if (s.source_index <= prefix) scans.push_back(&s);
  std::vector<const LogOdometry*> odometry;
  for (const LogOdometry& o : ros1.odometry)
    if (o.source_index <= prefix) odometry.push_back(&o);
  ASSERT_EQ(ros2.scans.size(), scans.size()) << what;
  ASSERT_EQ(ros2.odometry.size(), odometry.size()) << what;
  ASSERT_GT(scans.size(), 100u) << what;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const LogScan& a = *scans[i];
    const LogScan& b = ros2.scans[i];
    ASSERT_EQ(a.stamp_us, b.stamp_us) << what << " scan " << i;
    ASSERT_EQ(a.angle_min_rad, b.angle_min_rad) << what << " scan " << i;
    ASSERT_EQ(a.angle_increment_rad, b.angle_increment_rad) << what << " scan " << i;
    ASSERT_EQ(a.range_min_m, b.range_min_m) << what << " scan " << i;
    ASSERT_EQ(a.range_max_m, b.range_max_m) << what << " scan " << i;
    ASSERT_TRUE(same_floats(a.ranges_m, b.ranges_m)) << what << " scan " << i;
  }
  for (std::size_t i = 0; i < odometry.size(); ++i) {
    const LogOdometry& a = *odometry[i];
    const LogOdometry& b = ros2.odometry[i];
    ASSERT_EQ(a.stamp_us, b.stamp_us) << what << " odometry " << i;
    ASSERT_EQ(a.pose.x, b.pose.x) << what << " odometry " << i;
    ASSERT_EQ(a.pose.y, b.pose.y) << what << " odometry " << i;
    ASSERT_EQ(a.pose.yaw, b.pose.yaw) << what << " odometry " << i;
    if (odometry_speeds) {
      ASSERT_EQ(a.tv_mps, b.tv_mps) << what << " odometry " << i;
      ASSERT_EQ(a.rv_radps, b.rv_radps) << what << " odometry " << i;
    }
  }
  ASSERT_EQ(ros1.laser_in_base.has_value(), ros2.laser_in_base.has_value()) << what;
  if (ros1.laser_in_base) {
    EXPECT_EQ(ros1.laser_in_base->x, ros2.laser_in_base->x) << what;
    EXPECT_EQ(ros1.laser_in_base->y, ros2.laser_in_base->y) << what;
    EXPECT_EQ(ros1.laser_in_base->yaw, ros2.laser_in_base->yaw) << what;
  }
  // The same pose for every scan, whichever rule (time or file order) scan_odometry takes.
  RobotLog cut = ros1;
  cut.scans.clear();
  cut.odometry.clear();
  for (const LogScan* s : scans) cut.scans.push_back(*s);
  for (const LogOdometry* o : odometry) cut.odometry.push_back(*o);
  const auto pa = scan_odometry(cut), pb = scan_odometry(ros2);
  for (std::size_t i = 0; i < pa.size(); ++i) {
    ASSERT_EQ(pa[i].has_value(), pb[i].has_value()) << what << " scan " << i;
    if (pa[i]) {
      ASSERT_EQ(pa[i]->x, pb[i]->x) << what << " scan " << i;
    }
  }
}

TEST(Ros2Converted, FreiburgLogsReadScanForScanAsTheirRos1Bags) {
  if (test::shared_dir().empty() || !test::have_ros2_tools()) GTEST_SKIP() << "needs ../shared and tools/ros2-convert's npm packages";
  const test::ScratchDir dir;
  struct Variant {
    std::string file;
    std::vector<std::string> args;
  };
  for (const std::string name : {"intel", "fr079", "aces"}) {
    const RobotLog ros1 = read_robot_log(freiburg_bag(name));
    std::vector<Variant> variants = {{name + "-zstd.mcap", {"--storage", "mcap", "--compression", "zstd"}},
                                     {name + "-plain.mcap", {"--storage", "mcap", "--compression", "none"}},
                                     {name + ".db3", {"--storage", "sqlite3"}}};
    if (name == "intel") {
      variants.push_back({name + "-lz4.mcap", {"--storage", "mcap", "--compression", "lz4"}});
      variants.push_back({name + "-nosummary.mcap", {"--storage", "mcap", "--no-summary"}});
      variants.push_back({name + "-split-mcap", {"--storage", "mcap", "--split-messages", "700"}});
      variants.push_back({name + "-split-sqlite", {"--storage", "sqlite3", "--split-messages", "700"}});
    }
    for (Variant& v : variants) {
      v.args.insert(v.args.end(), {"--max-messages", prefix_argument()});
      const std::string out = dir.file(v.file);
      convert(freiburg_bag(name), out, v.args);
      const RobotLog ros2 = read_robot_log(out);
      EXPECT_TRUE(ros2.warnings.empty()) << v.file;
      expect_same_log(ros1, ros2, kPrefix, v.file);
      if (v.file.find("split") != std::string::npos) {
        ASSERT_TRUE(fs::exists(fs::path(out) / (v.file + "_4." + (v.file.find("mcap") != std::string::npos ? "mcap" : "db3"))));
      }
    }
  }
}

TEST(Ros2Converted, AFileCutShortReadsUpToItsLastWholeRecord) {
  if (test::shared_dir().empty() || !test::have_ros2_tools()) GTEST_SKIP() << "needs ../shared and tools/ros2-convert's npm packages";
  const test::ScratchDir dir;
  // Small chunks: the converter's chunks hold about 1 MiB; this prefix spans a few of them plain.
  const std::string file = dir.file("intel.mcap");
  convert(freiburg_bag("intel"), file, {"--storage", "mcap", "--compression", "none", "--max-messages", "12000"});
  const std::string bytes = test::read_text(file);
  const RobotLog whole = read_ros2_bag_bytes(bytes, file);
  ASSERT_TRUE(whole.warnings.empty());
  std::size_t previous = 0;
  for (const double fraction : {0.3, 0.6, 0.95}) {
    const std::string cut = bytes.substr(0, static_cast<std::size_t>(fraction * static_cast<double>(bytes.size())));
    const RobotLog part = read_ros2_bag_bytes(cut, "cut.mcap");
    ASSERT_FALSE(part.warnings.empty()) << fraction;
    EXPECT_NE(part.warnings.front().find("cut short"), std::string::npos) << part.warnings.front();
    ASSERT_LE(part.scans.size(), whole.scans.size());
    EXPECT_GE(part.scans.size(), previous) << fraction;
    previous = part.scans.size();
    for (std::size_t i = 0; i < part.scans.size(); ++i) ASSERT_EQ(part.scans[i].stamp_us, whole.scans[i].stamp_us);
  }
  EXPECT_GT(previous, 0u);
  // Cut inside the summary: every message is still there.
  const RobotLog summary_cut = read_ros2_bag_bytes(bytes.substr(0, bytes.size() - 20), "cut.mcap");
  EXPECT_EQ(summary_cut.scans.size(), whole.scans.size());
  EXPECT_FALSE(summary_cut.warnings.empty());
}

TEST(Ros2Converted, OdometryFromTfWhenTheBagHasNoOdometryTopic) {
  if (test::shared_dir().empty() || !test::have_ros2_tools()) GTEST_SKIP() << "needs ../shared and tools/ros2-convert's npm packages";
  const test::ScratchDir dir;
  const RobotLog ros1 = read_robot_log(freiburg_bag("fr079"));
  const std::string out = dir.file("fr079-noodom.db3");
  convert(freiburg_bag("fr079"), out, {"--storage", "sqlite3", "--drop-topic", "/odom", "--max-messages", prefix_argument()});
  const RobotLog ros2 = read_robot_log(out);
  EXPECT_EQ(ros2.params.at("odom_topic"), "/tf (odom -> base_link)");
  // /tf repeats /odom's poses and stamps (SOURCES.md); its speeds are not there.
  expect_same_log(ros1, ros2, kPrefix, "fr079 without /odom", false);
}

// ---- /tf odometry, IMU and truth topics on ROS 1 bags (the same assembly) ------------------------

std::string ros1_imu(std::uint32_t sec, double yaw, double rate) {
  test::Bytes b;
  test::ros_header(b, sec, 0, "imu");
  b.put(0.0).put(0.0).put(std::sin(yaw / 2)).put(std::cos(yaw / 2));
  for (int i = 0; i < 9; ++i) b.put(0.0);
  b.put(0.0).put(0.0).put(rate);
  for (int i = 0; i < 9; ++i) b.put(0.0);
  b.put(0.1).put(0.0).put(9.8);
  for (int i = 0; i < 9; ++i) b.put(0.0);
  return b.s;
}

// tf2_msgs/TFMessage whose transforms carry the stamp `sec`.
std::string ros1_tf(std::uint32_t sec, const std::vector<test::TransformSpec>& transforms) {
  test::Bytes b;
  b.u32(static_cast<std::uint32_t>(transforms.size()));
  for (const test::TransformSpec& t : transforms) {
    test::ros_header(b, sec, 0, t.parent);
    b.str(t.child);
    b.put(t.x).put(t.y).put(0.0);
    b.put(0.0).put(0.0).put(std::sin(t.yaw / 2)).put(std::cos(t.yaw / 2));
  }
  return b.s;
}

std::string ros1_pose_stamped(std::uint32_t sec, double x, double y, double yaw) {
  test::Bytes b;
  test::ros_header(b, sec, 0, "map");
  b.put(x).put(y).put(0.0).put(0.0).put(0.0).put(std::sin(yaw / 2)).put(std::cos(yaw / 2));
  return b.s;
}

TEST(BagTopics, OdometryFromTfImuAndTruthTopics) {
  test::BagWriter w("lz4");
  w.connection({0, "/scan", "sensor_msgs/LaserScan"});
  w.connection({1, "/tf", "tf2_msgs/TFMessage"});
  w.connection({2, "/imu", "sensor_msgs/Imu"});
  w.connection({3, "/ground_truth", "geometry_msgs/PoseStamped"});
  for (std::uint32_t t = 1; t <= 3; ++t) {
    w.message(1, t, 0, ros1_tf(t, {{"odom", "base_link", 0.5 * t, 0.0, 0.1 * t}, {"base_link", "wheel", 0.0, 0.1, 0.0}}));
    w.message(0, t, 0, test::laser_scan(t, 0, "laser", -0.5f, 0.5f, 10.0f, {1.0f, 2.0f, 3.0f}));
    w.message(2, t, 0, ros1_imu(t, 0.2 * t, 0.05));
    w.message(3, t, 0, ros1_pose_stamped(t, 1.0 * t, 2.0, 0.0));
  }
  const std::string bytes = w.bytes();
  const RobotLog log = read_ros1_bag(bytes, "tf.bag");
  ASSERT_EQ(log.odometry.size(), 3u);
  EXPECT_EQ(log.params.at("odom_topic"), "/tf (odom -> base_link)");
  EXPECT_EQ(log.odometry[2].stamp_us, 3'000'000);  // the transform's own header stamp
  EXPECT_NEAR(log.odometry[2].pose.x, 1.5, 1e-12);
  EXPECT_NEAR(log.odometry[2].pose.yaw, 0.3, 1e-12);
  ASSERT_EQ(log.imu.size(), 3u);  // the only Imu topic
  EXPECT_NEAR(*log.imu[1].yaw_rad, 0.4, 1e-12);
  EXPECT_DOUBLE_EQ(log.imu[1].angular_velocity_radps.z(), 0.05);
  EXPECT_DOUBLE_EQ(log.imu[1].linear_acceleration_mps2.z(), 9.8);
  EXPECT_TRUE(log.truth.empty());  // the truth is read only when named
  EXPECT_EQ(log.skipped.at("/ground_truth (geometry_msgs/PoseStamped)"), 3u);

  LogReadOptions o;
  o.truth_topic = "/ground_truth";
  const RobotLog with_truth = read_ros1_bag(bytes, "tf.bag", o);
  ASSERT_EQ(with_truth.truth.size(), 3u);
  EXPECT_DOUBLE_EQ(with_truth.truth[1].pose.x, 2.0);
  EXPECT_NEAR(with_truth.truth[1].odometry.x, 1.0, 1e-12);  // the odometry at the same instant (t = 2 s)
  o.truth_topic = "/imu";
  EXPECT_EQ(test::error_of([&] { read_ros1_bag(bytes, "tf.bag", o); }).find("tf.bag: --truth-topic:"), 0u);
  o.truth_topic.clear();
  o.imu_topic = "/nope";
  EXPECT_NE(test::error_of([&] { read_ros1_bag(bytes, "tf.bag", o); }).find("--imu-topic"), std::string::npos);
}

TEST(BagTopics, Fr079OdometryFromItsTfTopicEqualsItsOdomTopic) {
  const std::string bag = freiburg_bag("fr079");
  if (bag.empty()) GTEST_SKIP() << "needs ../shared";
  const RobotLog odom = read_robot_log(bag);
  LogReadOptions o;
  o.odom_topic = "/tf";
  const RobotLog tf = read_robot_log(bag, o);
  EXPECT_EQ(tf.skipped.count("/tf (tf2_msgs/TFMessage)"), 0u);
  EXPECT_EQ(odom.skipped.at("/tf (tf2_msgs/TFMessage)"), 8951u);
  ASSERT_EQ(tf.odometry.size(), 8951u);
  ASSERT_EQ(tf.odometry.size(), odom.odometry.size());
  for (std::size_t i = 0; i < tf.odometry.size(); ++i) {
    ASSERT_EQ(tf.odometry[i].stamp_us, odom.odometry[i].stamp_us) << i;
    ASSERT_EQ(tf.odometry[i].pose.x, odom.odometry[i].pose.x) << i;
    ASSERT_EQ(tf.odometry[i].pose.y, odom.odometry[i].pose.y) << i;
    ASSERT_EQ(tf.odometry[i].pose.yaw, odom.odometry[i].pose.yaw) << i;
  }
}

// ---- CDR ------------------------------------------------------------------------------------------

std::string cdr_scan(bool big, std::uint32_t nsec, const std::string& frame, const std::vector<float>& ranges, float increment = 0.25f,
                     float range_max = 8.0f) {
  test::CdrBytes c(big);
  c.header(100, nsec, frame);
  c.put(-0.5f).put(0.5f).put(increment).put(0.0f).put(0.1f).put(0.05f).put(range_max);
  c.put(static_cast<std::uint32_t>(ranges.size()));
  for (float r : ranges) c.put(r);
  c.put(std::uint32_t{1}).put(7.0f);  // one intensity
  return c.bytes;
}

std::string cdr_tf(bool big, const std::string& parent, const std::string& child, double x, double yaw) {
  test::CdrBytes c(big);
  c.put(std::uint32_t{1});
  c.header(100, 0, parent).str(child);
  c.put(x).put(0.0).put(0.0).put(0.0).put(0.0).put(std::sin(yaw / 2)).put(std::cos(yaw / 2));
  return c.bytes;
}

TEST(Ros2Cdr, BothByteOrdersAndOddFrameLengthsDecodeAlike) {
  std::vector<RobotLog> logs;
  for (const bool big : {false, true}) {
    McapWriter w("ros2", McapWriter::Compression::None);
    const std::uint16_t scan_schema = w.add_schema("sensor_msgs/msg/LaserScan", "ros2msg", "");
    const std::uint16_t tf_schema = w.add_schema("tf2_msgs/msg/TFMessage", "ros2msg", "");
    const std::uint16_t scan = w.add_channel(scan_schema, "/scan", "cdr");
    const std::uint16_t tf = w.add_channel(tf_schema, "/tf_static", "cdr");
    w.add_message(tf, 1, 1, cdr_tf(big, "/base_link", "laser_f", 0.25, 0.5));
    // Frame names of 1..3 characters shift every later field's alignment.
    w.add_message(scan, 2, 2, cdr_scan(big, 123'456'789, "laser_f", {1.0f, 2.5f, 8.0f}));
    w.add_message(scan, 3, 3, cdr_scan(big, 999'999'999, "l", {3.0f}));
    const std::string bytes = w.finish();
    logs.push_back(read_ros2_bag_bytes(bytes, big ? "big.mcap" : "little.mcap"));
  }
  for (const RobotLog& log : logs) {
    ASSERT_EQ(log.scans.size(), 2u);
    EXPECT_EQ(log.scans[0].stamp_us, 100'123'457);
    EXPECT_EQ(log.scans[1].stamp_us, 101'000'000);
    EXPECT_EQ(log.scans[0].ranges_m, (std::vector<float>{1.0f, 2.5f, 8.0f}));
    EXPECT_FLOAT_EQ(static_cast<float>(log.scans[0].angle_increment_rad), 0.25f);
    EXPECT_FALSE(log.scans[0].returned(2));
    ASSERT_TRUE(log.laser_in_base.has_value());
    EXPECT_DOUBLE_EQ(log.laser_in_base->x, 0.25);
    EXPECT_NEAR(log.laser_in_base->yaw, 0.5, 1e-12);
  }
}

TEST(Ros2Cdr, MalformedMessagesNameTheFieldAndPlace) {
  struct Row {
    std::string type, bytes, field;
  };
  std::string no_nul = cdr_scan(false, 0, "abc", {1.0f});
  no_nul[4 + 8 + 4 + 3] = 'x';  // the frame's terminator
  test::CdrBytes too_many(false);
  too_many.header(0, 0, "l").put(0.0f).put(0.0f).put(0.1f).put(0.0f).put(0.0f).put(0.0f).put(5.0f).put(std::uint32_t{200000});
  test::CdrBytes more_than_left(false);
  more_than_left.header(0, 0, "l").put(0.0f).put(0.0f).put(0.1f).put(0.0f).put(0.0f).put(0.0f).put(5.0f).put(std::uint32_t{1000});
  test::CdrBytes tfs(false);
  tfs.put(std::uint32_t{4000000});
  const std::vector<Row> rows = {
      {"sensor_msgs/msg/LaserScan", std::string("\x00\x01", 2), "encapsulation"},
      {"sensor_msgs/msg/LaserScan", std::string("\x00\x07\x00\x00", 4) + std::string(60, '\0'), "encapsulation"},
      {"sensor_msgs/msg/LaserScan", cdr_scan(false, 0, "l", {1.0f}).substr(0, 20), "angle_min"},
      {"sensor_msgs/msg/LaserScan", no_nul, "header.frame_id"},
      {"sensor_msgs/msg/LaserScan", too_many.bytes, "ranges"},
      {"sensor_msgs/msg/LaserScan", more_than_left.bytes, "ranges"},
      {"sensor_msgs/msg/LaserScan", cdr_scan(false, 0, "l", {1.0f, 2.0f}, 0.0f), "angle_increment"},
      {"sensor_msgs/msg/LaserScan", cdr_scan(false, 0, "l", {1.0f}, 0.1f, 0.0f), "range_max"},
      {"sensor_msgs/msg/LaserScan", cdr_scan(false, 1'000'000'000, "l", {1.0f}), "header.stamp.nanosec"},
      {"tf2_msgs/msg/TFMessage", tfs.bytes, "transforms"},
      {"nav_msgs/msg/Odometry", cdr_tf(false, "a", "b", 0, 0), "pose.covariance"},
  };
  for (const Row& r : rows) {
    try {
      decode_ros2_message(r.type, r.bytes, "x.mcap", "/scan message 1 (record at file byte 80),");
      ADD_FAILURE() << "accepted a message that should fail on " << r.field;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << e.what();
      EXPECT_EQ(e.file(), "x.mcap");
      EXPECT_NE(std::string(e.what()).find("file byte 80"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(decode_ros2_message("std_msgs/msg/String", "", "x", ""));
}

// ---- MCAP and SQLite3 files ----------------------------------------------------------------------

std::string small_mcap(McapWriter::Compression c) {
  McapWriter w("ros2", c, 64);  // chunks of a message or two
  const std::uint16_t schema = w.add_schema("sensor_msgs/msg/LaserScan", "ros2msg", "");
  const std::uint16_t scan = w.add_channel(schema, "/scan", "cdr");
  for (std::uint32_t i = 0; i < 6; ++i) w.add_message(scan, i, i, cdr_scan(false, i * 1000, "laser", {1.0f, 2.0f, 3.0f}));
  return w.finish();
}

TEST(Mcap, IndexedAndScannedReadsAgreeAndCorruptFilesAreRefused) {
  const std::string bytes = small_mcap(McapWriter::Compression::Zstd);
  McapReader indexed(bytes, "a.mcap");
  EXPECT_TRUE(indexed.indexed());
  McapReader scanned(bytes, "a.mcap");
  scanned.ignore_summary();
  std::vector<std::uint64_t> a, b;
  indexed.for_each_message([](const McapChannel&) { return true; }, [&](const McapMessageView& m) { a.push_back(m.log_time_ns); });
  scanned.for_each_message([](const McapChannel&) { return true; }, [&](const McapMessageView& m) { b.push_back(m.log_time_ns); });
  EXPECT_EQ(a, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(a, b);
  EXPECT_EQ(indexed.message_counts().at(0), 6u);

  // The first chunk record: opcode 0x06 after the header, schema and channel records.
  const std::size_t chunk = bytes.find('\x06', 8 + 9);
  struct Row {
    std::string name;
    std::string bytes;
    std::string field;
  };
  std::string bad_compression = bytes;
  bad_compression.replace(bad_compression.find("zstd"), 4, "zip!");
  std::string huge = bytes;
  const std::uint64_t claim = std::uint64_t{1} << 40;
  std::memcpy(huge.data() + chunk + 9 + 16, &claim, 8);  // uncompressed_size
  std::string crc = small_mcap(McapWriter::Compression::None);
  crc[crc.find("laser") + 1] ^= 0x20;  // a record byte inside the first chunk
  const std::vector<Row> rows = {
      {"magic", "\x89MCAP1\r\n", "magic"},
      {"compression", bad_compression, "compression"},
      {"size", huge, "uncompressed_size"},
      {"crc", crc, "uncompressed_crc"},
  };
  for (const Row& r : rows) {
    try {
      McapReader reader(r.bytes, "bad.mcap");
      reader.ignore_summary();
      reader.for_each_message([](const McapChannel&) { return true; }, [](const McapMessageView&) {});
      ADD_FAILURE() << r.name << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << r.name << ": " << e.what();
      EXPECT_EQ(e.file(), "bad.mcap");
    }
  }
}

TEST(Rosbag2Sqlite, HostileDatabasesAreRefusedInOneLine) {
  const test::ScratchDir dir;
  const auto make = [&](const std::string& name, const std::string& sql) {
    const std::string path = dir.file(name);
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
    sqlite3_close(db);
    return path;
  };
  const std::string topics = "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);";
  struct Row {
    std::string name, sql, field;
  };
  for (const Row& r : {Row{"no_messages.db3", topics, "messages"},
                       // A view that would never end: refused before it is queried.
                       Row{"view.db3",
                           topics + "CREATE VIEW messages AS WITH RECURSIVE n(id, topic_id, timestamp, data) AS "
                                    "(SELECT 1, 1, 0, x'00' UNION ALL SELECT id + 1, 1, 0, x'00' FROM n) SELECT * FROM n;",
                           "messages"},
                       Row{"orphan.db3",
                           topics + "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);"
                                    "INSERT INTO messages VALUES (1, 9, 0, x'00');",
                           "messages.topic_id"},
                       Row{"columns.db3", "CREATE TABLE topics(id INTEGER); CREATE TABLE messages(id INTEGER);", "topics"}}) {
    const std::string path = make(r.name, r.sql);
    LogReadOptions o;
    o.allow_no_scans = true;
    try {
      read_robot_log(path, o);
      ADD_FAILURE() << r.name << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << r.name << ": " << e.what();
      EXPECT_EQ(e.file(), path);
    }
  }
}

// ---- What a recording's records may cost, for every bag reader ----------------------------------

// A message of a small recording, serialised for ROS 1 or ROS 2 (CDR).
struct RecordingMessage {
  enum Kind { Scan, Odometry, CutOdometry, TfOdometry } kind;
  std::uint32_t sec;
};

std::string cdr_odometry(std::uint32_t sec, double x) {
  test::CdrBytes c(false);
  c.header(static_cast<std::int32_t>(sec), 0, "odom").str("base_link");
  c.put(x).put(0.0).put(0.0).put(0.0).put(0.0).put(0.0).put(1.0);
  for (int i = 0; i < 36; ++i) c.put(0.0);
  for (int i = 0; i < 6; ++i) c.put(0.0);
  for (int i = 0; i < 36; ++i) c.put(0.0);
  return c.bytes;
}

std::string serialised(const RecordingMessage& m, bool ros2) {
  const double x = 0.1 * m.sec;
  switch (m.kind) {
    case RecordingMessage::Scan:
      return ros2 ? cdr_scan(false, 0, "laser", {1.0f, 2.0f, 3.0f}) : test::laser_scan(m.sec, 0, "laser", -0.5f, 0.5f, 10.0f, {1.0f, 2.0f, 3.0f});
    case RecordingMessage::Odometry: return ros2 ? cdr_odometry(m.sec, x) : test::odometry(m.sec, 0, "base_link", x, 0.0, 0.0, 0.0, 0.0);
    case RecordingMessage::CutOdometry: {
      const std::string whole = ros2 ? cdr_odometry(m.sec, x) : test::odometry(m.sec, 0, "base_link", x, 0.0, 0.0, 0.0, 0.0);
      return whole.substr(0, whole.size() / 2);  // ends inside its pose's covariance
    }
    case RecordingMessage::TfOdometry: return ros2 ? cdr_tf(false, "odom", "base_link", x, 0.0) : ros1_tf(m.sec, {{"odom", "base_link", x, 0.0, 0.0}});
  }
  return {};
}

// The topics: /scan (LaserScan) and /odom (Odometry), or /tf (TFMessage) for TfOdometry messages.
struct RecordingTopic {
  std::string name, ros1_type, ros2_type;
};
const RecordingTopic kScanTopic{"/scan", "sensor_msgs/LaserScan", "sensor_msgs/msg/LaserScan"};
const RecordingTopic kOdomTopic{"/odom", "nav_msgs/Odometry", "nav_msgs/msg/Odometry"};
const RecordingTopic kTfTopic{"/tf", "tf2_msgs/TFMessage", "tf2_msgs/msg/TFMessage"};
const RecordingTopic& topic_of(const RecordingMessage& m) {
  return m.kind == RecordingMessage::Scan ? kScanTopic : m.kind == RecordingMessage::TfOdometry ? kTfTopic : kOdomTopic;
}

// `messages` as a recording of `format` in `dir`: ROS 1 bags (none, bz2, lz4 chunks), MCAP (indexed,
// or cut before its summary so that it is read record by record), SQLite3, and a rosbag2 folder of
// an SQLite3 file whose messages are compressed one by one with zstd. Every topic is declared,
// whether or not it has messages. Returns the path to read.
std::string write_recording(const std::string& format, const std::vector<RecordingMessage>& messages, const test::ScratchDir& dir) {
  const std::vector<RecordingTopic> topics = {kScanTopic, kOdomTopic, kTfTopic};
  if (format.rfind("ros1", 0) == 0) {
    test::BagWriter w(format.substr(5));
    for (std::uint32_t i = 0; i < topics.size(); ++i) w.connection({i, topics[i].name, topics[i].ros1_type});
    for (const RecordingMessage& m : messages) {
      const auto at = std::find_if(topics.begin(), topics.end(), [&](const RecordingTopic& t) { return t.name == topic_of(m).name; });
      w.message(static_cast<std::uint32_t>(at - topics.begin()), m.sec, 0, serialised(m, false));
    }
    const std::string path = dir.file(format + ".bag");
    test::write_text(path, w.bytes());
    return path;
  }
  if (format.rfind("mcap", 0) == 0) {
    McapWriter w("ros2", McapWriter::Compression::Zstd, 256);
    std::map<std::string, std::uint16_t> channels;
    for (const RecordingTopic& t : topics) channels[t.name] = w.add_channel(w.add_schema(t.ros2_type, "ros2msg", ""), t.name, "cdr");
    for (const RecordingMessage& m : messages) w.add_message(channels.at(topic_of(m).name), m.sec, m.sec, serialised(m, true));
    std::string bytes = w.finish();
    if (format == "mcap_unindexed") {
      // Cut at the footer's summary_start: the data section alone, read record by record.
      std::uint64_t summary_start = 0;
      std::memcpy(&summary_start, bytes.data() + bytes.size() - 8 - 20, 8);
      bytes.resize(static_cast<std::size_t>(summary_start));
    }
    const std::string path = dir.file(format + ".mcap");
    test::write_text(path, bytes);
    return path;
  }
  const bool folder = format == "rosbag2_zstd_messages";
  const std::string db = folder ? dir.file("bag") + "/bag_0.db3" : dir.file(format + ".db3");
  if (folder) {
    fs::create_directories(dir.file("bag"));
    test::write_text(dir.file("bag") + "/metadata.yaml",
                     "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n  relative_file_paths: [bag_0.db3]\n"
                     "  compression_format: zstd\n  compression_mode: MESSAGE\n");
  }
  sqlite3* handle = nullptr;
  EXPECT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(handle,
                         "PRAGMA synchronous = OFF; BEGIN;"
                         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);"
                         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  for (std::size_t i = 0; i < topics.size(); ++i)
    EXPECT_EQ(sqlite3_exec(handle, ("INSERT INTO topics VALUES (" + std::to_string(i + 1) + ", '" + topics[i].name + "', '" + topics[i].ros2_type + "', 'cdr');").c_str(),
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
  sqlite3_stmt* insert = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(handle, "INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &insert, nullptr), SQLITE_OK);
  for (const RecordingMessage& m : messages) {
    const auto at = std::find_if(topics.begin(), topics.end(), [&](const RecordingTopic& t) { return t.name == topic_of(m).name; });
    const std::string data = folder ? zstd_compress(serialised(m, true)) : serialised(m, true);
    sqlite3_bind_int64(insert, 1, at - topics.begin() + 1);
    sqlite3_bind_int64(insert, 2, m.sec);
    sqlite3_bind_blob(insert, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(insert), SQLITE_DONE);
    sqlite3_reset(insert);
  }
  sqlite3_finalize(insert);
  EXPECT_EQ(sqlite3_exec(handle, "COMMIT;", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(handle);
  return folder ? dir.file("bag") : db;
}

const std::vector<std::string> kRecordingFormats = {"ros1_none", "ros1_bz2", "ros1_lz4", "mcap_indexed", "mcap_unindexed", "sqlite3",
                                                    "rosbag2_zstd_messages"};

// A recording for scans whose scan topic has no message is refused before its odometry is read: the
// cut odometry message at its end is never reached (`log info`'s allow_no_scans reaches it).
TEST(BagRecords, ARecordingWithoutScansIsRefusedBeforeItsOdometryIsRead) {
  const test::ScratchDir dir;
  std::vector<RecordingMessage> messages;
  for (std::uint32_t t = 1; t <= 20; ++t) messages.push_back({RecordingMessage::Odometry, t});
  messages.push_back({RecordingMessage::CutOdometry, 21});
  for (const std::string& format : kRecordingFormats) {
    SCOPED_TRACE(format);
    const std::string path = write_recording(format, messages, dir);
    LogReadOptions o;
    o.odom_topic = "/odom";
    try {
      read_robot_log(path, o);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "--scan-topic") << e.what();
      EXPECT_NE(e.message().find("holds no message on its sensor_msgs/LaserScan topic /scan"), std::string::npos) << e.what();
    }
    o.allow_no_scans = true;
    try {
      read_robot_log(path, o);
      ADD_FAILURE() << "accepted the cut message";
    } catch (const Error& e) {
      EXPECT_NE(e.field().find("covariance"), std::string::npos) << e.what();
    }
  }
}

// A recording's records are bounded as a text log's (LogRecordBudget; here with a small limit
// instead of its size + 64 MiB): messages counted before any is decoded are refused from their
// count (the cut message at the end is never reached), transforms as they are stored.
TEST(BagRecords, RecordsAreBoundedFromTheirCountsOrAsTheyAreStored) {
  const test::ScratchDir dir;
  std::vector<RecordingMessage> counted{{RecordingMessage::Scan, 1}};
  std::vector<RecordingMessage> transforms{{RecordingMessage::Scan, 1}};
  for (std::uint32_t t = 1; t <= 50; ++t) {
    counted.push_back({RecordingMessage::Odometry, t});
    transforms.push_back({RecordingMessage::TfOdometry, t});
  }
  counted.push_back({RecordingMessage::CutOdometry, 51});
  const std::size_t limit = sizeof(LogScan) + 3 * sizeof(float) + 20 * sizeof(LogOdometry);
  for (const std::string& format : kRecordingFormats) {
    SCOPED_TRACE(format);
    const test::ScratchDir sub;
    LogReadOptions o;
    o.record_limit_bytes = limit;
    const std::string from_counts = test::error_of([&] { read_robot_log(write_recording(format, counted, sub), o); });
    EXPECT_NE(from_counts.find("its 1 scan, 51 odometry, 0 ground-truth and 0 IMU messages would take more than " + std::to_string(limit) +
                               " bytes parsed"),
              std::string::npos)
        << from_counts;
    const test::ScratchDir sub2;
    const std::string path = write_recording(format, transforms, sub2);
    o.odom_topic = "/tf";
    const std::string as_stored = test::error_of([&] { read_robot_log(path, o); });
    EXPECT_NE(as_stored.find("its 1 scan, 20 odometry, 0 ground-truth, 0 IMU and 0 static transform records would take more than"),
              std::string::npos)
        << as_stored;
    // Under the log's own rule (its size + 64 MiB) the same recording is read whole.
    o.record_limit_bytes.reset();
    EXPECT_EQ(read_robot_log(path, o).odometry.size(), 50u);
  }
}

// A message that two entries of an MCAP message index point at is read once.
TEST(BagRecords, AMessageIndexedTwiceIsReadOnce) {
  McapWriter w("ros2", McapWriter::Compression::None);
  const std::uint16_t scan = w.add_channel(w.add_schema("sensor_msgs/msg/LaserScan", "ros2msg", ""), "/scan", "cdr");
  w.add_message(scan, 1, 1, cdr_scan(false, 1000, "laser", {1.0f}));
  w.add_message(scan, 2, 2, cdr_scan(false, 2000, "laser", {2.0f}));
  std::string bytes = w.finish();
  ASSERT_EQ(read_ros2_bag_bytes(bytes, "a.mcap").scans.size(), 2u);
  // The message index right after the chunk (opcode 0x06 after the header, schema and channel
  // records): opcode 0x07, its length, the channel id, then (log_time, offset) pairs.
  const std::size_t chunk = bytes.find('\x06', 8 + 9);
  std::uint64_t chunk_length = 0;
  std::memcpy(&chunk_length, bytes.data() + chunk + 1, 8);
  const std::size_t index = chunk + 9 + static_cast<std::size_t>(chunk_length);
  ASSERT_EQ(bytes[index], '\x07');
  const std::size_t entries = index + 9 + 2 + 4;
  std::memcpy(bytes.data() + entries + 16, bytes.data() + entries, 16);  // the second entry: the first's
  const RobotLog log = read_ros2_bag_bytes(bytes, "a.mcap");
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].ranges_m, std::vector<float>{1.0f});
}

// Positions beyond kMaxCoordinateM are refused by the ROS 2 decoders as by every other reader.
TEST(Ros2Cdr, PositionsFartherThanTheCoordinateLimitAreRefused) {
  test::CdrBytes pose(false);
  pose.header(1, 0, "map").put(0.0).put(-2e9).put(0.0).put(0.0).put(0.0).put(0.0).put(1.0);
  struct Row {
    std::string type, bytes, field;
  };
  for (const Row& r : {Row{"nav_msgs/msg/Odometry", cdr_odometry(1, 1e19), "pose.pose.position"},
                       Row{"tf2_msgs/msg/TFMessage", cdr_tf(false, "base_link", "laser", 1e12, 0.0), "transforms"},
                       Row{"geometry_msgs/msg/PoseStamped", pose.bytes, "pose.position"}}) {
    try {
      decode_ros2_message(r.type, r.bytes, "far.mcap", "message 1,");
      ADD_FAILURE() << r.type << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << e.what();
      EXPECT_NE(std::string(e.what()).find("farther than 1000000000 m"), std::string::npos) << e.what();
    }
  }
}

TEST(Zstd, DecompressionIsBoundedBeforeItAllocates) {
  const std::string zeros(1 << 20, '\0');
  const std::string z = zstd_compress(zeros);
  EXPECT_EQ(zstd_decompress(z, zeros.size(), "z", 0), zeros);
  EXPECT_EQ(zstd_decompress_any(z, "z", 0, zeros.size()), zeros);
  EXPECT_NE(test::error_of([&] { zstd_decompress_any(z, "z", 0, zeros.size() - 1); }).find("more than"), std::string::npos);
  EXPECT_NE(test::error_of([&] { zstd_decompress(z, zeros.size() - 1, "z", 0); }).find("longer than"), std::string::npos);
  EXPECT_NE(test::error_of([&] { zstd_decompress(z.substr(0, z.size() / 2), zeros.size(), "z", 0); }).find("zstd"), std::string::npos);
}

}  // namespace
}  // namespace starnav
