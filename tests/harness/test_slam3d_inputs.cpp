// `starnav slam3d`'s three kinds of input: one simulated recording written as a frames folder, as
// a ROS 1 bag of PointCloud2 (with odometry, truth and /tf_static) and as a folder of PLY files
// with a TUM poses file, mapped by the same pipeline; the bag must give the folder's trajectory,
// the cloud files (no odometry) a small error against their poses. Then a KITTI sequence folder
// as it is, and the decoders' and readers' errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "logs/bag_writer.hpp"
#include "logs/cdr_writer.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/lidar_recording.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/slam3d_run.hpp"
#include "starnav/harness/lidar_frame_recorder.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// A 6 s recording of the mapping scenario at a coarse LiDAR resolution (fast).
std::string record(const test::ScratchDir& dir) {
  const std::vector<ScenarioOverride> o = {parse_scenario_override("sim.duration_s=6.0"),
                                           parse_scenario_override("sensors.lidar.horizontal_resolution_deg=0.5")};
  const ScenarioSpec spec = load_scenario(test::scenario_path("ou2022_mapping3d.yaml"), o);
  Simulation sim(spec);
  const std::string out = dir.file("lidar");
  LidarFrameRecorder recorder(sim, out, spec.outputs.lidar_frames_every_n_scans);
  sim.run();
  recorder.finish();
  return out;
}

std::pair<std::uint32_t, std::uint32_t> stamp(double t_s) {
  const auto ns = static_cast<std::int64_t>(std::llround(t_s * 1e9)) + 1'000'000'000'000LL;  // from 1000 s
  return {static_cast<std::uint32_t>(ns / 1'000'000'000), static_cast<std::uint32_t>(ns % 1'000'000'000)};
}

// The frames folder as a bag: clouds on /velodyne_points (two rows, NaN holes), wheel odometry on
// /odom, the truth on /ground_truth (moved into a frame of its own), the mount on /tf_static;
// chunks of a few messages, LZ4.
std::string write_bag(const LidarFrameFolder& f, const std::string& path) {
  test::BagWriter w("lz4");
  w.connection({0, "/tf_static", "tf2_msgs/TFMessage"});
  w.connection({1, "/velodyne_points", "sensor_msgs/PointCloud2"});
  w.connection({2, "/odom", "nav_msgs/Odometry"});
  w.connection({3, "/ground_truth", "nav_msgs/Odometry"});
  const Eigen::Quaterniond& mq = f.mount.orientation;
  w.message(0, 1000, 0, test::tf_message3({{"base_link", "velodyne", f.mount.position.x(), f.mount.position.y(), f.mount.position.z(),
                                             mq.x(), mq.y(), mq.z(), mq.w()}}));
  for (const LidarFrameRecord& r : f.frames) {
    const auto [sec, nsec] = stamp(r.t_s);
    if (r.odometry)
      w.message(2, sec, nsec, test::odometry(sec, nsec, "base_link", r.odometry->x, r.odometry->y, r.odometry->yaw, 0, 0));
    if (r.truth) {
      // In a frame of its own (as a motion-capture or GNSS truth would be): only its motion counts.
      const Pose3 t = Pose3::from_rpy(Vec3(100.0, -50.0, 500.0), 0.0, 0.0, 0.3).compose(*r.truth);
      const Eigen::Quaterniond& q = t.orientation;
      w.message(3, sec, nsec, test::odometry3(sec, nsec, "base_link", t.position.x(), t.position.y(), t.position.z(), q.x(),
                                               q.y(), q.z(), q.w()));
    }
    std::vector<test::PointXyz> pts;
    for (const Vec3& p : read_point_cloud(f.cloud_path(r)).points) pts.push_back({p.x(), p.y(), p.z()});
    if (pts.size() % 2) pts.push_back({std::nan(""), 0.0, 0.0});  // a hole: dropped by the reader
    w.message(1, sec, nsec, test::point_cloud2(sec, nsec, "velodyne", pts, false, false, 2, 8));
    if (r.frame % 5 == 4) w.flush_chunk();
  }
  test::write_text(path, w.bytes());
  return path;
}

// The frames folder as a ROS 2 MCAP: the same topics and messages as write_bag, in CDR, zstd chunks
// of about 64 KiB.
std::string write_mcap(const LidarFrameFolder& f, const std::string& path) {
  McapWriter w("ros2", McapWriter::Compression::Zstd, 1 << 16);
  const auto channel = [&](const char* topic, const char* type) { return w.add_channel(w.add_schema(type, "ros2msg", ""), topic, "cdr"); };
  const std::uint16_t tf = channel("/tf_static", "tf2_msgs/msg/TFMessage"), cloud = channel("/velodyne_points", "sensor_msgs/msg/PointCloud2");
  const std::uint16_t odom = channel("/odom", "nav_msgs/msg/Odometry"), truth = channel("/ground_truth", "nav_msgs/msg/Odometry");
  const auto odometry = [](std::uint32_t sec, std::uint32_t nsec, const Pose3& p) {
    test::CdrBytes c;
    c.header(static_cast<std::int32_t>(sec), nsec, "odom").str("base_link");
    c.put(p.position.x()).put(p.position.y()).put(p.position.z());
    c.put(p.orientation.x()).put(p.orientation.y()).put(p.orientation.z()).put(p.orientation.w());
    for (int i = 0; i < 36 + 6 + 36; ++i) c.put(0.0);
    return c.bytes;
  };
  test::CdrBytes t;
  t.put(std::uint32_t{1}).header(1000, 0, "base_link").str("velodyne");
  const Pose3& m = f.mount;
  t.put(m.position.x()).put(m.position.y()).put(m.position.z());
  t.put(m.orientation.x()).put(m.orientation.y()).put(m.orientation.z()).put(m.orientation.w());
  w.add_message(tf, 1000'000'000'000ull, 0, t.bytes);
  for (const LidarFrameRecord& r : f.frames) {
    const auto [sec, nsec] = stamp(r.t_s);
    const std::uint64_t ns = std::uint64_t{sec} * 1'000'000'000ull + nsec;
    if (r.odometry) w.add_message(odom, ns, ns, odometry(sec, nsec, Pose3::from_rpy(Vec3(r.odometry->x, r.odometry->y, 0.0), 0, 0, r.odometry->yaw)));
    if (r.truth) w.add_message(truth, ns, ns, odometry(sec, nsec, Pose3::from_rpy(Vec3(100.0, -50.0, 500.0), 0.0, 0.0, 0.3).compose(*r.truth)));
    std::vector<Vec3> pts = read_point_cloud(f.cloud_path(r)).points;
    if (pts.size() % 2) pts.emplace_back(std::nan(""), 0.0, 0.0);
    // Two rows of intensity, x, y, z (FLOAT32), each row padded by 8 bytes.
    test::CdrBytes c;
    c.header(static_cast<std::int32_t>(sec), nsec, "velodyne").put(std::uint32_t{2}).put(static_cast<std::uint32_t>(pts.size() / 2)).put(std::uint32_t{4});
    const char* names[] = {"intensity", "x", "y", "z"};
    for (std::uint32_t k = 0; k < 4; ++k) c.str(names[k]).put(4 * k).put(std::uint8_t{7}).put(std::uint32_t{1});
    const std::uint32_t row = static_cast<std::uint32_t>(pts.size() / 2) * 16 + 8;
    c.put(std::uint8_t{0}).put(std::uint32_t{16}).put(row).put(2 * row);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const float v[4] = {1.0f, static_cast<float>(pts[i].x()), static_cast<float>(pts[i].y()), static_cast<float>(pts[i].z())};
      c.raw(v, 16);
      if (i + 1 == pts.size() / 2 || i + 1 == pts.size()) c.bytes.append(8, '\0');
    }
    c.put(std::uint8_t{0});
    w.add_message(cloud, ns, ns, c.bytes);
  }
  test::write_text(path, w.finish());
  return path;
}

// The frames folder as PLY files named by number, with the sensor's true poses in TUM format.
std::string write_cloud_files(const LidarFrameFolder& f, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::string tum;
  for (const LidarFrameRecord& r : f.frames) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.ply", r.frame);
    write_point_cloud(dir + "/" + name, read_point_cloud(f.cloud_path(r)).points, PointCloudFormat::Ply, PointCloudEncoding::Binary);
    const Pose3 s = r.truth->compose(f.mount);
    char line[256];
    std::snprintf(line, sizeof line, "%.6f %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n", r.t_s, s.position.x(), s.position.y(),
                  s.position.z(), s.orientation.x(), s.orientation.y(), s.orientation.z(), s.orientation.w());
    tum += line;
  }
  test::write_text(dir + "/poses.txt", tum);
  return dir;
}

TEST(Slam3dInputs, ABagAndCloudFilesMapLikeTheFramesFolder) {
  test::ScratchDir dir;
  const std::string folder = record(dir);
  const LidarFrameFolder f = read_lidar_frame_folder(folder);
  ASSERT_GE(f.frames.size(), 60u);
  for (const LidarFrameRecord& r : f.frames) ASSERT_TRUE(r.truth);

  Slam3dRunConfig c;
  const Slam3dRunResult a = run_slam3d(folder, c);
  EXPECT_EQ(a.input_kind, "frames folder");
  ASSERT_TRUE(a.has_truth);
  EXPECT_LT(a.ate_rmse_m, 0.05);

  Slam3dRunConfig cb = c;
  cb.recording.bag.truth_topic = "/ground_truth";
  const Slam3dRunResult b = run_slam3d(write_bag(f, dir.file("run.bag")), cb);
  EXPECT_EQ(b.input_kind, "ROS 1 bag");
  ASSERT_EQ(b.trajectory.size(), a.trajectory.size());
  EXPECT_NEAR(b.input.mount.position.z(), f.mount.position.z(), 1e-12);
  ASSERT_TRUE(b.has_truth);
  // Same clouds, same odometry (through a quaternion): the same map, to rounding.
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    EXPECT_NEAR(b.input.frames[i].t_s, a.input.frames[i].t_s, 1e-6);
    EXPECT_EQ(b.input.frames[i].odometry.has_value(), a.input.frames[i].odometry.has_value()) << i;
    ASSERT_LT((b.trajectory[i].translation() - a.trajectory[i].translation()).norm(), 1e-4) << i;
  }
  EXPECT_NEAR(b.ate_rmse_m, a.ate_rmse_m, 1e-4);
  EXPECT_NEAR(b.elevation_drift_m, a.elevation_drift_m, 1e-4);

  // The same recording as a ROS 2 MCAP: the same input, so the same trajectory as the ROS 1 bag.
  const Slam3dRunResult r2 = run_slam3d(write_mcap(f, dir.file("run.mcap")), cb);
  EXPECT_EQ(r2.input_kind, "ROS 2 bag");
  ASSERT_EQ(r2.trajectory.size(), b.trajectory.size());
  EXPECT_NEAR(r2.input.mount.position.z(), f.mount.position.z(), 1e-12);
  for (std::size_t i = 0; i < b.trajectory.size(); ++i) {
    ASSERT_EQ(r2.input.frames[i].t_s, b.input.frames[i].t_s) << i;
    ASSERT_LT((r2.trajectory[i].translation() - b.trajectory[i].translation()).norm(), 1e-9) << i;
  }
  EXPECT_NEAR(r2.ate_rmse_m, b.ate_rmse_m, 1e-9);

  Slam3dRunConfig cc = c;
  cc.recording.mount = f.mount;
  const Slam3dRunResult p = run_slam3d(write_cloud_files(f, dir.file("clouds")), cc);
  EXPECT_EQ(p.input_kind, "cloud files");
  ASSERT_EQ(p.trajectory.size(), a.trajectory.size());
  EXPECT_NEAR(p.input.frames.back().t_s, a.input.frames.back().t_s, 1e-6);  // times from the TUM poses
  EXPECT_FALSE(p.input.frames[5].odometry.has_value());
  ASSERT_TRUE(p.has_truth);
  // The same driven distance from the poses file as from the simulator's truth; without wheel
  // odometry the guess is the last motion, and the error stays small.
  EXPECT_NEAR(p.driven_m, a.driven_m, 1e-3);
  EXPECT_LT(p.ate_rmse_m, 0.05);
  EXPECT_LT(p.elevation_drift_m, 0.05);
}

TEST(Slam3dInputs, AKittiSequenceFolderAsItIs) {
  const std::string seq = test::shared_path("datasets/lidar3d/kitti_odometry_mini/sequences/05");
  if (seq.empty()) GTEST_SKIP() << "../shared/datasets/lidar3d is not here";
  Slam3dRunConfig c;
  c.max_frames = 4;
  c.settings = {{"floor", "false", "", 0, "--set floor"}, {"keyframe_delta_trans_m", "0.01", "", 0, "--set keyframe_delta_trans_m"}};  // the road is not level (docs/mapping3d.md)
  c.recording.mount = Pose3::from_rpy(Vec3(0, 0, 1.73), 0, 0, 0);
  const Slam3dRunResult r = run_slam3d(seq, c);
  EXPECT_EQ(r.input_kind, "cloud files");
  ASSERT_EQ(r.trajectory.size(), 4u);
  ASSERT_TRUE(r.has_truth);  // poses.txt (camera poses) through KITTI's Tr for sequence 05
  EXPECT_NEAR(r.input.frames[1].t_s, 0.104, 0.001);  // times.txt
  EXPECT_GT(r.driven_m, 1.5);
  EXPECT_LT(r.ate_rmse_m, 0.05);
}

TEST(Slam3dInputs, PoseFilesAndCloudFoldersNameTheirErrors) {
  test::ScratchDir dir;
  auto poses_error = [&](const std::string& text) {
    test::write_text(dir.file("p.txt"), text);
    try {
      read_pose_file(dir.file("p.txt"));
    } catch (const Error& e) {
      return e.field() + ": " + e.message();
    }
    return std::string("no error");
  };
  EXPECT_EQ(poses_error("1 0 0 0 0 1 0 0 0 0 1 0\n"), "no error");
  EXPECT_EQ(poses_error("0.1 1 2 3 0 0 0 1\n0.2 1 2 3 0 0 0 1\n"), "no error");
  EXPECT_NE(poses_error("1 2 3\n").find("pose: 3 values"), std::string::npos);
  EXPECT_NE(poses_error("0.1 1 2 3 0 0 0 1\n0.2 1 2 3 0 0 1\n").find("pose: 7 values"), std::string::npos);
  EXPECT_NE(poses_error("0.1 1 2 3 0 0 0 2\n").find("unit length"), std::string::npos);
  EXPECT_NE(poses_error("2 0 0 0 0 1 0 0 0 0 1 0\n").find("not a rotation"), std::string::npos);
  EXPECT_NE(poses_error("0.2 1 2 3 0 0 0 1\n0.1 1 2 3 0 0 0 1\n").find("t: times must increase"), std::string::npos);
  EXPECT_NE(poses_error("0.1 nan 2 3 0 0 0 1\n").find("finite"), std::string::npos);
  EXPECT_NE(poses_error("\n").find("no poses"), std::string::npos);
  // Gives the values and the readings that come with the first pose of each.
  test::write_text(dir.file("k.txt"), "0.5 1 0 0 7 0 1 0 8 0 0 1 9\n");
  const std::vector<PoseFileEntry> k = read_pose_file(dir.file("k.txt"));
  ASSERT_EQ(k.size(), 1u);
  EXPECT_DOUBLE_EQ(*k[0].t_s, 0.5);
  EXPECT_EQ(k[0].pose.translation(), Vec3(7, 8, 9));

  // Cloud folders: no clouds; more frames than poses.
  std::filesystem::create_directories(dir.file("empty"));
  EXPECT_NE(test::error_of([&] { open_lidar_recording(dir.file("empty")); }).find("no cloud files"), std::string::npos);
  std::filesystem::create_directories(dir.file("c"));
  for (const char* n : {"000000.pcd", "000001.pcd", "000002.pcd"})
    write_point_cloud(dir.file("c") + "/" + n, std::vector<Vec3>{Vec3(1, 2, 3)}, PointCloudFormat::Pcd, PointCloudEncoding::Binary);
  test::write_text(dir.file("c") + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  const std::string e = test::error_of([&] { open_lidar_recording(dir.file("c")); });
  EXPECT_NE(e.find("poses.txt"), std::string::npos) << e;
  EXPECT_NE(e.find("needs row 3"), std::string::npos) << e;
  // Frames named by number take that row: 000001 and 000002 alone use rows 2 and 3.
  std::filesystem::remove(dir.file("c") + "/000000.pcd");
  test::write_text(dir.file("c") + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n1 0 0 3 0 1 0 0 0 0 1 0\n");
  const LidarRecording rec = open_lidar_recording(dir.file("c"));
  ASSERT_EQ(rec.frames.frames.size(), 2u);
  EXPECT_NEAR(rec.frames.frames[1].truth->position.x(), 2.0, 1e-12);  // relative to the first: 3 - 1
  EXPECT_NEAR(rec.frames.frames[1].t_s, 0.2, 1e-12);                 // row 2 at the default 10 Hz
  std::size_t clouds = 0;
  rec.for_each_cloud(0, [&](std::size_t, PointCloud&& c) { clouds += c.size(); });
  EXPECT_EQ(clouds, 2u);
}

TEST(Slam3dInputs, PointCloud2DecodingAndItsErrors) {
  const std::vector<test::PointXyz> pts = {{1, 2, 3}, {4, 5, 6}, {std::nan(""), 0, 0}, {7, 8, 9}};
  auto bag_of = [](const std::vector<std::string>& clouds, bool two_topics = false) {
    test::BagWriter w;
    w.connection({1, "/points", "sensor_msgs/PointCloud2"});
    if (two_topics) w.connection({2, "/points2", "sensor_msgs/PointCloud2"});
    std::uint32_t sec = 10;
    for (const std::string& c : clouds) w.message(1, sec++, 0, c);
    return w.bytes();
  };
  // Every encoding gives the same three finite points (float32 rounding aside).
  for (bool dbl : {false, true})
    for (bool be : {false, true})
      for (std::uint32_t height : {1u, 2u}) {
        SCOPED_TRACE(std::to_string(dbl) + std::to_string(be) + std::to_string(height));
        const std::string bag = bag_of({test::point_cloud2(10, 0, "lidar", pts, dbl, be, height, height == 2 ? 5 : 0)});
        const PointCloudBagIndex ix = index_point_cloud_bag(bag, "x.bag");
        ASSERT_EQ(ix.cloud_stamps_us.size(), 1u);
        EXPECT_EQ(ix.cloud_stamps_us[0], 10'000'000);
        EXPECT_EQ(ix.cloud_frame, "lidar");
        std::vector<BagPointCloud> got;
        for_each_bag_point_cloud(bag, "x.bag", ix, [&](BagPointCloud&& c) { got.push_back(std::move(c)); });
        ASSERT_EQ(got.size(), 1u);
        ASSERT_EQ(got[0].points.size(), 3u);
        EXPECT_EQ(got[0].dropped, 1u);
        EXPECT_EQ(got[0].points[2], Vec3(7, 8, 9));
      }
  auto error = [&](const std::string& bag, const PointCloudBagOptions& o = {}) {
    return test::error_of([&] {
      const PointCloudBagIndex ix = index_point_cloud_bag(bag, "x.bag", o);
      for_each_bag_point_cloud(bag, "x.bag", ix, [](BagPointCloud&&) {});
    });
  };
  EXPECT_NE(error(bag_of({test::point_cloud2(10, 0, "l", pts, false, false, 1, 0, false)})).find("no 'z' field"), std::string::npos);
  // A cloud whose data is shorter than height x width points.
  std::string cut = test::point_cloud2(10, 0, "l", pts);
  const std::size_t data_len_at = cut.size() - 1 - 4 * 16 - 4;
  std::uint32_t wrong = 4 * 16 - 16;
  std::memcpy(cut.data() + data_len_at, &wrong, 4);
  cut.erase(data_len_at + 4, 16);
  const std::string short_data = error(bag_of({cut}));
  EXPECT_NE(short_data.find("x.bag"), std::string::npos) << short_data;
  EXPECT_NE(short_data.find("data"), std::string::npos) << short_data;
  EXPECT_NE(error(bag_of({test::point_cloud2(10, 0, "l", pts)}, true)).find("several sensor_msgs/PointCloud2"), std::string::npos);
  EXPECT_NE(error(bag_of({test::point_cloud2(10, 0, "l", pts)}), {"/nope", "", ""}).find("--cloud-topic"), std::string::npos);
  // Truncated bytes anywhere in the message: one error naming the bag, never a crash.
  const std::string good = test::point_cloud2(10, 0, "l", pts);
  for (std::size_t n = 0; n < good.size(); n += 7) {
    const std::string e = error(bag_of({good.substr(0, n)}));
    EXPECT_NE(e.find("x.bag"), std::string::npos) << n << ": " << e;
  }
}

}  // namespace
}  // namespace starnav
