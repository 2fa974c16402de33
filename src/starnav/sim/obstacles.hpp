#pragma once
// Obstacles of the simulated world: rigid groups of primitives with a lifetime and a motion, and
// the composite obstacles of the paper's test platform (docs/papers/li2019.md) built from them.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "starnav/sim/primitives.hpp"

namespace starnav {

class TerrainSurface;

struct Waypoint {
  double time = 0.0;  // s
  Vec3 position = Vec3::Zero();
};

// A rigid group of primitives. The parts are given in world coordinates for the moment the
// anchor is at `anchor`; at time t every part is translated by anchor(t) - anchor, where
//   no motion:          anchor(t) = anchor
//   constant velocity:  anchor(t) = anchor + velocity * (t - appear)
//   waypoints:          anchor(t) piecewise linear through (time_i, position_i), held at the first
//                       position before the first time and at the last after the last
// (velocity and waypoints are exclusive; orientation never changes). The obstacle exists for
// appear <= t < disappear; outside that interval sensors do not see it.
struct Obstacle {
  std::string name;
  std::vector<Primitive> parts;
  Vec3 anchor = Vec3::Zero();
  double appear = 0.0;
  double disappear = std::numeric_limits<double>::infinity();
  Vec3 velocity = Vec3::Zero();
  std::vector<Waypoint> waypoints;

  bool moving() const { return !waypoints.empty() || velocity != Vec3::Zero(); }
  bool exists_at(double t) const { return appear <= t && t < disappear; }
  Vec3 anchor_at(double t) const;
  Vec3 offset_at(double t) const { return anchor_at(t) - anchor; }
};

// Throws Error naming the field: no parts, a bad part, non-finite or unordered times, velocity
// together with waypoints, waypoint times not strictly increasing.
void validate(const Obstacle& o);

// --- Composite obstacles. Each is laid out in its own frame: x along `yaw` (the direction of
// travel across it), y to the left, z up from `position`, the centre of its footprint on the
// ground. Defaults keep steps <= 0.05 m and slopes <= 15 deg (drivable by the Mecanum robot).

// Five boxes along x: an up-ramp (a pitched box) to ramp_height, a platform, a step up by
// step_height, a step back down to the platform height, and a down-ramp.
struct SlopeStep {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  double width = 1.5;            // across the direction of travel
  double ramp_length = 0.5;      // horizontal length of each ramp
  double ramp_height = 0.08;     // atan(0.08 / 0.5) = 9.1 deg
  double platform_length = 0.6;  // each of the two platforms at ramp_height
  double step_height = 0.04;     // the middle box rises this much above the platforms
  double step_length = 0.6;
  double depth = 0.02;           // the boxes reach this far below `position` (uneven ground)
};
Obstacle make_slope_step(const SlopeStep& s);

// A row of `count` triangular prisms (isosceles ridges) along x.
struct UndulatingGround {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  int count = 5;
  double base_width = 0.5;  // along x, per ridge
  double height = 0.05;     // slope atan(0.05 / 0.25) = 11.3 deg
  double width = 1.5;       // across (prism length)
};
Obstacle make_undulating_ground(const UndulatingGround& u);

// A vertical cylinder standing on a box: a round two-tier bump.
struct RoundConvex {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  Vec3 box_size = Vec3(1.2, 1.2, 0.04);
  double radius = 0.4;
  double cylinder_height = 0.04;
  double depth = 0.02;  // the box reaches this far below `position`
};
Obstacle make_round_convex(const RoundConvex& r);

// `count` small cubes and spheres scattered uniformly over a length x width rectangle, from the
// seed: per piece, in this order, x, y (uniform), size (uniform in [size_min, size_max]), sphere
// or cube (probability sphere_fraction), cube yaw (uniform in [0, pi/2)). Each piece sinks by
// embed * size into the ground: the terrain height under it when `ground` is given and
// follow_terrain is set (and the terrain covers the point), position.z otherwise.
struct Gravel {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  double length = 2.0;
  double width = 1.5;
  int count = 150;
  double size_min = 0.01;
  double size_max = 0.04;
  double sphere_fraction = 0.5;
  double embed = 0.3;
  std::uint64_t seed = 0;
  bool follow_terrain = true;
};
Obstacle make_gravel(const Gravel& g, const TerrainSurface* ground = nullptr);

}  // namespace starnav
