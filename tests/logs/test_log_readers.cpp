// Robot log readers: stamps and odometry interpolation against closed forms; CARMEN lines of
// every kind and the text extracts on hand-written fixtures; ROS 1 bags written by an independent
// writer (bag_writer.hpp) with plain, bzip2 and LZ4 chunks; a malformed-input table (one error
// naming the file, line or byte, and field); and the benchmark logs of ../shared/ (the counts of
// their SOURCES.md, and bag and text extract agreeing scan by scan).
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "bag_writer.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/decompress.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/ros_bag.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(LogStamps, ParseExactlyAndRoundBeyondMicroseconds) {
  struct Row {
    const char* text;
    std::int64_t us;
  };
  for (const Row& r : {Row{"70.18", 70'180'000}, Row{"1134864629.895182", 1'134'864'629'895'182}, Row{"-0.5", -500'000},
                       Row{"1.0000005", 1'000'001}, Row{"1.0000004", 1'000'000}, Row{"12", 12'000'000}, Row{".25", 250'000},
                       Row{"+3.000001", 3'000'001}, Row{"4.29497e+09", 4'294'970'000'000'000}, Row{"1.08499e-42", 0},
                       Row{"2.5e-6", 3}, Row{"1E3", 1'000'000'000}, Row{"0.0000004999", 0}, Row{"123456789012.1234567", 123'456'789'012'123'457}}) {
    std::int64_t us = 0;
    ASSERT_TRUE(parse_stamp_us(r.text, us)) << r.text;
    EXPECT_EQ(us, r.us) << r.text;
  }
  for (const char* bad : {"", ".", "-", "1e", "1e+", "inf", "nan", "1.2.3", "0x10", "12a", "99999999999999999999", "1e30"}) {
    std::int64_t us = 0;
    EXPECT_FALSE(parse_stamp_us(bad, us)) << bad;
  }
  EXPECT_EQ(format_stamp_us(1'134'864'629'895'182), "1134864629.895182");
  EXPECT_EQ(format_stamp_us(-500'000), "-0.500000");
  EXPECT_EQ(format_stamp_us(70'180'000), "70.180000");
}

TEST(LogOdometryAt, InterpolatesLinearlyTheShortWayRoundAndClampsAtTheEnds) {
  std::vector<LogOdometry> od = {{2'000'000, Pose2(2, 0, 3.0), 0, 0}, {1'000'000, Pose2(0, 0, 0.0), 0, 0},
                                 {3'000'000, Pose2(2, 2, -3.0), 0, 0}};
  od = sort_by_time(od);
  ASSERT_EQ(od[0].stamp_us, 1'000'000);
  const Pose2 a = *odometry_at(od, 1'500'000);
  EXPECT_DOUBLE_EQ(a.x, 1.0);
  EXPECT_DOUBLE_EQ(a.yaw, 1.5);
  // From 3.0 to -3.0 the short way crosses pi: halfway is pi (or -pi).
  const Pose2 b = *odometry_at(od, 2'500'000);
  EXPECT_NEAR(std::abs(b.yaw), kPi, 1e-12);
  EXPECT_DOUBLE_EQ(b.y, 1.0);
  EXPECT_DOUBLE_EQ(odometry_at(od, 0)->x, 0.0);
  EXPECT_DOUBLE_EQ(odometry_at(od, 9'000'000)->y, 2.0);
  EXPECT_FALSE(odometry_at({}, 0).has_value());
}

const char* kCarmen =
    "# CARMEN Logfile\n"
    "PARAM robot_frontlaser_offset 0.25 nohost 0.0\n"
    "ODOM 1.0 2.0 0.5 0.3 0.1 0.0 100.000001 host 0.1\n"
    "FLASER 3 1.0 2.5 81.91 0.0 0.0 0.0 1.0 2.0 0.5 100.100000 host 0.2\n"
    "RAWLASER1 0 -1.5708 3.1416 0.0174533 30.0 0.01 0 2 4.0 5.0 0 100.2 host 0.3\n"
    "ROBOTLASER1 0 -1.0 2.0 0.5 20.0 0.01 0 3 1.5 2.5 3.5 1 9.0 0.1 0.2 0.3 1.0 2.0 0.4 0.5 0.6 0.1 0.1 0.2 100.3 host 0.4\n"
    "TRUEPOS 5.0 6.0 0.7 1.0 2.0 0.5 100.4 host 0.5\n"
    "NMEA $GPGGA whatever\n"
    "RLASER 1 1.0 0 0 0 0 0 0 100.5 host 0.6\n"
    "NMEA $GPGGA again\n";

TEST(CarmenLog, ReadsEveryLineKindAndCountsTheOthers) {
  const RobotLog log = read_carmen_log(kCarmen, "fixture.clf");
  ASSERT_EQ(log.scans.size(), 3u);
  ASSERT_EQ(log.odometry.size(), 1u);
  ASSERT_EQ(log.truth.size(), 1u);
  EXPECT_EQ(log.odometry[0].stamp_us, 100'000'001);
  EXPECT_DOUBLE_EQ(log.odometry[0].pose.yaw, 0.5);
  EXPECT_DOUBLE_EQ(log.odometry[0].tv_mps, 0.3);
  const LogScan& f = log.scans[0];
  EXPECT_EQ(f.stamp_us, 100'100'000);
  EXPECT_EQ(f.source_index, 4u);
  ASSERT_EQ(f.ranges_m.size(), 3u);
  // 3 beams span -90..+90 deg inclusive.
  EXPECT_NEAR(f.angle(0), -kPi / 2, 1e-12);
  EXPECT_NEAR(f.angle(2), kPi / 2, 1e-12);
  ASSERT_TRUE(f.odometry.has_value());
  EXPECT_DOUBLE_EQ(f.odometry->x, 1.0);
  // One FLASER scan holding 81.91 once: no repeated maximum, so every reading counts.
  EXPECT_TRUE(f.returned(2));
  const LogScan& raw = log.scans[1];
  EXPECT_DOUBLE_EQ(raw.angle_min_rad, -1.5708);
  EXPECT_DOUBLE_EQ(raw.range_max_m, 30.0);
  EXPECT_EQ(raw.ranges_m.size(), 2u);
  const LogScan& robot = log.scans[2];
  ASSERT_TRUE(robot.laser_pose && robot.odometry);
  EXPECT_DOUBLE_EQ(robot.laser_pose->x, 0.1);
  EXPECT_DOUBLE_EQ(robot.odometry->yaw, 0.4);
  EXPECT_EQ(robot.stamp_us, 100'300'000);
  EXPECT_DOUBLE_EQ(log.truth[0].pose.x, 5.0);
  ASSERT_TRUE(log.laser_in_base.has_value());
  EXPECT_DOUBLE_EQ(log.laser_in_base->x, 0.25);
  EXPECT_EQ(log.skipped.at("NMEA"), 2u);
  EXPECT_EQ(log.skipped.at("RLASER"), 1u);
}

TEST(CarmenLog, FlaserLayoutsAndTheRepeatedMaximumAsNoReturn) {
  std::string text;
  for (int i = 0; i < 20; ++i) {
    text += "FLASER 180";
    for (int b = 0; b < 180; ++b) text += b % 9 == 0 ? " 81.91" : " 3.25";
    text += " 0 0 0 0 0 0 " + std::to_string(10 + i) + ".5 h 0\n";
  }
  const RobotLog log = read_carmen_log(text, "f.clf");
  ASSERT_EQ(log.scans.size(), 20u);
  const LogScan& s = log.scans[0];
  EXPECT_NEAR(s.angle_increment_rad, deg_to_rad(1.0), 1e-15);
  EXPECT_NEAR(s.angle(179), deg_to_rad(89.0), 1e-12);
  EXPECT_FALSE(s.returned(0));  // 81.91 repeats: the no-return value
  EXPECT_TRUE(s.returned(1));
  LogReadOptions o;
  o.range_max_m = 100.0;
  EXPECT_TRUE(read_carmen_log(text, "f.clf", o).scans[0].returned(0));
  LogScan s360, s361;
  set_flaser_beam_angles(s360, 360);
  set_flaser_beam_angles(s361, 361);
  EXPECT_NEAR(s360.angle_min_rad + 359 * s360.angle_increment_rad, deg_to_rad(89.5), 1e-12);
  EXPECT_NEAR(s361.angle_min_rad + 360 * s361.angle_increment_rad, deg_to_rad(90.0), 1e-12);
}

// A log of 20 scans of 180 beams, every ninth at the sensor's no-return value 81.91 m, the others
// at 3.25 m; `edit` changes the reading of scan 3, beam 9 (a no-return one).
std::string saturated_log(bool text_extract, const std::string& edit = "") {
  std::string out;
  for (int i = 0; i < 20; ++i) {
    out += text_extract ? "LASERSCAN " + std::to_string(10 + i) + ".5 180" : std::string("FLASER 180");
    for (int b = 0; b < 180; ++b) out += " " + (i == 3 && b == 9 && !edit.empty() ? edit : b % 9 == 0 ? std::string("81.91") : std::string("3.25"));
    out += text_extract ? "\n" : " 0 0 0 0 0 0 " + std::to_string(10 + i) + ".5 h 0\n";
  }
  return out;
}

TEST(CarmenLog, TheNoReturnValueIsTheLargestRepeatedReadingWhateverStraysLieAbove) {
  for (const bool text : {false, true}) {
    SCOPED_TRACE(text ? "text extract" : "CARMEN");
    const auto read = [&](const std::string& log_text, std::vector<std::string>* warnings) {
      LogReadOptions o;
      if (warnings) o.warn = [warnings](const std::string& w) { warnings->push_back(w); };
      return text ? read_odomscan_text(log_text, "s.txt", o) : read_carmen_log(log_text, "s.clf", o);
    };
    std::vector<std::string> warnings;
    const RobotLog clean = read(saturated_log(text), &warnings);
    EXPECT_FLOAT_EQ(static_cast<float>(clean.scans[0].range_max_m), 81.91f);
    EXPECT_TRUE(warnings.empty());
    // One reading 0.01 m above the no-return value used to make every no-return reading a wall.
    const RobotLog stray = read(saturated_log(text, "81.92"), &warnings);
    EXPECT_FLOAT_EQ(static_cast<float>(stray.scans[0].range_max_m), 81.91f);
    EXPECT_FALSE(stray.scans[3].returned(9));
    EXPECT_FALSE(stray.scans[0].returned(0));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("1 readings lie above the no-return value 81.91"), std::string::npos) << warnings[0];
    // No value repeats at the top: every reading a return, with a word when the log is long.
    const auto distinct = [](int scans) {
      std::string out;
      for (int i = 0; i < scans; ++i) {
        out += "FLASER 180";
        for (int b = 0; b < 180; ++b) out += " " + std::to_string(1.0 + 0.0001 * (i * 180 + b));
        out += " 0 0 0 0 0 0 " + std::to_string(10 + i) + ".5 h 0\n";
      }
      return out;
    };
    if (!text) {
      warnings.clear();
      const RobotLog short_log = read(distinct(20), &warnings);
      EXPECT_TRUE(short_log.scans[19].returned(179));  // the largest reading is a return
      EXPECT_TRUE(warnings.empty());
      read(distinct(300), &warnings);
      ASSERT_EQ(warnings.size(), 1u);
      EXPECT_NE(warnings[0].find("every reading counts as a return"), std::string::npos) << warnings[0];
      warnings.clear();
    }
    // Nine repeats of a larger value are strays still (fewer than 10).
    std::string nine = saturated_log(text);
    for (int k = 0; k < 9; ++k) nine.replace(nine.find(" 3.25"), 5, " 90.5");
    EXPECT_FLOAT_EQ(static_cast<float>(read(nine, nullptr).scans[0].range_max_m), 81.91f);
    // A value beyond a float: an error at its line, not an infinite reading.
    try {
      read(saturated_log(text, "1e308"), nullptr);
      ADD_FAILURE() << "accepted 1e308";
    } catch (const Error& e) {
      EXPECT_EQ(e.line(), 4);
      EXPECT_EQ(e.field(), text ? "LASERSCAN range" : "FLASER range");
    }
    // No value repeats at the top: every reading counts (a short log: without a word).
    std::string distinct_short;
    for (int i = 0; i < 5; ++i) {
      distinct_short += text ? "LASERSCAN " + std::to_string(i) + ".5 3" : std::string("FLASER 3");
      for (int b = 0; b < 3; ++b) distinct_short += " " + std::to_string(1.0 + 0.01 * (3 * i + b));
      distinct_short += text ? "\n" : " 0 0 0 0 0 0 " + std::to_string(i) + ".5 h 0\n";
    }
    warnings.clear();
    EXPECT_TRUE(read(distinct_short, &warnings).scans[4].returned(2));
    EXPECT_TRUE(warnings.empty());
  }
}

TEST(OdomScanText, ReadsTheExtractFormat) {
  const std::string text =
      "# extract\nODOMETRY 1.000000 0.5 0.25 0.1 0.2 0.0\nLASERSCAN 1.100000 3 1.00 2.00 3.00\n"
      "ODOMETRY 1.200000 0.6 0.25 0.1 0.2 0.0\n";
  EXPECT_TRUE(looks_like_odomscan_text(text));
  EXPECT_FALSE(looks_like_odomscan_text(kCarmen));
  const RobotLog log = read_odomscan_text(text, "x.txt");
  ASSERT_EQ(log.scans.size(), 1u);
  ASSERT_EQ(log.odometry.size(), 2u);
  EXPECT_EQ(log.scans[0].stamp_us, 1'100'000);
  EXPECT_FALSE(log.scans[0].odometry.has_value());
  EXPECT_NEAR(odometry_at(sort_by_time(log.odometry), log.scans[0].stamp_us)->x, 0.55, 1e-12);
}

// Every malformed line: Error with the file, the line and the field.
TEST(LogReaders, MalformedInputNamesFileLineAndField) {
  struct Row {
    std::string text;
    bool odomscan;
    int line;
    std::string field;
  };
  const std::vector<Row> rows = {
      {"FLASER 3 1 2\n", false, 1, "FLASER fields"},
      {"FLASER x 1 2 3\n", false, 1, "FLASER num_readings"},
      {"FLASER 999999999 1\n", false, 1, "FLASER num_readings"},
      {"# c\nFLASER 1 nan 0 0 0 0 0 0 1.0 h 0\n", false, 2, "FLASER range"},
      {"FLASER 1 1.0 0 0 0 0 0 0 1x3 h 0\n", false, 1, "FLASER ipc_timestamp"},
      {"ODOM 1 2 inf 0 0 0 1.0 h 0\n", false, 1, "ODOM theta"},
      {"ODOM 1 2 3\n", false, 1, "ODOM fields"},
      {"TRUEPOS 1 2 3 4 5 6 x h 0\n", false, 1, "TRUEPOS ipc_timestamp"},
      {"RAWLASER1 0 0 3 0.1 0 0.01 0 2 1 2 0 1.0 h 0\n", false, 1, "RAWLASER1 maximum_range"},
      {"ROBOTLASER1 0 0 3 0.1 10 0.01 0 1 1 0 1 2 3\n", false, 1, "ROBOTLASER1 fields"},
      {"PARAM robot_frontlaser_offset abc h 0\n", false, 1, "PARAM robot_frontlaser_offset"},
      {"LASERSCAN 1.0 3 1 2\n", true, 1, "LASERSCAN ranges"},
      {"ODOMETRY 1.0 1 2 3 4\n", true, 1, "ODOMETRY fields"},
      {"ODOMETRY 1.0 1 2 3 4 5\nLASERSCAN 1.0 1 \x01\n", true, 2, "LASERSCAN range"},
      // Positions farther than kMaxCoordinateM (1e9 m) from the origin are corrupt, never mapped.
      {"FLASER 1 1.0 1e19 0 0 0 0 0 1.0 h 0\n", false, 1, "FLASER x"},
      {"FLASER 1 1.0 0 0 0 0 -1e300 0 1.0 h 0\n", false, 1, "FLASER odom_y"},
      {"ODOM 1e10 2 0 0 0 0 1.0 h 0\n", false, 1, "ODOM x"},
      {"TRUEPOS 0 0 0 2e9 0 0 1.0 h 0\n", false, 1, "TRUEPOS odom_x"},
      {"ROBOTLASER1 0 0 3 0.1 10 0.01 0 1 1 0 1e20 0 0 0 0 0 0 0 0 0 0 1.0 h 0\n", false, 1, "ROBOTLASER1 laser_x"},
      {"PARAM robot_frontlaser_offset 1e12 h 0\n", false, 1, "PARAM robot_frontlaser_offset"},
      {"ODOMETRY 1.0 3e9 2 3 4 5\n", true, 1, "ODOMETRY x"},
  };
  // Read as `log info` reads them: a log without scans is listed, not refused.
  LogReadOptions listing;
  listing.allow_no_scans = true;
  for (const Row& r : rows) {
    try {
      if (r.odomscan) read_odomscan_text(r.text, "bad.txt", listing);
      else read_carmen_log(r.text, "bad.clf", listing);
      ADD_FAILURE() << "accepted: " << r.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.line(), r.line) << r.text;
      EXPECT_EQ(e.field(), r.field) << r.text << ": " << e.what();
      EXPECT_FALSE(e.file().empty());
      EXPECT_EQ(std::string(e.message()).find('\x01'), std::string::npos) << "control character echoed";
    }
  }
}

std::string bag_fixture(const std::string& compression) {
  test::BagWriter w(compression);
  w.connection({0, "/tf_static", "tf2_msgs/TFMessage"});
  // base_link -> mount -> laser: the reader composes the chain.
  w.message(0, 1, 0, test::tf_message({{"base_link", "mount", 0.1, 0.0, kPi / 2}, {"mount", "laser", 0.2, 0.0, 0.0}}));
  w.connection({1, "/scan", "sensor_msgs/LaserScan"});
  w.connection({2, "/odom", "nav_msgs/Odometry"});
  w.connection({3, "/chatter", "std_msgs/String"});
  w.message(2, 10, 0, test::odometry(10, 0, "base_link", 1.0, 2.0, 0.5, 0.3, 0.1));
  w.message(1, 10, 100'000'000, test::laser_scan(10, 123'456'789, "laser", -1.0f, 0.5f, 30.0f, {1.0f, 2.0f, 30.0f, 4.0f, 5.0f}));
  w.flush_chunk();
  w.message(3, 11, 0, std::string("\x02\x00\x00\x00hi", 6));
  w.message(2, 11, 0, test::odometry(11, 0, "base_link", 2.0, 2.0, -0.5, 0.0, 0.0));
  return w.bytes();
}

template <class F>
Error error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error("none");
}

// A log its command needs scans from but that has none is refused from its lines' first words,
// before any record is read: the malformed ODOM line 2 is never reached (with allow_no_scans it is).
TEST(LogReaders, ALogWithoutScansIsRefusedBeforeItsOdometryIsRead) {
  struct Row {
    std::string text;
    bool odomscan;
    std::string refusal;
  };
  const std::vector<Row> rows = {
      {"ODOM 0 0 0 0 0 0 1.0 h 1.0\nODOM x 0 0 0 0 0 2.0 h 2.0\n", false, "holds no laser scan line (FLASER, ROBOTLASER1, RAWLASER1..4)"},
      {"ODOMETRY 1.0 0 0 0 0 0\nODOMETRY 2.0 x 0 0 0 0\n", true, "holds no LASERSCAN line"},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(r.text);
    const auto read = [&](const LogReadOptions& o) { return r.odomscan ? read_odomscan_text(r.text, "a.log", o) : read_carmen_log(r.text, "a.log", o); };
    const Error e = error_of([&] { read({}); });
    EXPECT_EQ(e.file(), "a.log");
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(e.message().find(r.refusal), std::string::npos) << e.what();
    LogReadOptions listing;
    listing.allow_no_scans = true;
    EXPECT_EQ(error_of([&] { read(listing); }).line(), 2);
  }
}

// Records cost more than their text only in a degenerate log: 2 million bare ODOM lines (40 MB)
// would take 112 MB parsed, more than their text plus 64 MiB, and are refused from the count of
// their lines; the same number of bytes in real lines (long ODOM lines) is read.
TEST(LogReaders, ParsedRecordsAreBoundedByTheTextTheyComeFrom) {
  std::string bare;
  for (int i = 0; i < 2'000'000; ++i) bare += "ODOM 0 0 0 0 0 0 1\n";
  LogReadOptions o;
  o.allow_no_scans = true;
  const Error e = error_of([&] { read_carmen_log(bare, "bare.clf", o); });
  EXPECT_EQ(e.file(), "bare.clf");
  EXPECT_NE(e.message().find("0 scan, 2000000 odometry and 0 ground-truth lines would take more than"), std::string::npos) << e.what();
  std::string real;
  const std::string line = "ODOM 1.000000 2.000000 0.500000 0.100000 0.010000 0.000000 1134864629.895182 nebula 0.013291\n";
  for (std::size_t i = 0; i < bare.size() / line.size() + 1; ++i) real += line;
  EXPECT_EQ(read_carmen_log(real, "real.clf", o).odometry.size(), bare.size() / line.size() + 1);
}

TEST(RosBag, ReadsScansOdometryAndTheStaticTransformFromEveryChunkCompression) {
  for (const std::string compression : {"none", "bz2", "lz4"}) {
    const std::string bytes = bag_fixture(compression);
    ASSERT_TRUE(is_ros1_bag(bytes));
    const RobotLog log = read_ros1_bag(bytes, "fixture.bag");
    ASSERT_EQ(log.scans.size(), 1u) << compression;
    ASSERT_EQ(log.odometry.size(), 2u);
    const LogScan& s = log.scans[0];
    EXPECT_EQ(s.stamp_us, 10'123'457);  // header.stamp, rounded to 1 us
    EXPECT_FLOAT_EQ(static_cast<float>(s.angle_increment_rad), 0.5f);
    EXPECT_FALSE(s.returned(2));  // at range_max
    EXPECT_TRUE(s.returned(3));
    EXPECT_NEAR(log.odometry[0].pose.yaw, 0.5, 1e-12);
    EXPECT_NEAR(log.odometry[1].pose.yaw, -0.5, 1e-12);
    EXPECT_DOUBLE_EQ(log.odometry[0].tv_mps, 0.3);
    ASSERT_TRUE(log.laser_in_base.has_value());
    // mount at (0.1, 0) turned 90 deg; the laser 0.2 m ahead of the mount: (0.1, 0.2), 90 deg.
    EXPECT_NEAR(log.laser_in_base->x, 0.1, 1e-12);
    EXPECT_NEAR(log.laser_in_base->y, 0.2, 1e-12);
    EXPECT_NEAR(log.laser_in_base->yaw, kPi / 2, 1e-12);
    EXPECT_EQ(log.skipped.at("/chatter (std_msgs/String)"), 1u);
  }
  LogReadOptions o;
  o.flaser_beam_angles = true;
  EXPECT_NEAR(read_ros1_bag(bag_fixture("none"), "f.bag", o).scans[0].angle_min_rad, -kPi / 2, 1e-12);
}

TEST(RosBag, TopicsAreChosenByTypeOrByName) {
  test::BagWriter w;
  w.connection({0, "/front", "sensor_msgs/LaserScan"});
  w.connection({1, "/rear", "sensor_msgs/LaserScan"});
  w.message(0, 1, 0, test::laser_scan(1, 0, "f", 0.0f, 0.1f, 10.0f, {1.0f}));
  w.message(1, 1, 0, test::laser_scan(1, 0, "r", 0.0f, 0.1f, 10.0f, {2.0f, 3.0f}));
  const std::string bytes = w.bytes();
  try {
    read_ros1_bag(bytes, "two.bag");
    FAIL() << "two LaserScan topics need a choice";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--scan-topic");
    EXPECT_NE(std::string(e.what()).find("/front, /rear"), std::string::npos) << e.what();
  }
  LogReadOptions o;
  o.scan_topic = "/rear";
  const RobotLog log = read_ros1_bag(bytes, "two.bag", o);
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].ranges_m.size(), 2u);
  EXPECT_TRUE(log.odometry.empty());
  o.scan_topic = "/side";
  EXPECT_THROW(read_ros1_bag(bytes, "two.bag", o), Error);
}

TEST(RosBag, MalformedBagsNameTheByteAndField) {
  const std::string good = bag_fixture("bz2");
  struct Row {
    std::string bytes;
    std::string field;
  };
  std::string bad_compression = bag_fixture("none");
  bad_compression.replace(bad_compression.find("compression=none"), 16, "compression=zip!");
  std::string corrupt = good;
  corrupt[corrupt.size() - 40] ^= 0x55;
  const std::vector<Row> rows = {
      {"#ROSBAG V1.2\n", "magic"},
      {good.substr(0, good.size() - 7), "data_len"},
      {good.substr(0, 4200), "data_len"},
      {bad_compression, "compression"},
      {corrupt, "bz2"},
  };
  for (const Row& r : rows) {
    try {
      read_ros1_bag(r.bytes, "bad.bag");
      ADD_FAILURE() << "accepted a bag that should fail on " << r.field;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << e.what();
      EXPECT_EQ(e.file(), "bad.bag");
      if (r.field != "magic") {
        EXPECT_NE(std::string(e.what()).find("byte"), std::string::npos) << e.what();
      }
    }
  }
}

// geometry_msgs/PoseStamped (ROS 1) at (x, 0).
std::string pose_stamped_at(double x) {
  test::Bytes b;
  test::ros_header(b, 1, 0, "map");
  b.put(x).put(0.0).put(0.0).put(0.0).put(0.0).put(0.0).put(1.0);
  return b.s;
}

TEST(RosBag, PositionsFartherThanTheCoordinateLimitAreRefused) {
  struct Row {
    std::string message;
    std::string topic, type, field;
  };
  const std::vector<Row> rows = {
      {test::odometry(1, 0, "base_link", 1e19, 0.0, 0.0, 0.0, 0.0), "/odom", "nav_msgs/Odometry", "pose.position"},
      {test::odometry(1, 0, "base_link", 0.0, -2e9, 0.0, 0.0, 0.0), "/odom", "nav_msgs/Odometry", "pose.position"},
      {test::tf_message({{"base_link", "laser", 1e12, 0.0, 0.0}}), "/tf_static", "tf2_msgs/TFMessage", "transforms"},
      {pose_stamped_at(3e9), "/truth", "geometry_msgs/PoseStamped", "pose.position"},
  };
  for (const Row& r : rows) {
    test::BagWriter w;
    w.connection({0, "/scan", "sensor_msgs/LaserScan"});
    w.connection({1, r.topic, r.type});
    w.message(0, 1, 0, test::laser_scan(1, 0, "laser", 0.0f, 0.1f, 10.0f, {1.0f, 2.0f}));
    w.message(1, 1, 0, r.message);
    LogReadOptions o;
    if (r.topic == "/truth") o.truth_topic = "/truth";
    try {
      read_ros1_bag(w.bytes(), "far.bag", o);
      ADD_FAILURE() << "accepted a position beyond 1e9 m on " << r.topic;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << e.what();
      EXPECT_NE(std::string(e.what()).find("farther than 1000000000 m"), std::string::npos) << e.what();
    }
  }
}

// One rule per quantity, whichever reader meets it: the beam limit, sound beam angles and range
// limits, no negative reading, the point limit of a cloud. Each row was accepted silently by at
// least one reader (a bag of 30,000,000 ranges per scan loaded 716 MB).
TEST(LogReaders, EveryReaderHoldsTheSameScanRules) {
  struct Row {
    std::string name;
    std::function<void()> read;
    std::string field;
    std::string says;
  };
  const auto bag_scan = [](const std::string& message) {
    return [message] {
      test::BagWriter w;
      w.connection({0, "/scan", "sensor_msgs/LaserScan"});
      w.message(0, 1, 0, message);
      read_ros1_bag(w.bytes(), "faulty.bag");
    };
  };
  const auto carmen = [](const std::string& text) { return [text] { read_carmen_log(text, "faulty.clf"); }; };
  const auto odomscan = [](const std::string& text) { return [text] { read_odomscan_text(text, "faulty.txt"); }; };
  std::string many = "LASERSCAN 1.0 100001";
  for (int i = 0; i < 100001; ++i) many += " 1";
  // A PointCloud2 of one point whose width claims 60,000,000.
  std::string cloud = test::point_cloud2(1, 0, "velodyne", {{1.0, 2.0, 3.0}});
  const std::uint32_t wide = 60'000'000;
  std::memcpy(cloud.data() + 12 + 4 + std::string("velodyne").size() + 4, &wide, 4);
  const std::vector<Row> rows = {
      {"bag beams", bag_scan(test::laser_scan_fields(0.0f, 1.0f, 1e-5f, 0.1f, 10.0f, std::vector<float>(100001, 1.0f))), "ranges",
       "more than the 100000 a scan may have"},
      {"bag increment 0", bag_scan(test::laser_scan_fields(0.0f, 0.0f, 0.0f, 0.1f, 10.0f, {1, 2, 3})), "angle_increment", "is 0 with 3 beams"},
      {"bag range_max 0", bag_scan(test::laser_scan_fields(0.0f, 0.2f, 0.1f, 0.0f, 0.0f, {1, 2, 3})), "range_max", "no reading could return"},
      {"bag range_max < 0", bag_scan(test::laser_scan_fields(0.0f, 0.2f, 0.1f, 0.0f, -5.0f, {1, 2, 3})), "range_max", "not above range_min"},
      {"bag range_min nan", bag_scan(test::laser_scan_fields(0.0f, 0.2f, 0.1f, NAN, 5.0f, {1, 2, 3})), "range_min", "not a distance"},
      {"bag angle_min > angle_max", bag_scan(test::laser_scan_fields(1.0f, -1.0f, 0.1f, 0.0f, 10.0f, {1, 2, 3})), "angle_max",
       "runs against angle_increment"},
      {"bag more than a turn", bag_scan(test::laser_scan_fields(0.0f, 16.0f, 4.0f, 0.0f, 10.0f, {1, 2, 3, 4, 5})), "angle_increment", "more than a turn"},
      {"bag negative range", bag_scan(test::laser_scan_fields(0.0f, 0.2f, 0.1f, 0.0f, 10.0f, {1, -0.5f, 3})), "ranges", "is -0.5 m"},
      {"RAWLASER resolution 0", carmen("RAWLASER1 0 0 3 0 10 0.01 0 2 1 2 0 1.0 h 0\n"), "RAWLASER1 angular_resolution", "is 0 with 2 beams"},
      {"ROBOTLASER more than a turn", carmen("ROBOTLASER1 0 0 3 4 10 0.01 0 5 1 2 3 4 5 0 0 0 0 0 0 0 0 0 0 0 0 1.0 h 0\n"),
       "ROBOTLASER1 angular_resolution", "more than a turn"},
      {"RAWLASER negative", carmen("RAWLASER1 0 0 3 0.1 10 0.01 0 2 1 -2 0 1.0 h 0\n"), "RAWLASER1 range", "is -2 m"},
      {"FLASER negative", carmen("FLASER 3 1 -1 2 0 0 0 0 0 0 1.0 h 0\n"), "FLASER range", "is -1 m"},
      {"LASERSCAN negative", odomscan("LASERSCAN 1.0 3 1 2 -3\n"), "LASERSCAN range", "is -3 m"},
      {"LASERSCAN beams", odomscan(many + "\n"), "LASERSCAN n", "expected a count 0..100000"},
      {"PointCloud2 points",
       [&cloud] {
         test::BagWriter w;
         w.connection({0, "/points", "sensor_msgs/PointCloud2"});
         w.message(0, 1, 0, cloud);
         const std::string bytes = w.bytes();
         for_each_bag_point_cloud(bytes, "faulty.bag", index_point_cloud_bag(bytes, "faulty.bag", {}), [](BagPointCloud&&) {});
       },
       "width", "more than the 50000000 a cloud may have"},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(r.name);
    try {
      r.read();
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), r.field) << e.what();
      EXPECT_NE(std::string(e.what()).find(r.says), std::string::npos) << e.what();
    }
  }
  // REP 117's special readings stay readable: -inf (too close), +inf (no return), NaN (erroneous).
  EXPECT_NO_THROW(bag_scan(test::laser_scan_fields(0.0f, 0.2f, 0.1f, 0.0f, 10.0f, {-INFINITY, INFINITY, NAN}))());
}

// `n` zero bytes as one gzip member (zlib's deflate, independent of the reader's inflate).
std::string gzip_zeros(std::size_t n) {
  const std::string raw(n, '\0');
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, static_cast<uLong>(n)), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = static_cast<uInt>(n);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

TEST(Decompress, GzipStopsAtTheLimitWhileInflatingOrFromItsTrailer) {
  constexpr std::size_t kLimit = std::size_t{1} << 20;
  EXPECT_EQ(gunzip(gzip_zeros(kLimit), "exact.gz", kLimit).size(), kLimit);
  // The trailer says 1 MiB + 1: refused before inflating.
  const std::string over = gzip_zeros(kLimit + 1);
  EXPECT_NE(test::error_of([&] { gunzip(over, "over.gz", kLimit); }).find("says it decompresses to 1048577 bytes"), std::string::npos);
  // A trailer that lies (0), or members that each fit: refused while inflating, at the limit.
  std::string lying = gzip_zeros(3 * kLimit);
  lying.replace(lying.size() - 4, 4, std::string(4, '\0'));
  const std::string members = gzip_zeros(kLimit / 2 + 1) + gzip_zeros(kLimit / 2);
  for (const std::string* bytes : {static_cast<const std::string*>(&lying), &members}) {
    const std::string what = test::error_of([&] { gunzip(*bytes, "many.gz", kLimit); });
    EXPECT_NE(what.find("many.gz: gzip: decompresses to more than 1048576 bytes"), std::string::npos) << what;
  }
  EXPECT_EQ(gunzip(gzip_zeros(kLimit / 2) + gzip_zeros(kLimit / 2), "two.gz", kLimit).size(), kLimit);
}

TEST(LogFile, DetectsTheFormatUndoesGzipAndRefusesNonRegularFiles) {
  const test::ScratchDir dir;
  const std::string gz = dir.file("log.clf.gz");
  gzFile f = gzopen(gz.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  gzputs(f, kCarmen);
  gzclose(f);
  EXPECT_EQ(read_robot_log(gz).scans.size(), 3u);
  test::write_text(dir.file("b.bag"), bag_fixture("lz4"));
  EXPECT_EQ(read_robot_log(dir.file("b.bag")).format, "ros1_bag");
  test::write_text(dir.file("empty.clf"), "# nothing\n");
  EXPECT_THROW(read_robot_log(dir.file("empty.clf")), Error);
  EXPECT_THROW(read_robot_log(dir.path().string()), Error);
  EXPECT_THROW(read_robot_log("/dev/zero"), Error);
  test::write_text(dir.file("trunc.gz"), std::string("\x1f\x8b\x08\x00", 4));
  EXPECT_THROW(read_robot_log(dir.file("trunc.gz")), Error);
}

// ---- The benchmark logs of ../shared/datasets/carmen_raw (SOURCES.md gives the counts) ----------

TEST(BenchmarkLogs, CountsMatchTheirSources) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/carmen_raw/mit-csail.clf.gz");
  const RobotLog csail = read_robot_log(test::shared_path("datasets/carmen_raw/mit-csail.clf.gz"));
  EXPECT_EQ(csail.scans.size(), 1988u);
  EXPECT_TRUE(csail.odometry.empty());
  EXPECT_EQ(format_stamp_us(csail.scans.front().stamp_us), "1134864629.895182");
  EXPECT_EQ(format_stamp_us(csail.scans.back().stamp_us), "1134865053.892206");
  const RobotLogSummary s = summarise_log(csail);
  EXPECT_EQ(s.no_return, 23711u);
  EXPECT_TRUE(s.scan_odometry_in_line);
  EXPECT_NEAR(csail.scans[0].odometry->x, 576.5, 0.05);
  struct Expect {
    const char* name;
    std::size_t scans, odometry, scans_back, odometry_back;
  };
  for (const Expect& e : {Expect{"intel", 13631, 26915, 631, 602}, Expect{"fr079", 4934, 8951, 0, 0},
                          Expect{"aces", 7374, 7375, 0, 0}}) {
    const std::string bag = test::shared_path(std::string("datasets/carmen_raw/ros1_bags/") + e.name + ".orig.bag");
    if (bag.empty()) continue;
    const RobotLogSummary b = summarise_log(read_robot_log(bag));
    EXPECT_EQ(b.scans, e.scans) << e.name;
    EXPECT_EQ(b.odometry, e.odometry) << e.name;
    EXPECT_EQ(b.scans_out_of_order, e.scans_back) << e.name;
    EXPECT_EQ(b.odometry_out_of_order, e.odometry_back) << e.name;
  }
  const std::string fr079 = test::shared_path("datasets/carmen_raw/ros1_bags/fr079.orig.bag");
  if (!fr079.empty()) {
    const RobotLog log = read_robot_log(fr079);
    ASSERT_TRUE(log.laser_in_base.has_value());
    EXPECT_NEAR(log.laser_in_base->x, 0.04, 1e-9);  // SOURCES.md: +0.04 m in /tf_static
  }
}

TEST(BenchmarkLogs, BagAndTextExtractGiveTheSameScansAndOdometry) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/carmen_raw/ros1_bags");
  for (const char* name : {"intel", "fr079", "aces"}) {
    const std::string bag = test::shared_path(std::string("datasets/carmen_raw/ros1_bags/") + name + ".orig.bag");
    const std::string text = test::shared_path(std::string("datasets/carmen_raw/derived_from_bags/") + name + ".odomscan.txt.gz");
    if (bag.empty() || text.empty()) continue;
    const RobotLog a = read_robot_log(bag), b = read_robot_log(text);
    ASSERT_EQ(a.scans.size(), b.scans.size()) << name;
    ASSERT_EQ(a.odometry.size(), b.odometry.size()) << name;
    std::size_t range_mismatches = 0;
    for (std::size_t i = 0; i < a.scans.size(); ++i) {
      ASSERT_EQ(a.scans[i].stamp_us, b.scans[i].stamp_us) << name << " scan " << i;
      ASSERT_EQ(a.scans[i].ranges_m.size(), b.scans[i].ranges_m.size()) << name << " scan " << i;
      for (std::size_t k = 0; k < a.scans[i].ranges_m.size(); ++k)
        range_mismatches += std::lround(a.scans[i].ranges_m[k] * 100.0) != std::lround(b.scans[i].ranges_m[k] * 100.0);
    }
    EXPECT_EQ(range_mismatches, 0u) << name;
    for (std::size_t i = 0; i < a.odometry.size(); ++i) {
      ASSERT_EQ(a.odometry[i].stamp_us, b.odometry[i].stamp_us) << name << " odometry " << i;
      EXPECT_NEAR(a.odometry[i].pose.x, b.odometry[i].pose.x, 5e-7) << name;
      EXPECT_NEAR(a.odometry[i].pose.y, b.odometry[i].pose.y, 5e-7) << name;
      EXPECT_NEAR(angle_diff(a.odometry[i].pose.yaw, b.odometry[i].pose.yaw), 0.0, 2e-6) << name;
    }
  }
}

}  // namespace
}  // namespace starnav
