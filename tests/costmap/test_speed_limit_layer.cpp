// The speed_limit costmap layer, found by name in the registry: its answer at points against a
// brute-force crossing-number test and on rectangles (footprints) against an independent clip
// (Sutherland-Hodgman: the zone clipped by the rectangle has area), on random polygons and limits;
// overlapping zones give the lowest; its parameter errors name the setting. Then a whole run of
// scenarios/speed_zone_corridor.yaml (with its path follower, the DWA and the regulated pure
// pursuit): at every recorded step whose pose lies inside the zone the robot's speed is within the
// limit, before and after it the robot drives faster, and it arrives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/costmap/layered_costmap.hpp"
#include "starnav/costmap/speed_limit_layer.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"
#include "support/polygon_clip.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// Even-odd crossing number: a horizontal ray from p to +x crosses the boundary an odd number of times.
bool crossing_number_inside(const Vec2& p, const std::vector<Vec2>& poly) {
  int crossings = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    if ((a.y() <= p.y() && b.y() > p.y()) || (b.y() <= p.y() && a.y() > p.y())) {
      const double t = (p.y() - a.y()) / (b.y() - a.y());
      if (p.x() < a.x() + t * (b.x() - a.x())) ++crossings;
    }
  }
  return crossings % 2 == 1;
}

// Distance from p to the polygon's boundary (points this close are left out: on the boundary the
// closed region and the crossing number may differ by rounding).
double boundary_distance(const Vec2& p, const std::vector<Vec2>& poly) {
  double best = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], d = poly[(i + 1) % poly.size()] - a;
    const double s = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (a + s * d)).norm());
  }
  return best;
}

// The body's rectangle (counter-clockwise) at a pose.
std::vector<Vec2> rectangle_at(const Pose2& pose, double length, double width) {
  return {pose.transform(Vec2(0.5 * length, 0.5 * width)), pose.transform(Vec2(-0.5 * length, 0.5 * width)),
          pose.transform(Vec2(-0.5 * length, -0.5 * width)), pose.transform(Vec2(0.5 * length, -0.5 * width))};
}

std::string polygons_text(const std::vector<std::vector<Vec2>>& zones) {
  std::vector<ParamPolygon> p;
  for (const auto& z : zones) {
    ParamPolygon& q = p.emplace_back();
    for (const Vec2& v : z) q.push_back({v.x(), v.y()});
  }
  return format_param_polygons(p);
}

std::unique_ptr<CostmapLayer> layer_from_registry(const std::vector<ParamSetting>& settings) {
  CostmapLayerContext ctx;
  ctx.geometry.width = 10;
  ctx.geometry.height = 10;
  ctx.geometry.resolution = 0.1;
  ctx.file = "z.yaml";
  return find_costmap_layer("speed_limit", "navigation.layers").make(ctx, settings);
}

TEST(SpeedLimitLayer, PointsAndFootprintsGetTheLowestLimitOfTheZonesTheyMeet) {
  Rng rng(23);
  int inside_points = 0, meeting_boxes = 0, missing_boxes = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<std::vector<Vec2>> zones;
    std::vector<double> limits;
    const int n = 1 + static_cast<int>(rng.uniform(0.0, 4.0));
    for (int i = 0; i < n; ++i) {
      zones.push_back(test::random_star_polygon(rng, {rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)}, rng.uniform(0.3, 2.0)));
      limits.push_back(std::round(rng.uniform(0.05, 1.0) * 1000.0) / 1000.0);
    }
    std::string limits_text = "[";
    for (std::size_t i = 0; i < limits.size(); ++i) limits_text += (i ? ", " : "") + format_param_real(limits[i]);
    limits_text += "]";
    const auto layer = layer_from_registry({{"zones", polygons_text(zones), "z.yaml", 2, "navigation.speed_limit.zones"},
                                            {"limits_mps", limits_text, "z.yaml", 3, "navigation.speed_limit.limits_mps"}});
    // Points: the lowest limit of the zones whose crossing number is odd.
    for (int k = 0; k < 600; ++k) {
      const Vec2 p(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
      std::optional<double> want;
      bool near_boundary = false;
      for (std::size_t i = 0; i < zones.size(); ++i) {
        near_boundary = near_boundary || boundary_distance(p, zones[i]) < 1e-9;
        if (crossing_number_inside(p, zones[i]) && (!want || limits[i] < *want)) want = limits[i];
      }
      if (near_boundary) continue;
      inside_points += want.has_value();
      EXPECT_EQ(layer->speed_limit_mps(std::span<const Vec2>(&p, 1)), want) << p.transpose();
    }
    // Rectangles: the lowest limit of the zones the clip finds inside them.
    for (int k = 0; k < 200; ++k) {
      const Pose2 pose(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-M_PI, M_PI));
      const std::vector<Vec2> box = rectangle_at(pose, rng.uniform(0.05, 1.0), rng.uniform(0.05, 0.8));
      std::optional<double> want;
      bool grazing = false;
      for (std::size_t i = 0; i < zones.size(); ++i) {
        const double a = test::overlap_area(zones[i], box);
        grazing = grazing || (a > 0.0 && a < 1e-9);
        if (a >= 1e-9 && (!want || limits[i] < *want)) want = limits[i];
      }
      if (grazing) continue;
      (want ? meeting_boxes : missing_boxes) += 1;
      EXPECT_EQ(layer->speed_limit_mps(box), want) << pose.x << " " << pose.y << " " << pose.yaw;
    }
  }
  // Both answers occur often (the test cannot pass by answering always or never).
  std::printf("points inside a zone %d, rectangles meeting one %d, missing all %d\n", inside_points, meeting_boxes, missing_boxes);
  EXPECT_GT(inside_points, 1000);  // of 24000
  EXPECT_GT(meeting_boxes, 1000);  // of 8000
  EXPECT_GT(missing_boxes, 1000);
}

TEST(SpeedLimitLayer, TouchingCountsAndTheLowestOfOverlappingZonesHolds) {
  const std::vector<Vec2> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}}, inner = {{1, 1}, {3, 1}, {3, 3}, {1, 3}};
  EXPECT_TRUE(polygons_meet(square, rectangle_at(Pose2(2.5, 1.0, 0.0), 1.0, 0.5)));    // an edge on the zone's edge
  EXPECT_TRUE(polygons_meet(square, rectangle_at(Pose2(2.5, 2.25, 0.0), 1.0, 0.5)));   // a corner on its corner
  EXPECT_FALSE(polygons_meet(square, rectangle_at(Pose2(2.51, 1.0, 0.0), 1.0, 0.5)));
  EXPECT_TRUE(polygons_meet(square, rectangle_at(Pose2(1.0, 1.0, 0.3), 0.2, 0.2)));    // wholly inside
  EXPECT_TRUE(polygons_meet(square, rectangle_at(Pose2(1.0, 1.0, 0.3), 5.0, 5.0)));    // wholly around
  EXPECT_TRUE(polygons_meet(square, rectangle_at(Pose2(1.0, 1.0, 0.0), 0.1, 9.0)));    // across, no vertex inside either
  const auto layer = layer_from_registry({{"zones", polygons_text({square, inner}), "", 0, "zones"},
                                          {"limits_mps", "[0.5, 0.25]", "", 0, "limits_mps"}});
  const auto at = [&](double x, double y) {
    const Vec2 p(x, y);
    return layer->speed_limit_mps(std::span<const Vec2>(&p, 1));
  };
  EXPECT_EQ(at(0.5, 0.5), 0.5);
  EXPECT_EQ(at(1.5, 1.5), 0.25);  // in both: the lower
  EXPECT_EQ(at(2.5, 2.5), 0.25);
  EXPECT_EQ(at(2.0, 0.5), 0.5);   // on the boundary
  EXPECT_EQ(at(3.5, 0.5), std::nullopt);
  EXPECT_EQ(layer->speed_limit_mps(rectangle_at(Pose2(0.5, 0.5, 0.0), 1.05, 0.2)), 0.5);
  EXPECT_EQ(layer->speed_limit_mps(rectangle_at(Pose2(0.5, 0.5, 0.0), 1.0, 0.2)), 0.5);  // below the inner zone's corner (1, 1)
  EXPECT_EQ(layer->speed_limit_mps(rectangle_at(Pose2(0.5, 0.5, 0.0), 1.2, 1.2)), 0.25);
  // It adds no obstacle and observes nothing.
  GridGeometry g;
  g.width = 40;
  g.height = 40;
  g.resolution = 0.1;
  std::vector<std::unique_ptr<CostmapLayer>> layers;
  layers.push_back(layer_from_registry({{"zones", polygons_text({square}), "", 0, "zones"}, {"limits_mps", "[0.5]", "", 0, "limits_mps"}}));
  const LayeredCostmap map(g, NodeMapParams{}, std::move(layers));
  EXPECT_EQ(std::count(map.raw_blocked().begin(), map.raw_blocked().end(), 1), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) ASSERT_FALSE(map.observed(x, y));
  const Vec2 p(1.0, 1.0);
  EXPECT_EQ(map.speed_limit_mps(std::span<const Vec2>(&p, 1)), 0.5);
}

TEST(SpeedLimitLayer, ParameterErrorsNameTheSetting) {
  const std::string zone = "[[[0, 0], [1, 0], [1, 1]]]", two = "[[[0, 0], [1, 0], [1, 1]], [[2, 2], [3, 2], [3, 3]]]";
  struct Case {
    std::vector<ParamSetting> settings;
    std::string field, says;
    int line;
  };
  const std::vector<Case> cases = {
      {{{"zones", zone, "z.yaml", 4, "navigation.speed_limit.zones"}, {"limits_mps", "[0]", "z.yaml", 5, "navigation.speed_limit.limits_mps"}},
       "navigation.speed_limit.limits_mps", "must be > 0", 5},
      {{{"zones", zone, "z.yaml", 4, "navigation.speed_limit.zones"}, {"limits_mps", "[-0.2]", "z.yaml", 5, "navigation.speed_limit.limits_mps"}},
       "navigation.speed_limit.limits_mps", "must be > 0", 5},
      {{{"zones", two, "z.yaml", 4, "navigation.speed_limit.zones"}, {"limits_mps", "[0.3]", "z.yaml", 5, "navigation.speed_limit.limits_mps"}},
       "navigation.speed_limit.limits_mps", "gives 1 limit for 2 zones", 5},
      {{{"zones", zone, "z.yaml", 4, "navigation.speed_limit.zones"}, {"limits_mps", "[0.3, 0.4]", "z.yaml", 5, "navigation.speed_limit.limits_mps"}},
       "navigation.speed_limit.limits_mps", "gives 2 limits for 1 zone ", 5},
      // Zones without limits: the key is named though the scenario does not give it.
      {{{"zones", zone, "z.yaml", 4, "navigation.speed_limit.zones"}}, "navigation.speed_limit.limits_mps", "gives 0 limits for 1 zone ", 0},
      {{{"zones", "[[[0, 0], [1, 0]]]", "z.yaml", 4, "navigation.speed_limit.zones"}}, "navigation.speed_limit.zones", "at least 3 points", 4},
      {{{"limits_mps", "[0.3, x]", "z.yaml", 6, "navigation.speed_limit.limits_mps"}}, "navigation.speed_limit.limits_mps", "finite number", 6},
      {{{"limit_mps", "[0.3]", "z.yaml", 7, "navigation.speed_limit.limit_mps"}}, "navigation.speed_limit.limit_mps", "unknown key", 7},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.says);
    try {
      layer_from_registry(c.settings);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "z.yaml");
      EXPECT_EQ(e.line(), c.line);
      EXPECT_EQ(e.field(), c.field);
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

TEST(SpeedLimitLayer, TheCorridorRunKeepsToTheLimitInsideTheZoneAndArrives) {
  // The zone and its limit as the scenario states them (docs/navigation.md shows the same).
  const std::vector<Vec2> zone = {{2.0, 0.0}, {2.8, 0.0}, {2.8, 2.0}, {2.0, 2.0}};
  const double limit = 0.2;
  // The scenario's path follower, and the same corridor with the DWA and the regulated pure
  // pursuit at the same cruise speed.
  const std::string file = test::scenario_path("speed_zone_corridor.yaml");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string follower = "controller: path_follower\n  follower: {cruise_speed_mps: 0.5}";
  ASSERT_NE(text.str().find(follower), std::string::npos);
  for (const std::string& controller :
       {follower, std::string("controller: dwa\n  dwa: {max_vx_mps: 0.5}"),
        std::string("controller: regulated_pure_pursuit\n  rpp: {desired_linear_vel_mps: 0.5}")}) {
    SCOPED_TRACE(controller);
    std::string yaml = text.str();
    yaml.replace(yaml.find(follower), follower.size(), controller);
    const ScenarioSpec spec = parse_scenario(yaml, file);
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun run(spec, o);
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
    EXPECT_EQ(m.collisions, 0);
    int inside = 0;
    double fastest_inside = 0.0, fastest_before = 0.0, fastest_after = 0.0;
    for (const TrajectorySample& s : run.simulation().trajectory()) {
      const Vec2 p = s.position.head<2>();
      const double speed = std::hypot(s.twist.vx, s.twist.vy);
      if (crossing_number_inside(p, zone)) {
        ++inside;
        fastest_inside = std::max(fastest_inside, speed);
        // The achieved body speed, not only the command: the limit holds from the moment the
        // body touched the zone, half a body length before its centre entered.
        EXPECT_LE(speed, limit + 1e-6) << "t = " << s.t_s << " at x = " << p.x();
      } else if (p.x() < zone[0].x()) {
        fastest_before = std::max(fastest_before, speed);
      } else {
        fastest_after = std::max(fastest_after, speed);
      }
    }
    EXPECT_GT(inside, 50);                   // the robot crossed the zone, sample after sample
    EXPECT_GT(fastest_inside, 0.9 * limit);  // and drove at the limit there, not stopped
    EXPECT_GT(fastest_before, 2.0 * limit);  // before and after it the robot is faster than the limit
    EXPECT_GT(fastest_after, 2.0 * limit);
    // The navigator's events: the limit came on once and went off once.
    std::vector<std::string> changes;
    for (const NavEvent& e : run.navigator().events())
      if (e.kind == "speed_limit") changes.push_back(e.detail);
    EXPECT_EQ(changes, (std::vector<std::string>{"0.2", "none"}));
  }
}

}  // namespace
}  // namespace starnav
