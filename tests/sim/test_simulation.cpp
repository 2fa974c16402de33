// The scenario runner: closed-form motion on flat ground, determinism, event episodes, obstacles
// appearing for the LiDAR, the E1 platform run, and the `starnav sim` command.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;
using test::kE1;

// Flat ground, no lag, an acceleration limit that never binds: the achieved twist is the command.
std::string flat_scenario(const std::string& commands, const std::string& extra = {}) {
  return "world:\n  terrain:\n    generate: {kind: flat, size_m: [20, 20], resolution_m: 0.1, origin_m: [-10, -10]}\n" +
         extra +
         "robot:\n  actuator_lag_s: 0\n  max_wheel_accel_radps2: 100000\n  start: {x_m: 0.5, y_m: -1.0, yaw_deg: 30}\n"
         "sim: {dt_s: 0.01}\n"
         "commands:\n" +
         commands;
}

TEST(Simulation, ConstantTwistOnFlatGroundFollowsTheClosedFormArc) {
  const double vx = 0.3, vy = 0.2, wz = 0.4, dt = 0.01;
  ScenarioSpec spec = parse_scenario(flat_scenario("  - {duration_s: 6, vx_mps: 0.3, vy_mps: 0.2, wz_radps: 0.4}\n"), "arc.yaml");
  Simulation sim(spec);
  sim.run();
  ASSERT_EQ(sim.trajectory().size(), 601u);
  const double x0 = 0.5, y0 = -1.0, p0 = deg_to_rad(30.0);
  // From rest to the command the drive needs at most one step (its discretisation of the jump:
  // trapezoid or step): afterwards the pose is the arc at t - delay, delay in [0, dt], read off
  // the heading at the end.
  const double delay = sim.trajectory().back().t_s - angle_diff(sim.trajectory().back().rpy.z(), p0) / wz;
  EXPECT_GE(delay, -1e-9);
  EXPECT_LE(delay, dt + 1e-9);
  double worst = 0.0;
  for (const TrajectorySample& s : sim.trajectory()) {
    if (s.t_s < dt + 1e-9) continue;
    // x' = vx cos(psi) - vy sin(psi), y' = vx sin(psi) + vy cos(psi), psi = p0 + wz t.
    const double te = s.t_s - delay;
    const double p = p0 + wz * te;
    const double x = x0 + (vx * (std::sin(p) - std::sin(p0)) + vy * (std::cos(p) - std::cos(p0))) / wz;
    const double y = y0 + (-vx * (std::cos(p) - std::cos(p0)) + vy * (std::sin(p) - std::sin(p0))) / wz;
    worst = std::max(worst, std::hypot(s.position.x() - x, s.position.y() - y));
    EXPECT_NEAR(angle_diff(s.rpy.z(), p), 0.0, 1e-9) << s.t_s;
    EXPECT_NEAR(s.position.z(), 0.0, 1e-12);
    if (s.t_s > 2.5 * dt) {
      EXPECT_NEAR(s.twist.vx, vx, 1e-9);
      EXPECT_NEAR(s.twist.vy, vy, 1e-9);
      EXPECT_NEAR(s.twist.wz, wz, 1e-9);
    }
  }
  EXPECT_LT(worst, 1e-6);
  const SimulationMetrics m = sim.metrics();
  // Constant speed along the arc (the metric sums chords: relative error (wz dt)^2 / 24).
  EXPECT_NEAR(m.distance_m, (6.0 - delay) * std::hypot(vx, vy), 1e-5);
  EXPECT_EQ(m.collisions, 0);
  EXPECT_EQ(m.steps, 600);
}

TEST(Simulation, ScriptSegmentsAndStopAfterTheEnd) {
  ScenarioSpec spec = parse_scenario(
      flat_scenario("  - {duration_s: 1, vx_mps: 0.5}\n  - {duration_s: 1, vy_mps: -0.25}\n"), "seg.yaml");
  spec.duration_s = 3.0;
  Simulation sim(spec);
  sim.run();
  const double c = std::cos(deg_to_rad(30.0)), s = std::sin(deg_to_rad(30.0));
  // 0.5 m forward, then 0.25 m to the right, then standing still (no lag: stops at once).
  const Vec2 expected = Vec2(0.5, -1.0) + 0.5 * Vec2(c, s) + 0.25 * Vec2(s, -c);
  const TrajectorySample& end = sim.trajectory().back();
  EXPECT_NEAR(end.t_s, 3.0, 1e-12);
  EXPECT_NEAR(end.position.x(), expected.x(), 1e-9);
  EXPECT_NEAR(end.position.y(), expected.y(), 1e-9);
  int commands = 0;
  for (const SimEvent& e : sim.events())
    if (e.kind == "command") ++commands;
  EXPECT_EQ(commands, 3);  // two segments and the end of the script
}

TEST(Simulation, TrajectoryEveryNStepsKeepsTheLastRow) {
  ScenarioSpec spec = parse_scenario(flat_scenario("  - {duration_s: 1.05, vx_mps: 0.2}\n"), "n.yaml");
  spec.outputs.trajectory_every_n_steps = 10;
  Simulation sim(spec);
  sim.run();
  ASSERT_EQ(sim.trajectory().size(), 12u);  // t = 0, 0.1, ..., 1.0 and the last step at 1.05
  EXPECT_NEAR(sim.trajectory()[3].t_s, 0.3, 1e-12);
  EXPECT_NEAR(sim.trajectory().back().t_s, 1.05, 1e-12);
  EXPECT_EQ(sim.metrics().steps, 105);
}

TEST(Simulation, StartWithoutGroundNamesTheStartLine) {
  const ScenarioSpec spec = parse_scenario(
      "world:\n  terrain: {generate: {kind: flat, size_m: [4, 4]}}\nrobot:\n  drive: mecanum\n"
      "  start: {x_m: 9, y_m: 1}\nsim: {duration_s: 1}\n",
      "off.yaml");
  try {
    Simulation sim(spec);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "off.yaml");
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.field(), "robot.start");
  }
}

// A scenario with every random source on: rough terrain (its own seed), gravel, slip, LiDAR
// noise and dropout, IMU noise, encoder slip.
std::string noisy_scenario() {
  return "world:\n"
         "  terrain:\n    generate: {kind: hills, size_m: [12, 8], resolution_m: 0.1, seed: 3, amplitude: 0.2, roughness_m: 0.02}\n"
         "  obstacles:\n    - {kind: gravel, position_m: [3, 4], count: 60, seed: 4}\n"
         "robot:\n  start: {x_m: 1.5, y_m: 4, yaw_deg: 0}\n"
         "vehicle: {rough_slip_sigma: 0.3}\n"
         "sensors:\n"
         "  lidar: {preset: vlp16, horizontal_resolution_deg: 4, noise_sigma_m: 0.02, dropout: 0.05}\n"
         "  imu: {yaw_rate_noise_sigma_radps: 0.01}\n"
         "  encoders: {slip_sigma: 0.05}\n"
         "sim: {dt_s: 0.01, seed: 1}\n"
         "commands:\n  - {duration_s: 4, vx_mps: 0.3, wz_radps: 0.1}\n";
}

std::vector<std::string> record_files(const ScenarioSpec& spec, const fs::path& dir) {
  fs::create_directories(dir);
  Simulation sim(spec);
  sim.run();
  write_simulation_records(sim, dir.string());
  std::vector<std::string> out;
  for (const char* f : {"trajectory.csv", "events.csv", "metrics.json", "lidar.csv", "imu.csv", "encoders.csv"})
    out.push_back(test::read_text((dir / f).string()));
  return out;
}

TEST(Simulation, SameSeedSameBytesDifferentSeedDifferentNoise) {
  test::ScratchDir dir;
  const ScenarioSpec spec = parse_scenario(noisy_scenario(), "noisy.yaml");
  const auto a = record_files(spec, dir.path() / "a");
  const auto b = record_files(spec, dir.path() / "b");
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_FALSE(a[i].empty()) << i;
    EXPECT_EQ(a[i], b[i]) << "file " << i << " differs between two runs with the same seed";
  }
  ScenarioSpec other = spec;
  other.seed = 2;
  const auto c = record_files(other, dir.path() / "c");
  EXPECT_NE(a[3], c[3]) << "lidar.csv: LiDAR noise must follow the seed";
  EXPECT_NE(a[4], c[4]) << "imu.csv: IMU noise must follow the seed";
  EXPECT_NE(a[5], c[5]) << "encoders.csv: encoder slip must follow the seed";
}

TEST(Simulation, ObstacleAppearingIsSeenByTheLidarOnlyWhileItExists) {
  const std::string yaml =
      "world:\n  terrain:\n    generate: {kind: flat, size_m: [10, 6], resolution_m: 0.1}\n"
      "  obstacles:\n"
      "    - {name: late, kind: box, position_m: [4, 3], size_m: [1, 1, 1], appear_s: 1.0, disappear_s: 1.5}\n"
      "robot:\n  start: {x_m: 1, y_m: 3}\n"
      "sensors:\n  lidar: {preset: generic_360, rate_hz: 10}\n"
      "sim: {dt_s: 0.01, duration_s: 2.0}\n";
  ScenarioSpec spec = parse_scenario(yaml, "appear.yaml");
  Simulation sim(spec);
  std::vector<std::pair<double, int>> seen;  // scan time, returns on the box
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [&](const LidarScan& scan) {
    int n = 0;
    for (const Vec3& p : scan.points_world)
      if (std::abs(p.x() - 3.5) < 0.02 && std::abs(p.y() - 3.0) < 0.5) ++n;  // the box's near face
    seen.emplace_back(scan.time, n);
  });
  sim.run();
  ASSERT_EQ(seen.size(), 21u);  // t = 0, 0.1, ..., 2.0
  for (const auto& [t, n] : seen) {
    if (t >= 1.0 - 1e-9 && t < 1.5 - 1e-9) {
      EXPECT_GT(n, 10) << "t = " << t;
    } else {
      EXPECT_EQ(n, 0) << "t = " << t;
    }
  }
  int appear = 0, disappear = 0;
  for (const SimEvent& e : sim.events()) {
    if (e.kind == "appear") {
      ++appear;
      EXPECT_NEAR(e.t_s, 1.0, 1e-9);
      EXPECT_EQ(e.detail, "late");
    }
    if (e.kind == "disappear") ++disappear;
  }
  EXPECT_EQ(appear, 1);
  EXPECT_EQ(disappear, 1);
}

TEST(Simulation, DrivingIntoAWallIsOneCollisionEpisodeAndTheRobotStops) {
  ScenarioSpec spec = parse_scenario(
      flat_scenario("  - {duration_s: 8, vx_mps: 0.4}\n",
                    "  obstacles:\n    - {name: wall, kind: box, position_m: [3, 0], size_m: [0.2, 6, 0.8], yaw_deg: 0}\n"),
      "wall.yaml");
  spec.start = Pose2(0.0, 0.0, 0.0);
  Simulation sim(spec);
  sim.run();
  const SimulationMetrics m = sim.metrics();
  EXPECT_EQ(m.collisions, 1);
  // Never through the wall: the body's front (0.275 m ahead of base_link) stays before x = 2.9.
  for (const TrajectorySample& s : sim.trajectory()) EXPECT_LE(s.position.x() + 0.275, 2.9 + 1e-9);
  EXPECT_GT(m.final_state.position.x() + 0.275, 2.9 - 0.05);  // it got there
  bool named = false;
  for (const SimEvent& e : sim.events())
    if (e.kind == "collision") named = e.detail.find("wall") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(Simulation, E1CrossesThePlatformWithoutCollisions) {
  ScenarioSpec spec = load_scenario(kE1);
  Simulation sim(spec);
  sim.run();
  const SimulationMetrics m = sim.metrics();
  EXPECT_EQ(m.collisions, 0);
  EXPECT_EQ(m.events_by_kind.count("step"), 0u);
  EXPECT_TRUE(m.has_reference);
  EXPECT_LT(m.deviation_max_m, 0.05);
  // 70 s at 0.2 m/s behind a 0.1 s actuator lag: about 14 m, across all four obstacles.
  EXPECT_GT(m.final_state.position.x(), 13.5);
  EXPECT_LT(m.final_state.position.x(), 14.6);
  // The highest point is on the slope step: ramp 0.08 plus step 0.04 above the ground.
  EXPECT_NEAR(m.z_max_m, 0.12, 0.01);
  EXPECT_NEAR(m.z_min_m, 0.0, 0.01);
  // The 9.1 deg ramps show up in the pitch.
  EXPECT_GT(m.pitch_max_abs_rad, deg_to_rad(5.0));
  EXPECT_LT(m.pitch_max_abs_rad, deg_to_rad(15.0));
  EXPECT_EQ(m.lidar_scans, 701);
  EXPECT_EQ(m.lidar_rays, 701 * 5760);
}

TEST(Simulation, DistanceToPolyline) {
  const std::vector<Vec2> line{{0, 0}, {10, 0}, {10, 5}};
  EXPECT_DOUBLE_EQ(distance_to_polyline({5, 2}, line), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_polyline({12, 3}, line), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_polyline({-3, 4}, line), 5.0);
}

TEST(Simulation, PointCloudFormats) {
  const std::vector<Vec3> pts{{1, 2, 3}, {-0.5, 0.25, 0}};
  const std::string ply = format_point_cloud(pts, PointCloudFormat::Ply);
  EXPECT_NE(ply.find("element vertex 2\n"), std::string::npos);
  EXPECT_NE(ply.find("end_header\n1.000000 2.000000 3.000000\n-0.500000 0.250000 0.000000\n"), std::string::npos);
  const std::string pcd = format_point_cloud(pts, PointCloudFormat::Pcd);
  EXPECT_NE(pcd.find("POINTS 2\nDATA ascii\n1.000000 2.000000 3.000000\n"), std::string::npos);
}

// ---- the command -------------------------------------------------------------------------------

TEST(SimCli, WritesEveryFileExitsZeroAndRefusesToOverwrite) {
  test::ScratchDir dir;
  const std::string out = dir.file("run");
  const auto r = test::run_cli({"sim", kE1, "--out", out, "--duration", "3", "--point-clouds", "ply", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"trajectory.csv", "events.csv", "metrics.json", "timing.json", "scene.svg", "height_trace.svg",
                        "track.svg", "lidar.csv", "imu.csv", "encoders.csv", "clouds/scan_000000.ply"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  const auto metrics = nlohmann::ordered_json::parse(test::read_text(out + "/metrics.json"));
  EXPECT_EQ(nlohmann::ordered_json::parse(r.out), metrics);  // --json prints metrics.json
  EXPECT_DOUBLE_EQ(metrics["duration_s"].get<double>(), 3.0);
  const auto timing = nlohmann::json::parse(test::read_text(out + "/timing.json"));
  for (const char* k : {"wall_s", "sim_s", "real_time_factor", "rays_per_s"}) EXPECT_TRUE(timing.contains(k)) << k;
  EXPECT_FALSE(metrics.contains("wall_s"));
  // The first cloud holds the first scan's returns.
  const std::string lidar = test::read_text(out + "/lidar.csv");
  std::istringstream rows(lidar);
  std::string header, first;
  std::getline(rows, header);
  std::getline(rows, first);
  std::vector<std::string> cols;
  std::stringstream ss(first);
  for (std::string c; std::getline(ss, c, ',');) cols.push_back(c);
  ASSERT_EQ(cols.size(), 9u);
  EXPECT_NE(test::read_text(out + "/clouds/scan_000000.ply").find("element vertex " + cols[5] + "\n"), std::string::npos);
  // Without a terminal, progress comes as one line per tenth of the run (readable in CI logs), then
  // (stdout holding the --json document) the files written, every one of them, and nothing else.
  std::istringstream err_lines(r.err);
  int progress_lines = 0;
  std::string wrote;
  for (std::string line; std::getline(err_lines, line);) {
    if (line.rfind("wrote ", 0) == 0 && wrote.empty()) {
      wrote = line;
      continue;
    }
    EXPECT_TRUE(wrote.empty()) << "after the wrote line: " << line;
    EXPECT_EQ(line.rfind("sim: ", 0), 0u) << "not a progress line: " << line;
    ++progress_lines;
  }
  for (const std::string f : {"trajectory.csv", "events.csv", "lidar.csv", "imu.csv", "encoders.csv", "metrics.json", "run.json",
                              "world.json", "clouds/ (31 files)"})
    EXPECT_NE(wrote.find(f), std::string::npos) << f << " missing from: " << wrote;
  EXPECT_GE(progress_lines, 10);
  EXPECT_LE(progress_lines, 12);
  const std::string scene = test::read_text(out + "/scene.svg");
  for (const char* label : {"trajectory", "obstacle", "reference line"}) EXPECT_NE(scene.find(label), std::string::npos) << label;
  const std::string track = test::read_text(out + "/track.svg");
  for (const char* label : {"round_convex", "slope_step", "undulating_ground", "gravel", "reference line"})
    EXPECT_NE(track.find(label), std::string::npos) << label;

  // Again into the same folder: refused without --force, byte-identical records with it.
  const auto again = test::run_cli({"sim", kE1, "--out", out, "--duration", "3"});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  const std::string before = test::read_text(out + "/trajectory.csv");
  const auto forced = test::run_cli({"sim", kE1, "--out", out, "--duration", "3", "--force", "--quiet"});
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_EQ(test::read_text(out + "/trajectory.csv"), before);
  EXPECT_EQ(test::read_text(out + "/metrics.json"), metrics.dump(2) + "\n");
  EXPECT_FALSE(fs::exists(fs::path(out) / "clouds")) << "stale clouds are removed";
}

TEST(SimCli, BadScenarioExitsTwoWithOneErrorLine) {
  test::ScratchDir dir;
  const std::string bad = dir.file("bad.yaml");
  test::write_text(bad, "world:\n  obstacles:\n    - {kind: box, position_m: [1, 1], size_m: [1, -1, 1]}\nsim: {duration_s: 1}\n");
  const auto r = test::run_cli({"sim", bad, "--out", dir.file("o")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "starnav: error: " + bad + ":3: world.obstacles[0].size_m: every size must be > 0\n");
  const auto seed = test::run_cli({"sim", kE1, "--out", dir.file("o2"), "--seed", "x"});
  EXPECT_EQ(seed.exit_code, 2);
  EXPECT_NE(seed.err.find("--seed"), std::string::npos);
  const auto missing = test::run_cli({"sim", dir.file("none.yaml"), "--out", dir.file("o3")});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1);
}

}  // namespace
}  // namespace starnav
