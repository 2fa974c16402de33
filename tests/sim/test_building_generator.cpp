// The large building floors of the SLAM benchmark of scale: the same seed gives the same bytes;
// every kind is at least 150 m x 80 m; its loops, counted on the map itself as the walled islands
// the free space runs round (occupied 8-connected components not touching the border), are the
// blocks the generator says, each large; the corridors and open rooms form one free space that
// shut rooms are not part of; and the route goes round every block and stays on free cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/sim/building_generator.hpp"
#include "starnav/sim/scenario.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

constexpr BuildingKind kKinds[] = {BuildingKind::Grid, BuildingKind::Ladder, BuildingKind::Courtyard};

struct Island {
  int x0, y0, x1, y1;
  bool touches_border;
};

// Connected components of cells equal to `occupied` (8-neighbours for walls, 4 for free space).
std::vector<int> components(const OccupancyGrid& g, bool occupied, std::vector<Island>* islands) {
  const int w = g.width(), h = g.height();
  std::vector<int> label(static_cast<std::size_t>(w) * h, -1);
  std::vector<int> stack;
  int next = 0;
  for (int start = 0; start < w * h; ++start) {
    if (label[start] >= 0 || (g[start] == kOccupiedOccupancy) != occupied) continue;
    Island is{w, h, -1, -1, false};
    label[start] = next;
    stack.push_back(start);
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      const int x = c % w, y = c / w;
      is.x0 = std::min(is.x0, x), is.y0 = std::min(is.y0, y), is.x1 = std::max(is.x1, x), is.y1 = std::max(is.y1, y);
      if (x == 0 || y == 0 || x == w - 1 || y == h - 1) is.touches_border = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || (!occupied && dx != 0 && dy != 0)) continue;
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const int n = ny * w + nx;
          if (label[n] < 0 && (g[n] == kOccupiedOccupancy) == occupied) label[n] = next, stack.push_back(n);
        }
    }
    if (islands) islands->push_back(is);
    ++next;
  }
  return label;
}

int label_at(const OccupancyGrid& g, const std::vector<int>& label, const Vec2& p) {
  const int ix = static_cast<int>(p.x() / g.resolution()), iy = static_cast<int>(p.y() / g.resolution());
  return label[static_cast<std::size_t>(iy) * g.width() + ix];
}

TEST(BuildingGenerator, SameSeedSameBytesOtherSeedOtherBuilding) {
  for (BuildingKind k : kKinds) {
    BuildingOptions o;
    o.kind = k;
    o.seed = 7;
    const BuildingFloor a = generate_building(o), b = generate_building(o);
    EXPECT_TRUE(a.map == b.map) << building_kind_name(k);
    EXPECT_EQ(a.route, b.route);
    const BuildingRoute ra = building_route(a, 3000.0);
    EXPECT_EQ(building_scenario_yaml(a, ra, {"x", "x_map.yaml", 7, 0.6, 5.0}), building_scenario_yaml(b, ra, {"x", "x_map.yaml", 7, 0.6, 5.0}));
    o.seed = 8;
    EXPECT_FALSE(generate_building(o).map == a.map) << building_kind_name(k);
  }
  EXPECT_THROW(parse_building_kind("castle", "--kind"), Error);
}

// Each wheel's systematic error is drawn within the bound, both signs occur and fill the range
// over many seeds, the same seed draws the same values, and the scenario file carries exactly the
// drawn values to the simulator's encoders (read back through the scenario loader).
TEST(BuildingGenerator, WheelScaleErrorsAreDrawnWithinTheBoundAndReachTheEncoders) {
  double lowest = 1.0, highest = -1.0;
  int differing = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    BuildingScenarioOptions o{"x", "x_map.yaml", seed, 0.6, 5.0, 0.005};
    const std::vector<double> e = building_wheel_scale_errors(o);
    ASSERT_EQ(e.size(), 2u);
    for (double v : e) {
      EXPECT_LE(std::abs(v), 0.005);
      lowest = std::min(lowest, v), highest = std::max(highest, v);
    }
    if (e[0] != e[1]) ++differing;
    EXPECT_EQ(e, building_wheel_scale_errors(o));
    o.wheel_scale_error = 0.0;
    EXPECT_EQ(building_wheel_scale_errors(o), (std::vector<double>{0.0, 0.0}));
  }
  EXPECT_LT(lowest, -0.0045);
  EXPECT_GT(highest, 0.0045);
  EXPECT_EQ(differing, 200);
  EXPECT_THROW(building_wheel_scale_errors({"x", "x_map.yaml", 1, 0.6, 5.0, -0.001}), Error);

  BuildingOptions b;
  b.kind = BuildingKind::Courtyard;
  b.seed = 3;
  const BuildingFloor floor = generate_building(b);
  const BuildingRoute route = building_route(floor, 400.0);
  test::ScratchDir dir;
  write_ros_map(floor.map, dir.file("x_map.yaml"));
  const BuildingScenarioOptions o{"x", "x_map.yaml", 3, 0.6, 5.0, 0.004};
  test::write_text(dir.file("x.yaml"), building_scenario_yaml(floor, route, o));
  const ScenarioSpec spec = load_scenario(dir.file("x.yaml"));
  ASSERT_TRUE(spec.encoders.has_value());
  const std::vector<double> drawn = building_wheel_scale_errors(o);
  ASSERT_EQ(spec.encoders->config.scale_error.size(), 2u);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(spec.encoders->config.scale_error[i], drawn[i], 5e-7);
  EXPECT_NEAR(spec.encoders->config.slip_sigma, 0.05, 1e-12);
}

TEST(BuildingGenerator, SizeLoopsRoomsAndRouteHoldForEveryKind) {
  std::vector<double> lap_lengths;
  for (BuildingKind k : kKinds) {
    SCOPED_TRACE(building_kind_name(k));
    BuildingOptions o;
    o.kind = k;
    o.seed = 3;
    const BuildingFloor f = generate_building(o);
    const OccupancyGrid& g = f.map;
    // Size: the free space itself spans at least 150 m x 80 m.
    std::vector<Island> free_parts;
    const std::vector<int> free_label = components(g, false, &free_parts);
    int fx0 = g.width(), fy0 = g.height(), fx1 = 0, fy1 = 0;
    for (const Island& is : free_parts) fx0 = std::min(fx0, is.x0), fy0 = std::min(fy0, is.y0), fx1 = std::max(fx1, is.x1), fy1 = std::max(fy1, is.y1);
    EXPECT_GE((fx1 - fx0 + 1) * g.resolution(), 150.0);
    EXPECT_GE((fy1 - fy0 + 1) * g.resolution(), 80.0);
    // Loops: walled islands inside the free space, one per block, each at least 100 m round.
    std::vector<Island> walls;
    components(g, true, &walls);
    std::size_t islands = 0;
    for (const Island& is : walls) {
      if (is.touches_border) continue;
      ++islands;
      EXPECT_GE(2.0 * ((is.x1 - is.x0 + 1) + (is.y1 - is.y0 + 1)) * g.resolution(), 100.0);
    }
    EXPECT_EQ(islands, f.blocks.size());
    EXPECT_GE(f.blocks.size(), 4u);
    // One free space of corridors and open rooms; a shut room is cut off.
    const int corridors = label_at(g, free_label, f.start.translation());
    std::size_t open = 0;
    for (const BuildingRoom& r : f.rooms) {
      const Vec2 centre((r.interior.x0 + r.interior.x1) / 2, (r.interior.y0 + r.interior.y1) / 2);
      EXPECT_EQ(label_at(g, free_label, centre) == corridors, r.open);
      EXPECT_NEAR(r.interior.width() * r.interior.height(), f.room_size_m.x() * f.room_size_m.y(), 1e-6);  // identical rooms
      open += r.open;
    }
    EXPECT_GE(f.rooms.size(), 100u);
    EXPECT_GT(open, f.rooms.size() / 2);
    for (const Vec2& p : f.route) EXPECT_EQ(label_at(g, free_label, p), corridors) << p.transpose();
    // The route goes round every block: its junction waypoints hold each block's four corners in
    // ring order and back.
    std::vector<Vec2> junctions;
    for (const Vec2& p : f.route)
      if (std::find(f.corridor_x.begin(), f.corridor_x.end(), p.x()) != f.corridor_x.end() &&
          std::find(f.corridor_y.begin(), f.corridor_y.end(), p.y()) != f.corridor_y.end())
        junctions.push_back(p);
    for (const AxisBox& b : f.blocks) {
      bool ringed = false;
      for (std::size_t s = 0; s + 4 < junctions.size() && !ringed; ++s) {
        bool ok = (junctions[s] - junctions[s + 4]).norm() < 1e-9;
        for (std::size_t c = 0; c < 4 && ok; ++c) {
          const Vec2& p = junctions[s + c];
          const Vec2& q = junctions[s + c + 1];
          const bool corner = std::abs(std::abs(p.x() - (b.x0 + b.x1) / 2) - (b.width() + f.corridor_width_m) / 2) < 1e-9 &&
                              std::abs(std::abs(p.y() - (b.y0 + b.y1) / 2) - (b.height() + f.corridor_width_m) / 2) < 1e-9;
          ok = corner && ((p.x() == q.x()) != (p.y() == q.y()));  // the next corner along one side
        }
        ringed = ok;
      }
      EXPECT_TRUE(ringed) << b.x0 << " " << b.y0;
    }
    lap_lengths.push_back(route_length_m(f.route));
    const BuildingRoute km3 = building_route(f, 3000.0);
    EXPECT_GE(route_length_m(km3.waypoints) * km3.laps, 3000.0);
    const BuildingRoute short_route = building_route(f, 100.0);
    EXPECT_EQ(short_route.laps, 1);
    EXPECT_LT(route_length_m(short_route.waypoints), route_length_m(f.route));
  }
  for (double l : lap_lengths) EXPECT_GE(l, 1000.0);
}

// The shut-door chance: at 1 every room is cut off from the corridors (the corridors' walls run
// unbroken, nothing along them for a laser to fix the position by), at 0 every room joins them;
// the layout (blocks, corridors, rooms) is the seed's whatever the chance, and the route stays on
// the corridors' free space.
TEST(BuildingGenerator, ShutDoorChanceCutsRoomsOffAndKeepsTheLayout) {
  for (BuildingKind k : kKinds) {
    SCOPED_TRACE(building_kind_name(k));
    BuildingOptions o;
    o.kind = k;
    o.seed = 5;
    const BuildingFloor usual = generate_building(o);
    for (double chance : {0.0, 1.0}) {
      o.shut_door_probability = chance;
      const BuildingFloor f = generate_building(o);
      ASSERT_EQ(f.rooms.size(), usual.rooms.size());
      EXPECT_EQ(f.corridor_x, usual.corridor_x);
      EXPECT_EQ(f.corridor_y, usual.corridor_y);
      ASSERT_EQ(f.blocks.size(), usual.blocks.size());
      const std::vector<int> free_label = components(f.map, false, nullptr);
      const int corridors = label_at(f.map, free_label, f.start.translation());
      for (std::size_t i = 0; i < f.rooms.size(); ++i) {
        const BuildingRoom& r = f.rooms[i];
        EXPECT_EQ(r.interior.x0, usual.rooms[i].interior.x0);
        EXPECT_EQ(r.open, chance == 0.0);
        const Vec2 centre((r.interior.x0 + r.interior.x1) / 2, (r.interior.y0 + r.interior.y1) / 2);
        EXPECT_EQ(label_at(f.map, free_label, centre) == corridors, chance == 0.0);
      }
      for (const Vec2& p : f.route) EXPECT_EQ(label_at(f.map, free_label, p), corridors) << p.transpose();
    }
  }
  BuildingOptions bad;
  for (double chance : {-0.1, 1.5, std::nan("")}) {
    bad.shut_door_probability = chance;
    EXPECT_THROW(generate_building(bad), Error);
  }
}

}  // namespace
}  // namespace starnav
