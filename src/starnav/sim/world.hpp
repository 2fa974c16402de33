#pragma once
// The simulated world: an optional elevation terrain plus obstacles (rigid groups of primitives
// with lifetimes and motions). Built once from plain structs and immutable afterwards, so casts
// may run from several threads. Implements the sensors' RayCaster.
//
// Ray casting tests the obstacles through two bounding-volume hierarchies, one over the parts of
// the obstacles that never move (built once; each part's lifetime is checked per ray) and one
// over the moving obstacles posed at the time asked for (rebuilt whenever a cast asks for a new
// time), then the terrain up to the nearest obstacle hit.
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "starnav/map/elevation_map.hpp"
#include "starnav/sense/ray_caster.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/sim/primitive_set.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav {

struct WorldDescription {
  std::optional<ElevationMap> terrain;
  std::vector<Obstacle> obstacles;
};

class World final : public RayCaster {
 public:
  World();
  // Throws Error for an invalid obstacle (field named, message prefixed with the obstacle's index
  // and name) or a terrain without any observed cell.
  explicit World(const WorldDescription& description);
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  ~World() override;

  const TerrainSurface* terrain() const { return terrain_ ? terrain_.get() : nullptr; }
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }

  RayHit cast(const Vec3& origin, const Vec3& direction, double max_range, double time) const override;
  void cast_many(const Vec3& origin, std::span<const Vec3> directions, double max_range, double time,
                 std::span<RayHit> hits) const override;
  // The same answer by testing every primitive in `primitives_at(time)`, given as `primitives`
  // (reference for tests; a caller casting many rays at one time poses the obstacles once).
  RayHit cast_brute_force(std::span<const PosedPrimitive> primitives, const Vec3& origin, const Vec3& direction,
                          double max_range) const;

  // Terrain height at (x, y) (NaN outside the terrain or without one).
  double terrain_height(double x, double y) const;
  // Height of the highest surface (terrain or obstacle) above (x, y) at `time`; NaN when there is
  // nothing there.
  double surface_height(double x, double y, double time) const;

  // Every primitive that exists at `time`, posed where it is then.
  std::vector<PosedPrimitive> primitives_at(double time) const;
  // Bounds of the terrain and of the obstacles at `time`.
  Aabb bounds(double time) const;

 private:
  std::shared_ptr<const PrimitiveSet> moving_set(double time) const;
  RayHit cast_with(const PrimitiveSet* moving, const Vec3& origin, const Vec3& direction, double max_range,
                   double time) const;

  std::unique_ptr<TerrainSurface> terrain_;
  std::vector<Obstacle> obstacles_;
  std::vector<int> moving_;  // indices of moving obstacles
  PrimitiveSet static_set_;
  Aabb static_bounds_;  // terrain and non-moving obstacles (whatever their lifetimes)
  // The moving obstacles posed at the last time asked for (shared by concurrent casts).
  struct MovingCache {
    std::mutex mutex;
    double time = 0.0;
    std::shared_ptr<const PrimitiveSet> set;
  };
  std::unique_ptr<MovingCache> cache_ = std::make_unique<MovingCache>();
};

}  // namespace starnav
