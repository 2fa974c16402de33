#include "starnav/sim/world.hpp"

#include <cmath>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

void pose_obstacle(const Obstacle& o, int index, const Vec3& offset, std::vector<PosedPrimitive>& out) {
  for (std::size_t j = 0; j < o.parts.size(); ++j) {
    PosedPrimitive p = pose_primitive(offset == Vec3::Zero() ? o.parts[j] : translated(o.parts[j], offset));
    p.appear = o.appear;
    p.disappear = o.disappear;
    p.obstacle = index;
    p.part = static_cast<int>(j);
    out.push_back(std::move(p));
  }
}

// Whether an obstacle hit at `distance` on (obstacle, part) replaces `out`: nearer, as near as
// the terrain, or as near as another obstacle with a higher (obstacle, part), so that ties never
// depend on the order of the tests.
bool replaces(const RayHit& out, double distance, int obstacle, int part) {
  if (!out.hit() || distance < out.distance) return true;
  if (distance > out.distance) return false;
  if (out.kind == HitKind::terrain) return true;
  return obstacle != out.obstacle ? obstacle < out.obstacle : part < out.part;
}

}  // namespace

World::World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

World::World(const WorldDescription& d) {
  if (d.terrain) terrain_ = std::make_unique<TerrainSurface>(*d.terrain);
  obstacles_ = d.obstacles;
  std::vector<PosedPrimitive> fixed;
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    const Obstacle& o = obstacles_[i];
    try {
      validate(o);
    } catch (const Error& e) {
      throw Error("obstacle " + std::to_string(i) + (o.name.empty() ? "" : " (" + o.name + ")") + ": " + e.message(),
                  e.file(), e.line(), e.field());
    }
    if (o.moving())
      moving_.push_back(static_cast<int>(i));
    else
      pose_obstacle(o, static_cast<int>(i), Vec3::Zero(), fixed);
  }
  for (const PosedPrimitive& p : fixed) static_bounds_.extend(p.box);
  if (terrain_) {
    const GridGeometry& g = terrain_->geometry();
    for (double u : {0.0, g.width_m()})
      for (double v : {0.0, g.height_m()}) {
        const Vec2 w = g.grid_to_world({u, v});
        static_bounds_.extend(Vec3(w.x(), w.y(), terrain_->min_height()));
        static_bounds_.extend(Vec3(w.x(), w.y(), terrain_->max_height()));
      }
  }
  static_set_ = PrimitiveSet(std::move(fixed));
}

std::shared_ptr<const PrimitiveSet> World::moving_set(double time) const {
  if (moving_.empty()) return nullptr;
  std::lock_guard<std::mutex> lock(cache_->mutex);
  if (cache_->set && cache_->time == time) return cache_->set;
  std::vector<PosedPrimitive> posed;
  for (int i : moving_) {
    const Obstacle& o = obstacles_[static_cast<std::size_t>(i)];
    if (o.exists_at(time)) pose_obstacle(o, i, o.offset_at(time), posed);
  }
  cache_->set = std::make_shared<const PrimitiveSet>(std::move(posed));
  cache_->time = time;
  return cache_->set;
}

RayHit World::cast_with(const PrimitiveSet* moving, const Vec3& origin, const Vec3& dir, double max_range,
                        double time) const {
  // The terrain first: its hit (when there is one) shortens the segment the obstacles' hierarchies
  // must cover. An obstacle at the same distance as the terrain wins.
  RayHit out;
  TerrainHit th;
  double limit = max_range;
  if (terrain_ && terrain_->cast(origin, dir, max_range, th)) {
    out = {th.distance, th.normal, HitKind::terrain, -1, -1, th.from_below};
    limit = th.distance;
  }
  SetHit sh;
  if (static_set_.cast(origin, dir, limit, time, sh)) {
    const PosedPrimitive& p = static_set_.primitives()[static_cast<std::size_t>(sh.index)];
    out = {sh.distance, sh.normal, HitKind::obstacle, p.obstacle, p.part, sh.inside};
    limit = sh.distance;
  }
  if (moving && moving->cast(origin, dir, limit, time, sh)) {
    const PosedPrimitive& p = moving->primitives()[static_cast<std::size_t>(sh.index)];
    if (replaces(out, sh.distance, p.obstacle, p.part))
      out = {sh.distance, sh.normal, HitKind::obstacle, p.obstacle, p.part, sh.inside};
  }
  return out;
}

RayHit World::cast(const Vec3& origin, const Vec3& direction, double max_range, double time) const {
  const auto moving = moving_set(time);
  return cast_with(moving.get(), origin, direction, max_range, time);
}

void World::cast_many(const Vec3& origin, std::span<const Vec3> directions, double max_range, double time,
                      std::span<RayHit> hits) const {
  const auto moving = moving_set(time);
  for (std::size_t i = 0; i < directions.size(); ++i)
    hits[i] = cast_with(moving.get(), origin, directions[i], max_range, time);
}

RayHit World::cast_brute_force(std::span<const PosedPrimitive> primitives, const Vec3& origin, const Vec3& dir,
                               double max_range) const {
  RayHit out;
  PrimitiveHit ph;
  for (const PosedPrimitive& p : primitives)
    if (intersect(p, origin, dir, max_range, ph) && replaces(out, ph.distance, p.obstacle, p.part))
      out = {ph.distance, ph.normal, HitKind::obstacle, p.obstacle, p.part, ph.inside};
  TerrainHit th;
  if (terrain_ && terrain_->cast(origin, dir, out.hit() ? out.distance : max_range, th) &&
      (!out.hit() || th.distance < out.distance))
    out = {th.distance, th.normal, HitKind::terrain, -1, -1, th.from_below};
  return out;
}

std::vector<PosedPrimitive> World::primitives_at(double time) const {
  std::vector<PosedPrimitive> out;
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    const Obstacle& o = obstacles_[i];
    if (o.exists_at(time)) pose_obstacle(o, static_cast<int>(i), o.offset_at(time), out);
  }
  return out;
}

Aabb World::bounds(double time) const {
  Aabb b;
  if (terrain_) {
    const GridGeometry& g = terrain_->geometry();
    for (double u : {0.0, g.width_m()})
      for (double v : {0.0, g.height_m()}) {
        const Vec2 w = g.grid_to_world({u, v});
        b.extend(Vec3(w.x(), w.y(), terrain_->min_height()));
        b.extend(Vec3(w.x(), w.y(), terrain_->max_height()));
      }
  }
  for (const PosedPrimitive& p : primitives_at(time)) b.extend(p.box);
  return b;
}

double World::terrain_height(double x, double y) const {
  return terrain_ ? terrain_->height(x, y) : std::numeric_limits<double>::quiet_NaN();
}

double World::surface_height(double x, double y, double time) const {
  Aabb b = static_bounds_;
  if (const auto moving = moving_set(time))
    for (const PosedPrimitive& p : moving->primitives()) b.extend(p.box);
  if (b.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double top = b.hi.z() + 1.0;
  const RayHit h = cast(Vec3(x, y, top), Vec3(0.0, 0.0, -1.0), top - b.lo.z() + 1.0, time);
  return h.hit() ? top - h.distance : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace starnav
