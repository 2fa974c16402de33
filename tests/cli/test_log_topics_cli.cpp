// Every command that reads a log takes the same topic flags (apps/starnav/log_flags.hpp): a bag
// with two LaserScan topics is refused by each with the flag to give, and read by each with it;
// a bag without an Odometry topic is read with the odometry of /tf; ROS 2 recordings are read by
// the same commands.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "logs/bag_writer.hpp"
#include "starnav/core/angle.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// A robot standing in a square room 4 m wide, seen by two lasers (/front, /rear) 40 times; its
// odometry on /odom, or only as odom -> base_link on /tf (`tf_odometry`).
std::string two_laser_bag(bool tf_odometry) {
  test::BagWriter w("lz4");
  w.connection({0, "/front", "sensor_msgs/LaserScan"});
  w.connection({1, "/rear", "sensor_msgs/LaserScan"});
  w.connection({2, tf_odometry ? "/tf" : "/odom", tf_odometry ? "tf2_msgs/TFMessage" : "nav_msgs/Odometry"});
  w.connection({3, "/tf_static", "tf2_msgs/TFMessage"});
  w.message(3, 1, 0, test::tf_message({{"base_link", "front", 0.1, 0.0, 0.0}, {"base_link", "rear", -0.1, 0.0, kPi}}));
  std::vector<float> ranges;
  const int n = 360;
  for (int i = 0; i < n; ++i) {
    const double a = -kPi + 2 * kPi * i / n;
    ranges.push_back(static_cast<float>(2.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)))));
  }
  for (std::uint32_t k = 0; k < 40; ++k) {
    const std::uint32_t sec = 2 + k / 10, nsec = (k % 10) * 100'000'000;
    if (tf_odometry) {
      test::Bytes b;
      b.u32(1);
      test::ros_header(b, sec, nsec, "odom");
      b.str("base_link");
      b.put(0.0).put(0.0).put(0.0).put(0.0).put(0.0).put(0.0).put(1.0);
      w.message(2, sec, nsec, b.s);
    } else {
      w.message(2, sec, nsec, test::odometry(sec, nsec, "base_link", 0.0, 0.0, 0.0, 0.0, 0.0));
    }
    w.message(0, sec, nsec, test::laser_scan(sec, nsec, "front", static_cast<float>(-kPi), static_cast<float>(2 * kPi / n), 30.0f, ranges));
    w.message(1, sec, nsec, test::laser_scan(sec, nsec, "rear", static_cast<float>(-kPi), static_cast<float>(2 * kPi / n), 30.0f, ranges));
  }
  return w.bytes();
}

TEST(CliLogTopics, EveryLogCommandTakesTheTopicFlags) {
  const test::ScratchDir dir;
  const std::string bag = dir.file("two.bag");
  test::write_text(bag, two_laser_bag(false));
  // A map and a trajectory for the commands that need them, made with the flag.
  const test::CliResult map = test::run_cli({"map", "build", bag, "--scan-topic", "/front", "--poses", "odometry", "--out", dir.file("m.yaml")});
  ASSERT_EQ(map.exit_code, 0) << map.err;
  const test::CliResult odo = test::run_cli({"slam", "odometry", bag, "--scan-topic", "/front", "--out", dir.file("t.csv")});
  ASSERT_EQ(odo.exit_code, 0) << odo.err;
  test::write_text(dir.file("r.relations"), "2.000000 3.000000 0 0 0 0 0 0\n");
  const std::vector<std::vector<std::string>> commands = {
      {"log", "info", bag},
      {"map", "build", bag, "--poses", "odometry", "--out", dir.file("m2.yaml"), "--force"},
      {"slam", "run", bag, "--out", dir.file("slam"), "--quiet", "--force"},
      {"slam", "odometry", bag, "--out", dir.file("t2.csv"), "--force"},
      {"slam", "eval", dir.file("t.csv"), dir.file("r.relations"), "--log", bag},
      {"localize", bag, "--map", dir.file("m.yaml"), "--out", dir.file("loc"), "--initial", "0,0,0", "--quiet", "--force"},
  };
  for (const std::vector<std::string>& c : commands) {
    const std::string name = c[0] + " " + c[1];
    const test::CliResult refused = test::run_cli(c);
    EXPECT_EQ(refused.exit_code, 2) << name;
    EXPECT_NE(refused.err.find("--scan-topic: several sensor_msgs/LaserScan topics (/front, /rear): name one"), std::string::npos)
        << name << ": " << refused.err;
    std::vector<std::string> with = c;
    with.insert(with.end(), {"--scan-topic", "/rear", "--odom-topic", "/odom"});
    const test::CliResult read = test::run_cli(with);
    EXPECT_EQ(read.exit_code, 0) << name << ": " << read.err;
    std::vector<std::string> missing = c;
    missing.insert(missing.end(), {"--scan-topic", "/rear", "--imu-topic", "/imu"});
    const test::CliResult no_imu = test::run_cli(missing);
    EXPECT_EQ(no_imu.exit_code, 2) << name;
    EXPECT_NE(no_imu.err.find("--imu-topic: no sensor_msgs/Imu topic '/imu'"), std::string::npos) << name << ": " << no_imu.err;
    std::vector<std::string> wrong_truth = c;
    wrong_truth.insert(wrong_truth.end(), {"--scan-topic", "/rear", "--truth-topic", "/front"});
    const test::CliResult truth = test::run_cli(wrong_truth);
    EXPECT_EQ(truth.exit_code, 2) << name;
    EXPECT_NE(truth.err.find("--truth-topic: '/front' is of type sensor_msgs/LaserScan"), std::string::npos) << name << ": " << truth.err;
  }
  // The mount of the named laser: the rear one looks backwards.
  const test::CliResult rear = test::run_cli({"log", "info", bag, "--scan-topic", "/rear", "--json"});
  EXPECT_NE(rear.out.find("\"yaw_rad\":3.14159"), std::string::npos) << rear.out;
}

TEST(CliLogTopics, OdometryFromTfWhenTheBagHasNoOdometryTopic) {
  const test::ScratchDir dir;
  const std::string bag = dir.file("tf.bag");
  test::write_text(bag, two_laser_bag(true));
  const test::CliResult info = test::run_cli({"log", "info", bag, "--scan-topic", "/front"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("odometry:   40 readings"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("odom_topic: /tf (odom -> base_link)"), std::string::npos) << info.out;
  const test::CliResult slam = test::run_cli({"slam", "run", bag, "--scan-topic", "/front", "--out", dir.file("slam"), "--quiet"});
  EXPECT_EQ(slam.exit_code, 0) << slam.err;
}

}  // namespace
}  // namespace starnav
