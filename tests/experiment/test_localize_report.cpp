// starnav localize as a library call and through the CLI: a small room map, scans by exact ray
// casting against its boxes, odometry that over-reads distance and turns, a reference log holding
// the true poses of every fifth scan (paired by identical ranges); AMCL converges, and the
// matched-error statistics are recomputed by hand from the trajectory and the truth. Bad inputs
// through the CLI: a garbage --initial, a missing map, an unreadable log, a bad --set, and the
// overwrite rule.
#include <gtest/gtest.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/experiment/localize_report.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "support/box_world.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::Box;

// A 7 m x 5 m room at 0.05 m with its origin at (0, 0): walls, a partition and three boxes, all on
// cell boundaries, so the occupied squares are the boxes exactly.
const std::vector<Box>& loc_room_boxes() {
  static const std::vector<Box> boxes = {
      {0.0, 0.0, 7.0, 0.1}, {0.0, 4.9, 7.0, 5.0}, {0.0, 0.0, 0.1, 5.0}, {6.9, 0.0, 7.0, 5.0},  // walls
      {3.5, 0.1, 3.6, 1.6},                                                                    // partition
      {1.0, 3.5, 1.6, 4.0}, {5.2, 3.0, 5.5, 3.7}, {5.6, 0.8, 6.2, 1.1}};
  return boxes;
}

OccupancyGrid loc_room_grid() {
  GridGeometry g;
  g.width = 140;
  g.height = 100;
  g.resolution = 0.05;
  return test::rasterise_boxes(g, loc_room_boxes());
}

constexpr double kLocRangeMax = 8.0;

// 181 beams over -90..+90 deg from `pose` (laser = base), ranges at 1 cm as the raw logs print them.
LogScan loc_scan(const Pose2& pose, std::int64_t stamp_us) {
  LogScan s;
  s.stamp_us = stamp_us;
  s.angle_min_rad = -kPi / 2;
  s.angle_increment_rad = kPi / 180;
  s.range_max_m = kLocRangeMax;
  for (int i = 0; i < 181; ++i) {
    const double r = test::cast_to_boxes(loc_room_boxes(), pose.x, pose.y, pose.yaw + s.angle(static_cast<std::size_t>(i)));
    s.ranges_m.push_back(static_cast<float>(std::min(kLocRangeMax, std::round(r * 100.0) / 100.0)));
  }
  return s;
}

struct LocDrive {
  RobotLog raw, reference;
  std::vector<Pose2> truth;  // per raw scan
};

// A loop round the room, 0.1 m and at most 9 deg per scan; the robot stands still for the first two
// scans (identical ranges: no unique twin). The odometry reads 4 % too far and turns 5 % too much.
// The reference holds the true pose of every fifth scan.
LocDrive loc_drive() {
  const std::vector<Vec2> corners = {{1.0, 1.0}, {3.0, 1.0}, {3.0, 2.5}, {6.0, 2.2}, {6.0, 4.2}, {2.5, 4.4}, {2.4, 2.8}, {0.8, 2.8}, {1.0, 1.0}};
  LocDrive d;
  Pose2 p(1.0, 1.0, 0.0);
  d.truth.push_back(p);
  d.truth.push_back(p);
  for (std::size_t c = 1; c < corners.size(); ++c) {
    const double heading = std::atan2(corners[c].y() - p.y, corners[c].x() - p.x);
    while (std::abs(angle_diff(heading, p.yaw)) > 1e-9) {
      const double turn = std::clamp(angle_diff(heading, p.yaw), -deg_to_rad(9.0), deg_to_rad(9.0));
      p.yaw = wrap_angle(p.yaw + turn);
      d.truth.push_back(p);
    }
    const double length = (corners[c] - p.translation()).norm();
    const int steps = static_cast<int>(std::ceil(length / 0.1));
    const Vec2 from = p.translation();
    for (int k = 1; k <= steps; ++k) {
      const Vec2 q = from + (corners[c] - from) * (static_cast<double>(k) / steps);
      p = Pose2(q.x(), q.y(), heading);
      d.truth.push_back(p);
    }
  }
  Pose2 odom(5.0, -3.0, 1.0);  // the odom frame is not the map frame
  for (std::size_t i = 0; i < d.truth.size(); ++i) {
    if (i > 0) {
      const Pose2 step = d.truth[i - 1].inverse().compose(d.truth[i]);
      odom = odom.compose(Pose2(step.x * 1.04, step.y * 1.04, step.yaw * 1.05));
    }
    LogScan s = loc_scan(d.truth[i], static_cast<std::int64_t>(i) * 200'000);
    s.odometry = odom;
    s.source_index = i + 1;
    d.raw.scans.push_back(s);
    if (i % 5 == 0) {
      LogScan r = s;
      r.odometry = d.truth[i];
      r.laser_pose = d.truth[i];
      d.reference.scans.push_back(std::move(r));
    }
  }
  d.raw.laser_in_base = Pose2();
  return d;
}

std::vector<ParamSetting> loc_settings() {
  return {{"min_particles", "200", "", 0, "amcl.min_particles"},
          {"max_particles", "1000", "", 0, "amcl.max_particles"},
          {"update_min_d_m", "0.05", "", 0, "amcl.update_min_d_m"},
          {"update_min_a_deg", "5", "", 0, "amcl.update_min_a_deg"},
          {"sigma_hit_m", "0.1", "", 0, "amcl.sigma_hit_m"}};
}

double loc_hand_quantile(const std::vector<double>& sorted, double q) {
  const double h = q * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

TEST(LocalizeReport, PairsScansByUniqueIdenticalRanges) {
  const auto scan = [](std::vector<float> r, std::optional<Pose2> pose = {}) {
    LogScan s;
    s.ranges_m = std::move(r);
    s.laser_pose = pose;
    return s;
  };
  RobotLog raw, ref;
  raw.scans = {scan({1.25f, 2.5f}), scan({3.0f, 0.35f}), scan({3.0f, 0.35f}), scan({7.0f, 7.0f}), scan({4.0f, 4.01f}),
               scan({9.0f})};
  // %g prints of the same readings; one twin twice; a scan without a pose; a reading 1 cm off.
  ref.scans = {scan({1.25f, 2.50f}, Pose2(1, 0, 0)), scan({3.00f, 0.35f}, Pose2(2, 0, 0)), scan({7.0f, 7.0f}, Pose2(3, 0, 0)),
               scan({7.0f, 7.0f}, Pose2(4, 0, 0)), scan({4.0f, 4.02f}, Pose2(5, 0, 0)), scan({9.0f})};
  const std::vector<std::optional<std::size_t>> m = match_scans_by_ranges(raw, ref);
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m[0], std::optional<std::size_t>(0));
  EXPECT_FALSE(m[1]);  // two raw scans share the readings
  EXPECT_FALSE(m[2]);
  EXPECT_FALSE(m[3]);  // two reference scans share them
  EXPECT_FALSE(m[4]);  // 1 cm apart
  EXPECT_FALSE(m[5]);  // the reference scan has no pose
}

TEST(LocalizeReport, ConvergesInARoomAndItsErrorStatisticsAreTheMatchedScansErrors) {
  const LocDrive d = loc_drive();
  ASSERT_GT(d.truth.size(), 150u);
  const OccupancyGrid grid = loc_room_grid();
  LocalizeRunRequest q;
  q.log = "room.clf";
  q.initial.kind = LocalizeStart::Pose;
  q.initial.pose = Pose2(d.truth[0].x + 0.3, d.truth[0].y - 0.2, deg_to_rad(8.0));
  q.settings = loc_settings();
  std::size_t calls = 0;
  const LocalizeRunResult r = run_localize(d.raw, grid, OccupancyThresholds{}, &d.reference, q, [&](std::size_t, std::size_t) { ++calls; });
  EXPECT_GT(calls, 1u);
  EXPECT_EQ(r.trajectory.size(), d.truth.size());
  // Every fifth scan has a twin, except scan 0 (scans 0 and 1 are the same).
  std::size_t expected_matched = 0;
  for (std::size_t i = 5; i < d.truth.size(); i += 5) ++expected_matched;
  EXPECT_EQ(r.matched, expected_matched);
  ASSERT_EQ(r.errors.size(), expected_matched);
  ASSERT_TRUE(r.converged_at_update.has_value());
  ASSERT_TRUE(r.converged_at_scan.has_value());
  EXPECT_LT(*r.converged_at_update, 40);
  EXPECT_GT(r.updates, 50);

  // The errors by hand: the trajectory at each matched scan against the truth.
  std::vector<double> m, deg;
  for (std::size_t i = 5; i < d.truth.size(); i += 5) {
    const LocalizePose& p = r.trajectory[i];
    ASSERT_EQ(p.scan, i);
    if (i < *r.converged_at_scan) continue;
    m.push_back(std::hypot(p.pose.x - d.truth[i].x, p.pose.y - d.truth[i].y));
    deg.push_back(std::abs(rad_to_deg(wrap_angle(p.pose.yaw - d.truth[i].yaw))));
  }
  ASSERT_GT(m.size(), 20u);
  std::sort(m.begin(), m.end());
  std::sort(deg.begin(), deg.end());
  const auto median = [](const std::vector<double>& v) {
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  ASSERT_EQ(r.after_m.n, m.size());
  EXPECT_NEAR(r.after_m.median, median(m), 1e-12);
  EXPECT_NEAR(r.after_m.p90, loc_hand_quantile(m, 0.9), 1e-12);
  EXPECT_NEAR(r.after_m.max, m.back(), 1e-12);
  EXPECT_NEAR(r.after_deg.median, median(deg), 1e-9);
  EXPECT_NEAR(r.after_deg.p90, loc_hand_quantile(deg, 0.9), 1e-9);
  EXPECT_NEAR(r.after_deg.max, deg.back(), 1e-9);
  // Converged: a few centimetres on a noiseless map despite the odometry's 4 % and 5 %.
  EXPECT_LT(r.after_m.median, 0.05);
  EXPECT_LT(r.after_m.max, 0.15);
  EXPECT_LT(r.after_deg.median, 2.0);
  // The odometry alone ends far off (the drift is real).
  const Pose2 odom_end = d.raw.scans.front().odometry->inverse().compose(*d.raw.scans.back().odometry);
  const Pose2 true_end = d.truth.front().inverse().compose(d.truth.back());
  EXPECT_GT(std::hypot(odom_end.x - true_end.x, odom_end.y - true_end.y), 0.3);

  // The files say the same.
  const test::ScratchDir dir;
  write_localize_outputs(r, dir.file("out"));
  const std::string traj = test::read_text(dir.file("out/trajectory.csv"));
  const std::string errors = test::read_text(dir.file("out/errors.csv"));
  EXPECT_EQ(traj.rfind("t_s,x_m,y_m,yaw_rad,converged,particles\n", 0), 0u);
  EXPECT_EQ(static_cast<std::size_t>(std::count(traj.begin(), traj.end(), '\n')), r.trajectory.size() + 1);
  EXPECT_EQ(errors.rfind("t_s,err_m,err_deg,converged\n", 0), 0u);
  EXPECT_EQ(static_cast<std::size_t>(std::count(errors.begin(), errors.end(), '\n')), r.errors.size() + 1);
  const nlohmann::json j = nlohmann::json::parse(test::read_text(dir.file("out/summary.json")));
  EXPECT_EQ(j["matched"], expected_matched);
  EXPECT_EQ(j["updates_until_converged"], *r.converged_at_update);
  EXPECT_EQ(j["error_after_convergence"]["count"], m.size());
  EXPECT_DOUBLE_EQ(j["error_after_convergence"]["m"]["median"].get<double>(), r.after_m.median);
  EXPECT_EQ(j["amcl"]["max_particles"], 1000);
  EXPECT_EQ(j["amcl"]["robot_model_type"], "differential");
  EXPECT_EQ(j["overrides"]["amcl.sigma_hit_m"], 0.1);
  EXPECT_TRUE(std::filesystem::file_size(dir.file("out/map.png")) > 1000);

  // The run record: a step per filter update (and the first scan), each with the estimate the
  // trajectory has at that scan, at most 200 particles, and the true pose where the reference has
  // the scan; the known map from the start; run.json of kind localization.
  std::vector<nlohmann::json> steps;
  {
    std::istringstream in(test::read_text(dir.file("out/steps.jsonl")));
    for (std::string line; std::getline(in, line);) steps.push_back(nlohmann::json::parse(line));
  }
  std::size_t updates_seen = 0, references = 0;
  for (const LocalizePose& p : r.trajectory) updates_seen += p.updated ? 1 : 0;
  EXPECT_EQ(steps.size(), updates_seen + (r.trajectory.front().updated ? 0 : 1));
  std::size_t k = 0;
  for (const LocalizePose& p : r.trajectory) {
    if (k >= steps.size() || !(p.updated || k == 0)) continue;
    const auto& s = steps[k++];
    EXPECT_NEAR(s["t_s"].get<double>(), static_cast<double>(p.stamp_us) * 1e-6, 5e-4);
    EXPECT_NEAR(s["estimate"][0].get<double>(), p.pose.x, 5e-4);
    EXPECT_NEAR(s["estimate"][1].get<double>(), p.pose.y, 5e-4);
    EXPECT_LE(s["particles"].size(), 200u);
    EXPECT_GE(s["particles"].size(), 1u);
    if (s.contains("reference")) {
      ++references;
      EXPECT_NEAR(s["reference"][0].get<double>(), d.truth[p.scan].x, 5e-4);
      EXPECT_NEAR(s["reference"][1].get<double>(), d.truth[p.scan].y, 5e-4);
    }
  }
  EXPECT_GT(references, 5u);
  const auto world = nlohmann::json::parse(test::read_text(dir.file("out/world.json")));
  std::vector<int> cells;
  for (std::size_t i = 0; i + 1 < world["nav_map"]["initial"].size(); i += 2)
    cells.insert(cells.end(), world["nav_map"]["initial"][i + 1].get<std::size_t>(), world["nav_map"]["initial"][i].get<int>());
  ASSERT_EQ(cells.size(), grid.cell_count());
  for (std::size_t i = 0; i < cells.size(); ++i) ASSERT_EQ(cells[i], grid[i]) << i;
  const auto manifest = nlohmann::json::parse(test::read_text(dir.file("out/run.json")));
  EXPECT_EQ(manifest["kind"], "localization");
  EXPECT_EQ(manifest["log"]["name"], "room.clf");
}

// A log's defaults (every scan, 180 beams, sigma_hit 0.1; more for a global start) are what an
// explicit --set of the same values gives, byte for byte, and the user's own values win over them.
TEST(LocalizeReport, TheLogDefaultsEqualTheSameValuesSetByHandAndGiveWayToTheUsers) {
  const LocDrive d = loc_drive();
  const OccupancyGrid grid = loc_room_grid();
  LocalizeRunRequest q;
  q.log = "room.clf";
  q.initial.kind = LocalizeStart::Pose;
  q.initial.pose = Pose2(d.truth[0].x + 0.3, d.truth[0].y - 0.2, deg_to_rad(8.0));
  const auto poses = [](const LocalizeRunResult& r) {
    std::vector<std::array<double, 3>> out;
    for (const LocalizePose& p : r.trajectory) out.push_back({p.pose.x, p.pose.y, p.pose.yaw});
    return out;
  };
  const auto value_of = [](const LocalizeRunResult& r, const std::string& key) {
    for (const auto& [k, v] : r.amcl)
      if (k == key) return v;
    return std::string("(missing)");
  };
  const LocalizeRunResult defaults = run_localize(d.raw, grid, OccupancyThresholds{}, &d.reference, q, {});
  EXPECT_EQ(value_of(defaults, "update_min_d_m"), "0");
  EXPECT_EQ(value_of(defaults, "max_beams"), "180");
  EXPECT_EQ(value_of(defaults, "sigma_hit_m"), "0.1");
  EXPECT_TRUE(defaults.overrides.empty());
  q.settings = {{"update_min_d_m", "0", "", 0, "--set amcl.update_min_d_m"},
                {"update_min_a_deg", "0", "", 0, "--set amcl.update_min_a_deg"},
                {"max_beams", "180", "", 0, "--set amcl.max_beams"},
                {"sigma_hit_m", "0.1", "", 0, "--set amcl.sigma_hit_m"}};
  const LocalizeRunResult by_hand = run_localize(d.raw, grid, OccupancyThresholds{}, &d.reference, q, {});
  EXPECT_EQ(poses(defaults), poses(by_hand));
  EXPECT_EQ(by_hand.overrides.size(), 4u);
  q.settings = {{"max_beams", "30", "", 0, "--set amcl.max_beams"}};
  const LocalizeRunResult users = run_localize(d.raw, grid, OccupancyThresholds{}, &d.reference, q, {});
  EXPECT_EQ(value_of(users, "max_beams"), "30");
  EXPECT_EQ(value_of(users, "update_min_d_m"), "0");
  EXPECT_NE(poses(users), poses(defaults));
  // A global start adds the search phase's particles and recovery.
  const std::vector<ParamSetting> global = localize_log_defaults(LocalizeStart::Global);
  for (const char* key : {"max_particles", "recovery_alpha_slow", "recovery_alpha_fast", "scan_proposal"})
    EXPECT_TRUE(std::any_of(global.begin(), global.end(), [&](const ParamSetting& s) { return s.key == key; })) << key;
}

TEST(LocalizeReport, FirstStartsAtTheFirstMatchedScanFromItsReferencePose) {
  const LocDrive d = loc_drive();
  LocalizeRunRequest q;
  q.initial.kind = LocalizeStart::FirstMatched;
  q.settings = loc_settings();
  const LocalizeRunResult r = run_localize(d.raw, loc_room_grid(), OccupancyThresholds{}, &d.reference, q);
  EXPECT_EQ(r.start_scan, 5u);  // scan 0 has no unique twin
  EXPECT_EQ(r.initial_pose.x, d.truth[5].x);
  EXPECT_EQ(r.initial_pose.y, d.truth[5].y);
  EXPECT_EQ(r.trajectory.front().scan, 5u);
  EXPECT_EQ(r.trajectory.size(), d.truth.size() - 5);
  ASSERT_TRUE(r.converged_at_update.has_value());
  EXPECT_LT(r.after_m.median, 0.05);
  // Without a reference, 'first' has nothing to start from; amcl.initial is --initial's job.
  EXPECT_NE(test::error_of([&] { run_localize(d.raw, loc_room_grid(), OccupancyThresholds{}, nullptr, q); }).find("--initial"),
            std::string::npos);
  q.initial.kind = LocalizeStart::Global;
  q.settings.push_back({"initial", "global", "", 0, "--set amcl.initial"});
  EXPECT_NE(test::error_of([&] { run_localize(d.raw, loc_room_grid(), OccupancyThresholds{}, &d.reference, q); }).find("--set amcl.initial"),
            std::string::npos);
}

// The CLI on files: the room map as map_server YAML, the raw and reference logs as CARMEN.
class LocalizeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const LocDrive d = loc_drive();
    write_ros_map(loc_room_grid(), dir_.file("room.yaml"));
    test::write_text(dir_.file("raw.clf"), carmen_log_text(d.raw));
    test::write_text(dir_.file("ref.clf"), carmen_log_text(d.reference));
  }
  std::vector<std::string> args(std::vector<std::string> extra) const {
    std::vector<std::string> a = {"localize", dir_.file("raw.clf"), "--map", dir_.file("room.yaml"), "--out", dir_.file("out"), "--quiet"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  static void expect_one_line_error(const test::CliResult& r, const std::string& needle) {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  }
  test::ScratchDir dir_;
};

TEST_F(LocalizeCli, RunsWithAReferenceAndRefusesToOverwrite) {
  const std::vector<std::string> a =
      args({"--reference", dir_.file("ref.clf"), "--set", "amcl.max_particles=1000", "--set", "amcl.update_min_d_m=0.05", "--json"});
  const test::CliResult r = test::run_cli(a);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["initial"]["mode"], "first");
  EXPECT_EQ(j["initial"]["start_scan"], 5);
  EXPECT_EQ(j["converged"], true);
  EXPECT_LT(j["error_after_convergence"]["m"]["median"].get<double>(), 0.05);
  for (const std::string& f : localize_output_files()) EXPECT_TRUE(std::filesystem::exists(dir_.file("out/" + f))) << f;
  expect_one_line_error(test::run_cli(a), "--out");
  std::vector<std::string> forced = a;
  forced.push_back("--force");
  EXPECT_EQ(test::run_cli(forced).exit_code, 0);
}

TEST_F(LocalizeCli, BadInputsAreOneLineErrorsNamingTheFileOrFlag) {
  for (const char* bad : {"garbage", "1,2", "1,2,3,4", "1,nan,3", "Global"})
    expect_one_line_error(test::run_cli(args({"--initial", bad})), "--initial");
  // 'first' (the default) needs a reference.
  expect_one_line_error(test::run_cli(args({})), "--initial");
  {
    std::vector<std::string> a = args({"--initial", "1,1,0"});
    a[3] = dir_.file("missing.yaml");
    const test::CliResult r = test::run_cli(a);
    expect_one_line_error(r, "missing.yaml");
    EXPECT_NE(r.err.find("--map"), std::string::npos) << r.err;
  }
  {
    test::write_text(dir_.file("junk.clf"), "FLASER 3 1.0 zz\n");
    std::vector<std::string> a = args({"--initial", "1,1,0"});
    a[1] = dir_.file("junk.clf");
    expect_one_line_error(test::run_cli(a), "junk.clf");
  }
  expect_one_line_error(test::run_cli(args({"--initial", "global", "--set", "alpha1=0.3"})), "--set alpha1");
  expect_one_line_error(test::run_cli(args({"--initial", "global", "--set", "amcl.alpha1=-1"})), "--set amcl.alpha1");
  expect_one_line_error(test::run_cli(args({"--initial", "global", "--set", "amcl.no_such_key=1"})), "no_such_key");
  {
    const test::CliResult r = test::run_cli(args({"--initial", "global", "--reference", dir_.file("noref.clf")}));
    expect_one_line_error(r, "noref.clf");
    EXPECT_NE(r.err.find("--reference"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.file("out")));
}

}  // namespace
}  // namespace starnav
