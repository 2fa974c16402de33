#pragma once
// The ray-casting interface the sensors use. The sense module knows nothing of the simulator:
// sim's World implements RayCaster, and tests can implement it with a closed-form scene.
#include <cstdint>
#include <limits>
#include <span>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class HitKind : std::uint8_t { none, terrain, obstacle };

// The first surface a ray meets. `distance` is along the unit direction, +inf when nothing is
// hit within the range; `normal` is the unit outward normal of the solid hit (for the terrain:
// the upward normal of the surface), whichever side the ray came from.
struct RayHit {
  double distance = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();
  HitKind kind = HitKind::none;
  int obstacle = -1;    // index of the obstacle in its world (kind == obstacle)
  int part = -1;        // index of the primitive within the obstacle
  bool inside = false;  // the ray started inside the solid (below the terrain) and hit it from within

  bool hit() const { return kind != HitKind::none; }
};

class RayCaster {
 public:
  virtual ~RayCaster() = default;

  // The first hit along origin + s * direction for s in [0, max_range], at simulation time
  // `time` (moving obstacles are where they are at that time). `direction` must be a unit vector.
  virtual RayHit cast(const Vec3& origin, const Vec3& direction, double max_range, double time) const = 0;

  // Many rays from one origin at one time (a LiDAR scan). hits.size() must equal
  // directions.size(). The default calls cast() once per ray; implementations may share work.
  virtual void cast_many(const Vec3& origin, std::span<const Vec3> directions, double max_range, double time,
                         std::span<RayHit> hits) const {
    for (std::size_t i = 0; i < directions.size(); ++i) hits[i] = cast(origin, directions[i], max_range, time);
  }
};

}  // namespace starnav
