// Indoor worlds from map_server maps: the wall boxes cover exactly the occupied cells (every
// occupied cell's centre inside a box, no free or unknown cell's, areas adding up), rotated maps
// included; a scenario with world.occupancy_map builds it, its 2D LiDAR sees the walls where the
// map has them, and a bad map is one error naming the scenario's key.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/sim/occupancy_world.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

bool inside(const Box& b, const Vec2& p) {
  const Vec2 d = Eigen::Rotation2Dd(-b.yaw) * (p - b.center.head<2>());
  return std::abs(d.x()) < 0.5 * b.size.x() && std::abs(d.y()) < 0.5 * b.size.y();
}

TEST(OccupancyWorld, BoxesCoverExactlyTheOccupiedCells) {
  for (const double yaw : {0.0, 0.4}) {
    OccupancyGrid g(GridGeometry{37, 23, 0.1, Pose2(-1.0, 2.0, yaw)}, 0);
    Rng rng(3);
    std::size_t occupied = 0;
    for (int y = 0; y < g.height(); ++y)
      for (int x = 0; x < g.width(); ++x) {
        const double u = rng.uniform(0, 1);
        const bool wall = (x == 0 || y == 0 || x == g.width() - 1 || (x == 17 && y > 3) || u < 0.08);
        g(x, y) = wall ? 100 : (u > 0.95 ? -1 : 0);
        occupied += wall;
      }
    const Obstacle o = occupancy_walls(g, 65.0, 1.5, "walls");
    double area = 0.0;
    for (const Primitive& p : o.parts) {
      const Box& b = std::get<Box>(p);
      area += b.size.x() * b.size.y();
      EXPECT_DOUBLE_EQ(b.size.z(), 1.5);
      EXPECT_DOUBLE_EQ(b.center.z(), 0.75);
    }
    EXPECT_NEAR(area, static_cast<double>(occupied) * 0.01, 1e-9);
    EXPECT_LT(o.parts.size(), occupied / 2);  // runs merged
    for (int y = 0; y < g.height(); ++y)
      for (int x = 0; x < g.width(); ++x) {
        const Vec2 c = g.origin().transform(Vec2((x + 0.5) * 0.1, (y + 0.5) * 0.1));
        int hits = 0;
        for (const Primitive& p : o.parts) hits += inside(std::get<Box>(p), c);
        EXPECT_EQ(hits, g(x, y) == 100 ? 1 : 0) << x << " " << y << " yaw " << yaw;
      }
  }
  OccupancyGrid g(GridGeometry{2, 2, 0.1, {}}, 0);
  EXPECT_THROW(occupancy_walls(g, 65, 0.0, "w"), Error);
  EXPECT_TRUE(occupancy_walls(g, 65, 1.0, "w").parts.empty());
}

// A 6 m x 4 m room with 0.1 m walls, written as a map_server map.
std::string write_room(const test::ScratchDir& dir) {
  OccupancyGrid g(GridGeometry{120, 80, 0.05, {}}, 0);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 120; ++x)
      if (x < 2 || y < 2 || x >= 118 || y >= 78) g(x, y) = 100;
  const std::string path = dir.file("room.yaml");
  write_ros_map(g, path);
  return path;
}

TEST(OccupancyWorld, AScenarioMapWorldIsSeenByItsLidar) {
  const test::ScratchDir dir;
  write_room(dir);
  const std::string yaml = R"(name: room
world:
  occupancy_map: room.yaml
robot:
  drive: differential
  start: {x_m: 2.0, y_m: 1.5, yaw_deg: 0.0}
sensors:
  lidar: {preset: generic_360, rate_hz: 10.0, mount: {x_m: 0.0, y_m: 0.0, z_m: 0.4}}
sim: {dt_s: 0.01, duration_s: 0.1}
commands:
  - {duration_s: 0.1, vx_mps: 0.0, vy_mps: 0.0, wz_radps: 0.0}
)";
  const ScenarioSpec spec = parse_scenario(yaml, dir.file("room_scenario.yaml"));
  ASSERT_TRUE(spec.occupancy_map.has_value());
  EXPECT_EQ(spec.occupancy_map->resolved_file, dir.file("room.yaml"));
  EXPECT_DOUBLE_EQ(spec.occupancy_map->wall_height_m, 2.0);
  Simulation sim(spec);
  std::optional<LidarScan> first;
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [&](const LidarScan& s) {
    if (!first) first = s;
  });
  sim.run();
  ASSERT_TRUE(first.has_value());
  // Straight ahead (+x) the east wall's face at x = 5.9: 3.9 m; behind, the west face at 0.1: 1.9 m;
  // to the left the north face at y = 3.9: 2.4 m.
  const auto range_at = [&](double azimuth) {
    const LidarConfig& c = spec.lidar->config;
    for (int i = 0; i < first->beams; ++i)
      if (std::abs(wrap_angle(c.azimuth(i) - azimuth)) < 1e-9) return first->range(0, i);
    return -1.0;
  };
  EXPECT_NEAR(range_at(0.0), 3.9, 1e-6);
  EXPECT_NEAR(range_at(kPi), 1.9, 1e-6);
  EXPECT_NEAR(range_at(kPi / 2), 2.4, 1e-6);
}

TEST(OccupancyWorld, ABadMapNamesTheScenarioKey) {
  const test::ScratchDir dir;
  test::write_text(dir.file("bad.yaml"), "image: nothing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const std::string yaml = "name: x\nworld:\n  occupancy_map: {file: bad.yaml, wall_height_m: 1.0}\nrobot: {drive: differential}\nsim: {duration_s: 0.1}\n";
  const ScenarioSpec spec = parse_scenario(yaml, dir.file("s.yaml"));
  try {
    build_world(spec);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "world.occupancy_map.file") << e.what();
    EXPECT_NE(std::string(e.what()).find("nothing.pgm"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_scenario("name: x\nworld:\n  occupancy_map: {file: a.yaml, wall_height_m: -1}\nrobot: {drive: differential}\nsim: {duration_s: 0.1}\n",
                              dir.file("s.yaml")),
               Error);
  EXPECT_THROW(parse_scenario("name: x\nworld:\n  occupancy_map: {file: a.yaml, height: 1}\nrobot: {drive: differential}\nsim: {duration_s: 0.1}\n",
                              dir.file("s.yaml")),
               Error);
}

}  // namespace
}  // namespace starnav
