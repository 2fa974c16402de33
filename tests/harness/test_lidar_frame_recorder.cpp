// The recording of a 3D LiDAR run for mapping (outputs.lidar_frames): sensor-frame clouds that the
// truth places back on the world, frames.csv and sensor.yaml read back; then `starnav slam3d` on it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/lidar_frames.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/lidar_frame_recorder.hpp"
#include "starnav/sim/scenario.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

const std::string kMapping3d = test::scenario_path("ou2022_mapping3d.yaml");

std::vector<ScenarioOverride> short_run() {
  return {parse_scenario_override("sim.duration_s=4.0"), parse_scenario_override("sensors.lidar.horizontal_resolution_deg=0.5")};
}

TEST(LidarFrameRecorder, WritesSensorFrameCloudsThatTheTruthPlacesOnTheWorld) {
  const std::vector<ScenarioOverride> o = short_run();
  const ScenarioSpec spec = load_scenario(kMapping3d, o);
  test::ScratchDir dir;
  Simulation sim(spec);
  LidarFrameRecorder recorder(sim, dir.file("lidar"), spec.outputs.lidar_frames_every_n_scans);
  sim.run();
  recorder.finish();
  const LidarFrameFolder f = read_lidar_frame_folder(dir.file("lidar"));
  ASSERT_EQ(f.frames.size(), recorder.frames());
  EXPECT_GE(f.frames.size(), 40u);  // 10 Hz for 4 s
  EXPECT_EQ(f.lines, 16);
  EXPECT_EQ(f.beams, 720);
  EXPECT_NEAR(f.mount.position.z(), 0.55, 1e-9);
  // The scan at t = 0 comes before the first gyro reading; every later frame has all three.
  for (std::size_t k = 1; k < f.frames.size(); ++k) ASSERT_TRUE(f.frames[k].odometry && f.frames[k].truth && f.frames[k].imu_yaw_rate_radps);
  // Frame 20's points, placed with the true pose: the floor at z ~ 0, nothing below it.
  const LidarFrameRecord& r = f.frames[20];
  const PointCloud pts = read_point_cloud(f.cloud_path(r)).points;
  ASSERT_GT(pts.size(), 1000u);
  const Rigid3 sensor = to_rigid(*r.truth) * to_rigid(f.mount);
  std::size_t floor = 0, below = 0;
  for (const Vec3& p : pts) {
    const double z = (sensor * p).z();
    floor += std::abs(z) < 0.05;
    below += z < -0.1;
  }
  EXPECT_GT(floor, pts.size() / 20);  // the lower beams that reach the floor between the walls
  EXPECT_EQ(below, 0u);
  // In the sensor frame, not the world's: the sensor sits 0.55 m up, so the floor is below it.
  std::size_t sensor_below = 0;
  for (const Vec3& p : pts) sensor_below += p.z() < -0.4;
  EXPECT_GT(sensor_below, pts.size() / 20);
}

TEST(LidarFrameRecorder, Slam3dMapsTheRecordingAndReportsItsError) {
  test::ScratchDir dir;
  const std::string run = dir.file("run"), slam = dir.file("slam");
  const test::CliResult sim = test::run_cli({"sim", kMapping3d, "--out", run, "--quiet", "--set", "sim.duration_s=12",
                                             "--set", "sensors.lidar.horizontal_resolution_deg=0.4"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const test::CliResult s = test::run_cli({"slam3d", run, "--out", slam, "--quiet", "--json", "--plan-to", "3.0,0.0"});
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const nlohmann::json j = nlohmann::json::parse(s.out);
  EXPECT_EQ(j["frames"].get<int>(), 121);  // t = 0, 0.1, ..., 12 s
  EXPECT_GE(j["keyframes"].get<int>(), 3);
  EXPECT_GT(j["driven_m"].get<double>(), 2.5);
  EXPECT_LT(j["ate_rmse_m"].get<double>(), 0.05);
  EXPECT_LT(j["elevation_drift_m"].get<double>(), 0.05);
  EXPECT_TRUE(std::ifstream(slam + "/trajectory.csv").good());
  EXPECT_TRUE(std::ifstream(slam + "/keyframes.csv").good());
  // The octree, its 2D grid (the corridor ahead is free: the improved A* finds the 3 m path) and the picture.
  for (const char* f : {"/map.bt", "/map.yaml", "/map.pgm", "/map.svg", "/map.png", "/path.csv"})
    EXPECT_TRUE(std::ifstream(slam + f).good()) << f;
  const test::CliResult far = test::run_cli({"slam3d", run, "--out", dir.file("far"), "--quiet", "--plan-to", "500,0"});
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("--plan-to"), std::string::npos) << far.err;
  // Bad input: a folder without frames, an unknown matcher.
  const test::CliResult bad = test::run_cli({"slam3d", dir.path().string(), "--out", dir.file("x"), "--quiet"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("frames.csv"), std::string::npos) << bad.err;
  const test::CliResult m = test::run_cli({"slam3d", run, "--out", dir.file("y"), "--quiet", "--matcher", "loam"});
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("--matcher"), std::string::npos) << m.err;
}

TEST(LidarFrames, MalformedFramesFilesNameTheirField) {
  test::ScratchDir dir;
  auto write = [&](const std::string& name, const std::string& text) { std::ofstream(dir.file(name)) << text; };
  write("sensor.yaml", "model: x\nlines: 16\nbeams: 100\nrate_hz: 10\nrange_min_m: 0.1\nrange_max_m: 50\n"
                       "mount: {x_m: 0, y_m: 0, z_m: 0.5, roll_deg: 0, pitch_deg: 0, yaw_deg: 0}\n");
  const std::string header = lidar_frames_header();
  auto field_of = [&](const std::string& csv) {
    write("frames.csv", csv);
    try {
      read_lidar_frame_folder(dir.path().string());
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field_of(header + "0,0.0,0.pcd,1,2,,,,,,,,\n"), "odom_x_m");
  EXPECT_EQ(field_of(header + "0,0.0,0.pcd,,,,,1,2,3,,,\n"), "true_x_m");
  EXPECT_EQ(field_of(header + "0,0.0,../x.pcd,,,,,,,,,,\n"), "cloud");
  EXPECT_EQ(field_of(header + "0,1.0,0.pcd,,,,,,,,,,\n1,0.5,1.pcd,,,,,,,,,,\n"), "t_s");
  EXPECT_EQ(field_of(header + "0,nan,0.pcd,,,,,,,,,,\n"), "t_s");
  EXPECT_EQ(field_of("frame,t\n"), "");  // wrong column count: named by line
  EXPECT_EQ(field_of(header + "0,0.0,0.pcd,,,,,,,,,,\n"), "no error");
  write("sensor.yaml", "model: x\nlines: 16\n");
  EXPECT_EQ(field_of(header), "beams");
}

}  // namespace
}  // namespace starnav
