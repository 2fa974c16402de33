// Occupancy mapping with known poses: the grid traversal against a brute-force walk along the
// segment, the log-odds update against its closed form (one update per cell and scan, hits over
// pass-throughs), a room mapped from analytic scans against its walls, growth and its bound, maps
// from logs (poses of the log, truth, a trajectory file), and on ../shared/ the intel corrected
// log mapped so that its own readings land on occupied cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/occupancy_mapping.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using CellKey = std::pair<std::int64_t, std::int64_t>;

// Length (in cells) of the part of segment a-b inside cell c (Liang-Barsky clipping).
double length_inside(const Vec2& a, const Vec2& b, const CellKey& c) {
  double t0 = 0.0, t1 = 1.0;
  const double d[2] = {b.x() - a.x(), b.y() - a.y()}, p0[2] = {a.x(), a.y()};
  const double lo[2] = {static_cast<double>(c.first), static_cast<double>(c.second)};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (p0[k] < lo[k] || p0[k] > lo[k] + 1) return 0.0;
      continue;
    }
    double ta = (lo[k] - p0[k]) / d[k], tb = (lo[k] + 1 - p0[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  return t1 > t0 ? (t1 - t0) * std::hypot(d[0], d[1]) : 0.0;
}

TEST(GridTraversal, VisitsTheCellsABruteForceWalkFindsInOrder) {
  Rng rng(7);
  int extra_total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec2 a(rng.uniform(-20, 20), rng.uniform(-20, 20));
    const Vec2 b = trial % 10 == 0 ? Vec2(a.x() + rng.uniform(-0.4, 0.4), a.y()) : Vec2(rng.uniform(-20, 20), rng.uniform(-20, 20));
    std::vector<CellKey> dda;
    for_each_cell_on_segment(a, b, 1.0, [&](std::int64_t x, std::int64_t y, bool) { dda.push_back({x, y}); });
    // Brute force: 100,000 samples along the segment.
    std::set<CellKey> brute;
    const int n = 100000;
    for (int k = 0; k < n; ++k) {
      const Vec2 p = a + ((k + 0.5) / n) * (b - a);
      brute.insert({static_cast<std::int64_t>(std::floor(p.x())), static_cast<std::int64_t>(std::floor(p.y()))});
    }
    const std::set<CellKey> dda_set(dda.begin(), dda.end());
    ASSERT_EQ(dda_set.size(), dda.size()) << "a cell visited twice";
    for (const CellKey& c : brute) EXPECT_TRUE(dda_set.count(c)) << "missed a cell, trial " << trial;
    // Cells the samples did not hit: only slivers thinner than the sampling step.
    const double step = (b - a).norm() / n;
    for (const CellKey& c : dda_set)
      if (!brute.count(c)) {
        ++extra_total;
        EXPECT_LT(length_inside(a, b, c), 2 * step) << "trial " << trial;
      }
    // 4-connected, from a's cell to b's.
    EXPECT_EQ(dda.front(), CellKey(std::floor(a.x()), std::floor(a.y())));
    EXPECT_EQ(dda.back(), CellKey(std::floor(b.x()), std::floor(b.y())));
    for (std::size_t i = 1; i < dda.size(); ++i)
      EXPECT_EQ(std::abs(dda[i].first - dda[i - 1].first) + std::abs(dda[i].second - dda[i - 1].second), 1);
  }
  EXPECT_LT(extra_total, 20);  // slivers are rare
}

double logit(double p) { return std::log(p / (1 - p)); }

TEST(OccupancyMapper, OneUpdatePerCellAndScanAndHitsWinOverPassThroughs) {
  OccupancyMappingParams p;
  p.resolution_m = 0.1;
  OccupancyMapper m(p);
  // 50 beams from (0.05, 0.05) fanning out over 10 degrees: all cross the sensor's neighbour cells.
  std::vector<float> ranges(50, 2.0f);
  m.add_rays(Pose2(0.05, 0.05, 0.0), -deg_to_rad(5), deg_to_rad(10) / 49, ranges, 0.0, 10.0);
  EXPECT_NEAR(m.log_odds_at({0.25, 0.05}), logit(0.4), 1e-6);  // once, not 50 times
  EXPECT_NEAR(m.log_odds_at({2.05, 0.05}), logit(0.7), 1e-6);
  // Second scan: beam 0 passes through (0.55, 0.05) and beam 1 ends there.
  m.add_rays(Pose2(0.05, 0.05, 0.0), 0.0, 0.0, {1.0f, 0.52f}, 0.0, 10.0);
  EXPECT_NEAR(m.log_odds_at({0.55, 0.05}), logit(0.4) + logit(0.7), 1e-6);
  // Clamping.
  for (int i = 0; i < 100; ++i) m.add_rays(Pose2(0.05, 0.05, 0.0), 0.0, 0.0, {2.0f}, 0.0, 10.0);
  EXPECT_NEAR(m.log_odds_at({2.05, 0.05}), logit(0.97), 1e-6);
  EXPECT_NEAR(m.log_odds_at({1.05, 0.05}), logit(0.12), 1e-6);
  EXPECT_EQ(m.log_odds_at({-50, -50}), 0.0);
}

// Distance from p along direction a to the walls of [0, w] x [0, h] (p inside).
double to_walls(const Vec2& p, double a, double w, double h) {
  const double c = std::cos(a), s = std::sin(a);
  double t = 1e9;
  if (c > 1e-12) t = std::min(t, (w - p.x()) / c);
  if (c < -1e-12) t = std::min(t, -p.x() / c);
  if (s > 1e-12) t = std::min(t, (h - p.y()) / s);
  if (s < -1e-12) t = std::min(t, -p.y() / s);
  return t;
}

TEST(OccupancyMapper, AMappedRoomHasItsWallsOccupiedItsInsideFreeAndItsOutsideUnknown) {
  const double w = 4.0, h = 3.0;
  OccupancyMappingParams p;  // 0.05 m
  OccupancyMapper m(p);
  // Five scans: each lowers a free cell's log-odds by logit(0.4), and map_server's free threshold
  // (0.196) needs four of them.
  for (const Pose2& pose : {Pose2(1.0, 1.0, 0.3), Pose2(3.0, 2.0, -2.0), Pose2(2.0, 1.5, 1.0), Pose2(0.8, 2.2, 2.5),
                            Pose2(3.2, 0.7, -0.4)}) {
    std::vector<float> ranges;
    const int n = 720;
    const double inc = 2 * kPi / n;
    for (int i = 0; i < n; ++i) {
      const double d = to_walls(pose.translation(), pose.yaw - kPi + i * inc, w, h);
      // Every 10th beam returns nothing (a no-return value beyond range_max).
      ranges.push_back(i % 10 == 0 ? 30.0f : static_cast<float>(d + 1e-4));
    }
    m.add_rays(pose, -kPi, inc, ranges, 0.1, 25.0);
  }
  const OccupancyGrid g = m.grid();
  auto value = [&](double x, double y) {
    const Vec2 c = g.geometry().world_to_cell_continuous({x, y});
    return g.at(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
  };
  for (double s = 0.1; s < 3.9; s += 0.2) {
    EXPECT_GE(value(s, h + 0.01), 65) << "north wall at x " << s;
    EXPECT_GE(value(s, -0.01), 65) << "south wall at x " << s;  // readings end just beyond y = 0
  }
  for (double s = 0.1; s < 2.9; s += 0.2) {
    EXPECT_GE(value(w + 0.01, s), 65) << "east wall at y " << s;
    EXPECT_GE(value(-0.01, s), 65) << "west wall at y " << s;
  }
  for (double x = 0.3; x < 3.7; x += 0.25)
    for (double y = 0.3; y < 2.7; y += 0.25) EXPECT_LE(value(x, y), 19) << x << ", " << y;
  // Nothing beyond the walls: the grid ends within a cell or two of them.
  EXPECT_GE(g.origin().x, -0.1 - 1e-9);
  EXPECT_GE(g.origin().y, -0.1 - 1e-9);
  EXPECT_LE(g.origin().x + g.width() * g.resolution(), w + 0.1 + 1e-9);
  EXPECT_NEAR(std::fmod(std::abs(g.origin().x), 0.05), 0.0, 1e-9);  // on the lattice
}

// The viewer's map updates: replaying every scan's class changes over an all-unknown grid gives
// map_server's trinary reading of the final map, cell for cell, while the grid grows under it.
TEST(OccupancyMapper, ReplayingTheTrackedChangesGivesTheFinalMapsClasses) {
  OccupancyMapper m;
  m.track_changes(true);
  std::map<std::pair<std::int64_t, std::int64_t>, int> replay;
  std::size_t changes = 0;
  for (int k = 0; k < 12; ++k) {
    const Pose2 pose(0.5 + 0.4 * k, 1.0 + 0.2 * std::sin(k), 0.3 * k);
    std::vector<float> ranges;
    for (int i = 0; i < 360; ++i) ranges.push_back(static_cast<float>(to_walls(pose.translation(), pose.yaw - kPi + i * kPi / 180, 6.0, 3.0)));
    m.add_rays(pose, -kPi, kPi / 180, ranges, 0.1, 25.0);
    for (const MapCellChange& c : m.last_changes()) {
      replay[{c.ix, c.iy}] = c.value;
      ++changes;
    }
  }
  EXPECT_GT(changes, 100u);
  const OccupancyGrid g = m.grid();
  const auto x0 = static_cast<std::int64_t>(std::llround(g.origin().x / g.resolution()));
  const auto y0 = static_cast<std::int64_t>(std::llround(g.origin().y / g.resolution()));
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const int v = g(x, y);
      // The classes of the written map: its rounded percent as map_saver writes it (thresholds included).
      const int expected = v < 0 ? -1 : (v >= 65 ? 100 : (v <= 20 ? 0 : -1));
      const auto it = replay.find({x0 + x, y0 + y});
      ASSERT_EQ(it == replay.end() ? -1 : it->second, expected) << "cell " << x << ", " << y << " (" << v << "%)";
    }
  // Off, nothing is tracked.
  OccupancyMapper quiet;
  quiet.add_rays(Pose2(1, 1, 0), -kPi, kPi / 180, std::vector<float>(360, 1.0f), 0.1, 25.0);
  EXPECT_TRUE(quiet.last_changes().empty());
}

TEST(OccupancyMapper, GrowsFarAndRefusesAbsurdExtents) {
  OccupancyMapper m;
  m.add_rays(Pose2(0, 0, 0), 0, 0, {1.0f}, 0, 10);
  m.add_rays(Pose2(150, -80, 0), 0, 0, {1.0f}, 0, 10);
  EXPECT_GT(m.log_odds_at({151.02, -79.98}), 0.0);
  EXPECT_GT(m.log_odds_at({1.02, 0.02}), 0.0);
  EXPECT_THROW(m.add_rays(Pose2(1e7, 1e7, 0), 0, 0, {1.0f}, 0, 10), Error);
  EXPECT_THROW(m.add_rays(Pose2(NAN, 0, 0), 0, 0, {1.0f}, 0, 10), Error);
  OccupancyMappingParams bad;
  bad.hit_probability = 0.3;
  EXPECT_THROW(OccupancyMapper{bad}, Error);
}

// Beams without a return clear no_return_clear_m (cut to max_range_m) whatever the scene: one scan
// all round spans a square of 2 ceil(reach / resolution) + 1 cells a side, which the map must hold.
// Parameters whose square passes the map's cells are refused before any cell exists, naming both.
TEST(OccupancyMapper, ParametersWhoseOneScanPassesTheMapsCellsAreRefused) {
  struct Row {
    double no_return_clear_m, max_range_m, resolution_m;
    double side;  // cells a side of one scan's square; 0: accepted
  };
  const std::vector<Row> rows = {
      {1000, 0, 0.005, 400001},  // the attack's: 1.6e11 cells
      {1000, 50, 0.005, 20001},  // cut to max_range_m: 4e8 cells
      {300, 0, 0.05, 12001},     // 1.44e8 cells
      {1000, 10, 0.005, 0},      // 4001^2 = 1.6e7 cells
      {200, 0, 0.05, 0},         // 8001^2 = 6.4e7 cells, below 2^26 = 6.7e7
      {0, 0, 0.005, 0},          // no clearing
  };
  for (const Row& r : rows) {
    OccupancyMappingParams p;
    p.no_return_clear_m = r.no_return_clear_m;
    p.max_range_m = r.max_range_m;
    p.resolution_m = r.resolution_m;
    SCOPED_TRACE(std::to_string(r.no_return_clear_m) + " m at " + std::to_string(r.resolution_m) + " m");
    if (r.side == 0) {
      EXPECT_NO_THROW(OccupancyMapper{p});
      continue;
    }
    try {
      OccupancyMapper m(p);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "no_return_clear_m");
      const std::string what = e.what();
      EXPECT_NE(what.find("resolution_m"), std::string::npos) << what;
      EXPECT_NE(what.find(format_number(r.side) + " x " + format_number(r.side) + " cells, more than the 67108864"), std::string::npos)
          << what;
    }
  }
}

TEST(OccupancyMapper, WildCoordinatesAreRefusedBeforeAnyCellIsTouched) {
  // Each pose or reading is refused with the same error, and the mapper is as it was: no index was
  // computed from it (floor(1e19 / 0.05) does not fit an int64) and nothing was allocated for it.
  struct Case {
    Pose2 pose;
    std::vector<float> ranges;
    double range_max;
    const char* says;
  };
  const std::vector<Case> cases = {
      {Pose2(1e19, 0, 0), {1.0f}, 10, "reaches at most"},
      {Pose2(0, -1e300, 0), {1.0f}, 10, "reaches at most"},
      {Pose2(0, 0, 0), {1e30f}, kInfinity, "reaches at most"},  // a reading below an infinite range_max
      // 2e7 m from the map at 5 cm: 4e8 cells in a row, more than the cells a map may have.
      {Pose2(2e7, 0, 0), {1.0f}, 10, "more than the 67108864 a map may have"},
      {Pose2(0, 0, 0), {2e7f}, kInfinity, "more than the 67108864 a map may have"},
  };
  for (const Case& c : cases) {
    OccupancyMapper m;
    m.add_rays(Pose2(0.5, 0.5, 0), 0, 0, {1.0f}, 0, 10);
    const OccupancyGrid before = m.grid();
    try {
      m.add_rays(c.pose, 0, 0, c.ranges, 0, c.range_max);
      ADD_FAILURE() << "mapped a pose at " << c.pose.x << ", " << c.pose.y;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "resolution_m");
      EXPECT_NE(std::string(e.what()).find("far outside the mapped area"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
    const OccupancyGrid after = m.grid();
    EXPECT_EQ(after.width(), before.width());
    EXPECT_EQ(after.height(), before.height());
  }
}

TEST(LogMapping, AStrayReadingAboveTheNoReturnValueLeavesTheMapAsItWas) {
  // A robot turning in a round room of radius 3 m whose far half is open (no return, 81.91 m). One
  // reading 0.01 m above 81.91 used to make every no-return beam a wall 81.91 m away.
  const auto log_text = [](bool stray) {
    std::string out;
    for (int i = 0; i < 30; ++i) {
      out += "FLASER 180";
      for (int b = 0; b < 180; ++b) out += b < 90 ? " 3.00" : (stray && i == 7 && b == 100 ? " 81.92" : " 81.91");
      out += " 0 0 " + std::to_string(0.2 * i) + " 0 0 " + std::to_string(0.2 * i) + " " + std::to_string(i) + ".0 h 0\n";
    }
    return out;
  };
  const LogMapResult clean = map_log(read_carmen_log(log_text(false), "clean.clf"), LogPoseSource::Log, {});
  const LogMapResult stray = map_log(read_carmen_log(log_text(true), "stray.clf"), LogPoseSource::Log, {});
  EXPECT_EQ(stray.grid.width(), clean.grid.width());
  EXPECT_EQ(stray.grid.height(), clean.grid.height());
  EXPECT_TRUE(std::equal(stray.grid.data().begin(), stray.grid.data().end(), clean.grid.data().begin()));
  EXPECT_LT(clean.grid.width(), 200);  // the room, not a disc of 81.91 m
}

const char* kLoggedRoom =
    "PARAM robot_frontlaser_offset 0.2 h 0\n"
    "ODOM 1.0 1.0 0.0 0 0 0 1.000000 h 0\n"
    "TRUEPOS 1.5 1.0 0.0 1.0 1.0 0.0 1.000000 h 0\n"
    "ODOM 1.0 1.0 0.0 0 0 0 2.000000 h 0\n"
    "TRUEPOS 1.5 1.0 0.0 1.0 1.0 0.0 2.000000 h 0\n"
    "RAWLASER1 0 0.0 0.0 0.0 20.0 0.01 0 1 2.0 0 1.500000 h 0\n";

TEST(LogMapping, PosesFromTheLogTheTruthOrATrajectoryFile) {
  const RobotLog log = read_carmen_log(kLoggedRoom, "room.clf");
  OccupancyMappingParams p;
  // Odometry (1, 1) + the 0.2 m mount: the reading ends at x = 3.2.
  const LogMapResult odo = map_log(log, LogPoseSource::Log, p);
  ASSERT_EQ(odo.scans_mapped, 1u);
  EXPECT_NEAR(odo.base_poses[0].pose.x, 1.0, 1e-12);
  auto occupied_at = [](const OccupancyGrid& g, double x) {
    const Vec2 c = g.geometry().world_to_cell_continuous({x, 1.0});
    return g.at(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))) >= 65;
  };
  EXPECT_TRUE(occupied_at(odo.grid, 3.22));
  const LogMapResult truth = map_log(log, LogPoseSource::Truth, p);
  EXPECT_TRUE(occupied_at(truth.grid, 3.72));
  const test::ScratchDir dir;
  test::write_text(dir.file("t.csv"), "t_s,x_m,y_m,yaw_rad\n1.500000,0.5,1.0,0.0\n9.000000,0,0,0\n");
  const LogMapResult file = map_log(log, read_trajectory_csv(dir.file("t.csv")), p);
  EXPECT_TRUE(occupied_at(file.grid, 2.72));
  EXPECT_EQ(trajectory_csv(file.base_poses), "t_s,x_m,y_m,yaw_rad\n1.500000,0.5,1,0\n");
  test::write_text(dir.file("t2.csv"), "t_s,x_m,y_m,yaw_rad\n1.500000,0.5,1.0\n");
  EXPECT_THROW(read_trajectory_csv(dir.file("t2.csv")), Error);
  test::write_text(dir.file("t3.csv"), "t_s,x_m,y_m,yaw_rad\n1.5,nan,1.0,0\n");
  try {
    read_trajectory_csv(dir.file("t3.csv"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "x_m");
  }
  EXPECT_THROW(map_log(read_carmen_log("ODOM 0 0 0 0 0 0 1.0 h 0\n", "x.clf"), LogPoseSource::Truth, p), Error);
}

TEST(LogMapping, TheIntelCorrectedLogsReadingsLandOnItsOccupiedCells) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/carmen_radish_corrected/intel-corrected.log.gz");
  const RobotLog log = read_robot_log(test::shared_path("datasets/carmen_radish_corrected/intel-corrected.log.gz"));
  ASSERT_EQ(log.scans.size(), 910u);
  const LogMapResult r = map_log(log, LogPoseSource::Log, OccupancyMappingParams{});
  ASSERT_EQ(r.scans_mapped, 910u);
  // Independent of the map's pixels: every 7th scan's own readings, projected from its pose, land
  // on an occupied cell or next to one (a wall seen from many sides is a band of cells).
  std::size_t hits = 0, on_occupied = 0, near_occupied = 0;
  const GridGeometry& g = r.grid.geometry();
  auto occupied = [&](int x, int y) { return g.contains(x, y) && r.grid(x, y) >= 65; };
  for (std::size_t i = 0; i < log.scans.size(); i += 7) {
    const LogScan& s = log.scans[i];
    for (std::size_t b = 0; b < s.ranges_m.size(); ++b) {
      if (!s.returned(b) || s.ranges_m[b] > 20.0f) continue;
      const Vec2 p = s.laser_pose->transform(double(s.ranges_m[b]) * Vec2(std::cos(s.angle(b)), std::sin(s.angle(b))));
      const Vec2 c = g.world_to_cell_continuous(p);
      const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
      ++hits;
      on_occupied += occupied(x, y);
      bool near = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) near = near || occupied(x + dx, y + dy);
      near_occupied += near;
    }
  }
  EXPECT_GT(hits, 15000u);
  EXPECT_GT(static_cast<double>(on_occupied) / static_cast<double>(hits), 0.7) << on_occupied << " of " << hits;
  EXPECT_GT(static_cast<double>(near_occupied) / static_cast<double>(hits), 0.95) << near_occupied << " of " << hits;
}

}  // namespace
}  // namespace starnav
