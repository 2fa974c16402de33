#pragma once
// Solid primitives of the simulated world and exact ray intersection with each of them.
//
// Every primitive is a closed convex solid given in world coordinates (metres, radians, z up):
//   Box       centre, full size (x, y, z in its own frame), attitude R = Rz(yaw) Ry(pitch) Rx(roll)
//   Cylinder  vertical: centre of the bottom disc, radius, height
//   Prism     triangular prism standing on its bottom face: centre of the bottom face, yaw; in its
//             own frame the triangle lies in the x-z plane with base from x = -base/2 to +base/2
//             at z = 0 and apex at (apex_offset, height); it is extruded along y over `length`
//   Sphere    centre, radius
// A ray meets a solid's boundary at most twice; the hit reported is the first crossing at s >= 0
// (for a ray starting inside: the exit, flagged `inside`), with the outward unit normal there.
#include <array>
#include <cstdint>
#include <limits>
#include <variant>

#include "starnav/core/geometry.hpp"

namespace starnav {

struct Box {
  Vec3 center = Vec3::Zero();
  Vec3 size = Vec3::Ones();
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;
};

struct Cylinder {
  Vec3 base = Vec3::Zero();  // centre of the bottom disc
  double radius = 0.5;
  double height = 1.0;
};

struct Prism {
  Vec3 base = Vec3::Zero();  // centre of the bottom face
  double yaw = 0.0;
  double base_width = 1.0;   // triangle base along the prism's x axis
  double height = 0.5;       // apex height above the bottom face
  double apex_offset = 0.0;  // apex x in the prism frame, within [-base_width/2, base_width/2]
  double length = 1.0;       // extrusion along the prism's y axis
};

struct Sphere {
  Vec3 center = Vec3::Zero();
  double radius = 0.5;
};

using Primitive = std::variant<Box, Cylinder, Prism, Sphere>;

// Throws Error (field named) for a non-positive size or radius, a non-finite value, or an apex
// outside the prism's base.
void validate(const Primitive& p);
// Moved by a translation.
Primitive translated(const Primitive& p, const Vec3& offset);
// The primitive kind as written in scenarios: "box", "cylinder", "prism", "sphere".
const char* primitive_kind_name(const Primitive& p);

struct Aabb {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  bool empty() const { return !(lo.x() <= hi.x() && lo.y() <= hi.y() && lo.z() <= hi.z()); }
  Vec3 center() const { return 0.5 * (lo + hi); }
};

// Axis-aligned bounds of a primitive (tight for all four kinds).
Aabb bounds(const Primitive& p);

// A primitive compiled for ray casting: a local frame (origin, rotation) plus the kind's numbers.
struct PosedPrimitive {
  enum class Kind : std::uint8_t { box, cylinder, prism, sphere };
  Kind kind = Kind::box;
  Vec3 origin = Vec3::Zero();               // box: centre; cylinder, prism: bottom centre; sphere: centre
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // local -> world (box, prism)
  Vec3 half = Vec3::Zero();                 // box: half size; cylinder: (radius, radius, height)
  double radius = 0.0;                      // cylinder, sphere
  // prism: outward planes n . p <= d in the local frame (bottom, two ends, two sides)
  std::array<Vec3, 5> plane_n{};
  std::array<double, 5> plane_d{};
  Aabb box;
  double appear = -std::numeric_limits<double>::infinity();
  double disappear = std::numeric_limits<double>::infinity();
  int obstacle = -1;
  int part = -1;

  bool exists_at(double t) const { return appear <= t && t < disappear; }
};

PosedPrimitive pose_primitive(const Primitive& p);

// Result of one primitive test: distance (+inf on a miss), outward unit normal, inside flag.
struct PrimitiveHit {
  double distance = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();
  bool inside = false;
};

// The first crossing of the primitive's boundary at s in [0, max_range], exactly (to rounding).
bool intersect(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range, PrimitiveHit& hit);

// True when the world point lies inside or on the primitive (for tests and collision checks).
bool contains(const PosedPrimitive& p, const Vec3& point, double tolerance = 0.0);

}  // namespace starnav
