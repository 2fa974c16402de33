#pragma once
// Outlines of obstacle primitives seen from above, for pictures of the world (starnav sim's
// scene.svg, the navigation scene).
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/sim/primitives.hpp"

namespace starnav {

// Convex hull (counter-clockwise, Andrew's monotone chain) of points in the plane.
std::vector<Vec2> convex_hull(std::vector<Vec2> points);

struct PrimitiveOutline {
  std::vector<Vec2> polygon;  // closed outline (first point repeated), or empty for a circle
  Vec2 centre = Vec2::Zero();
  double radius = 0.0;
};

// The XY footprint of a primitive moved by `offset`: the hull of a box's corners or a prism's
// vertices; the circle of a cylinder or sphere.
PrimitiveOutline primitive_outline(const Primitive& part, const Vec3& offset);

}  // namespace starnav
