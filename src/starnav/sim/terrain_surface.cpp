#include "starnav/sim/terrain_surface.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Tolerance, in metres along the ray, for a hit found just outside the cell segment being tested
// (the segment ends come from rounded divisions), and in cell units for the diagonal split.
constexpr double kSegmentSlack = 1e-9;
constexpr double kDiagonalSlack = 1e-9;
constexpr int kStartLevel = 3;

float round_down(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

TerrainSurface::TerrainSurface(const ElevationMap& map) : geometry_(map.geometry()) {
  w_ = map.width();
  h_ = map.height();
  sw_ = w_ + 2;
  sh_ = h_ + 2;
  cos_yaw_ = std::cos(geometry_.origin.yaw);
  sin_yaw_ = std::sin(geometry_.origin.yaw);
  s_.resize(static_cast<std::size_t>(sw_) * static_cast<std::size_t>(sh_));
  min_h_ = kInfinity;
  max_h_ = -kInfinity;
  for (int q = 0; q < sh_; ++q) {
    const int iy = std::clamp(q - 1, 0, h_ - 1);
    for (int p = 0; p < sw_; ++p) {
      const int ix = std::clamp(p - 1, 0, w_ - 1);
      double v = std::numeric_limits<double>::quiet_NaN();
      if (map.observed_at(ix, iy)) {
        v = map.height_at(ix, iy);
        min_h_ = std::min(min_h_, v);
        max_h_ = std::max(max_h_, v);
      }
      s_[static_cast<std::size_t>(q) * static_cast<std::size_t>(sw_) + static_cast<std::size_t>(p)] = v;
    }
  }
  if (!(min_h_ <= max_h_)) throw Error("terrain has no observed cell", {}, 0, "terrain");

  // Level 1: blocks of 2 x 2 triangle pairs (3 x 3 samples); there are (w_ + 1) x (h_ + 1) pairs.
  const int pw = w_ + 1, ph = h_ + 1;
  Level first;
  first.w = (pw + 1) / 2;
  first.h = (ph + 1) / 2;
  first.range.resize(2 * static_cast<std::size_t>(first.w) * static_cast<std::size_t>(first.h));
  for (int by = 0; by < first.h; ++by) {
    for (int bx = 0; bx < first.w; ++bx) {
      double lo = kInfinity, hi = -kInfinity;
      for (int q = 2 * by; q <= std::min(2 * by + 2, sh_ - 1); ++q)
        for (int p = 2 * bx; p <= std::min(2 * bx + 2, sw_ - 1); ++p) {
          const double v = sample(p, q);
          if (std::isnan(v)) continue;
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      const std::size_t i = 2 * (static_cast<std::size_t>(by) * static_cast<std::size_t>(first.w) + static_cast<std::size_t>(bx));
      first.range[i] = round_down(lo);
      first.range[i + 1] = round_up(hi);
    }
  }
  levels_.push_back(std::move(first));
  while (levels_.back().w > 1 || levels_.back().h > 1) {
    const Level& below = levels_.back();
    Level up;
    up.w = (below.w + 1) / 2;
    up.h = (below.h + 1) / 2;
    up.range.resize(2 * static_cast<std::size_t>(up.w) * static_cast<std::size_t>(up.h));
    for (int by = 0; by < up.h; ++by)
      for (int bx = 0; bx < up.w; ++bx) {
        float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
        for (int y = 2 * by; y < std::min(2 * by + 2, below.h); ++y)
          for (int x = 2 * bx; x < std::min(2 * bx + 2, below.w); ++x) {
            const std::size_t j = 2 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(below.w) + static_cast<std::size_t>(x));
            lo = std::min(lo, below.range[j]);
            hi = std::max(hi, below.range[j + 1]);
          }
        const std::size_t i = 2 * (static_cast<std::size_t>(by) * static_cast<std::size_t>(up.w) + static_cast<std::size_t>(bx));
        up.range[i] = lo;
        up.range[i + 1] = hi;
      }
    levels_.push_back(std::move(up));
  }
  // Pack the levels into one array (level k >= 1 at level_offset_[k]) so that copies of the
  // surface stay self-contained and the walk needs no per-level indirection.
  level_offset_.assign(levels_.size() + 1, 0);
  level_width_.assign(levels_.size() + 1, 0);
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    level_offset_[k + 1] = pyramid_.size();
    level_width_[k + 1] = levels_[k].w;
    pyramid_.insert(pyramid_.end(), levels_[k].range.begin(), levels_[k].range.end());
    std::vector<float>().swap(levels_[k].range);
  }
}

double TerrainSurface::height(double x, double y) const {
  if (s_.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double wx = x - geometry_.origin.x, wy = y - geometry_.origin.y;
  const double sx = (cos_yaw_ * wx + sin_yaw_ * wy) / geometry_.resolution + 0.5;
  const double sy = (-sin_yaw_ * wx + cos_yaw_ * wy) / geometry_.resolution + 0.5;
  if (!(sx >= 0.5 && sx <= w_ + 0.5 && sy >= 0.5 && sy <= h_ + 0.5)) return std::numeric_limits<double>::quiet_NaN();
  const int cx = std::min(static_cast<int>(sx), w_), cy = std::min(static_cast<int>(sy), h_);
  const double fx = sx - cx, fy = sy - cy;
  const double h00 = sample(cx, cy), h10 = sample(cx + 1, cy), h01 = sample(cx, cy + 1), h11 = sample(cx + 1, cy + 1);
  if (std::isnan(h00) || std::isnan(h10) || std::isnan(h01) || std::isnan(h11)) return std::numeric_limits<double>::quiet_NaN();
  if (fx >= fy) return h00 + (h10 - h00) * fx + (h11 - h10) * fy;
  return h00 + (h11 - h01) * fx + (h01 - h00) * fy;
}

Vec3 TerrainSurface::world_normal(double a, double b) const {
  // Grid-frame gradient (a, b) per cell -> per metre, normal (-gx, -gy, 1), rotated to world.
  const double gx = a / geometry_.resolution, gy = b / geometry_.resolution;
  const double wx = cos_yaw_ * gx - sin_yaw_ * gy, wy = sin_yaw_ * gx + cos_yaw_ * gy;
  return Vec3(-wx, -wy, 1.0).normalized();
}

Vec3 TerrainSurface::normal(double x, double y) const {
  if (std::isnan(height(x, y))) return Vec3::Zero();
  const double wx = x - geometry_.origin.x, wy = y - geometry_.origin.y;
  const double sx = (cos_yaw_ * wx + sin_yaw_ * wy) / geometry_.resolution + 0.5;
  const double sy = (-sin_yaw_ * wx + cos_yaw_ * wy) / geometry_.resolution + 0.5;
  const int cx = std::min(static_cast<int>(sx), w_), cy = std::min(static_cast<int>(sy), h_);
  const double fx = sx - cx, fy = sy - cy;
  const double h00 = sample(cx, cy), h10 = sample(cx + 1, cy), h01 = sample(cx, cy + 1), h11 = sample(cx + 1, cy + 1);
  if (fx >= fy) return world_normal(h10 - h00, h11 - h10);
  return world_normal(h11 - h01, h01 - h00);
}

bool TerrainSurface::cast(const Vec3& origin, const Vec3& dir, double max_range, TerrainHit& hit) const {
  // A non-finite ray hits nothing (and must not reach the traversal, whose steps assume numbers).
  if (s_.empty() || !origin.allFinite() || !dir.allFinite() || std::isnan(max_range)) return false;
  const double res = geometry_.resolution;
  const double wx = origin.x() - geometry_.origin.x, wy = origin.y() - geometry_.origin.y;
  const double ox = (cos_yaw_ * wx + sin_yaw_ * wy) / res + 0.5;
  const double oy = (-sin_yaw_ * wx + cos_yaw_ * wy) / res + 0.5;
  const double dx = (cos_yaw_ * dir.x() + sin_yaw_ * dir.y()) / res;
  const double dy = (-sin_yaw_ * dir.x() + cos_yaw_ * dir.y()) / res;
  return cast_local(ox, oy, origin.z(), dx, dy, dir.z(), max_range, hit);
}

bool TerrainSurface::test_cell(int cx, int cy, double ox, double oy, double oz, double dx, double dy, double dz,
                               double t_lo, double t_hi, TerrainHit& hit) const {
  const double* row0 = &s_[static_cast<std::size_t>(cy) * static_cast<std::size_t>(sw_) + static_cast<std::size_t>(cx)];
  const double* row1 = row0 + sw_;
  const double h00 = row0[0], h10 = row0[1], h01 = row1[0], h11 = row1[1];
  if (std::isnan(h00 + h10 + h01 + h11)) return false;
  // Local coordinates at the segment start.
  const double lx = ox + dx * t_lo - cx, ly = oy + dy * t_lo - cy, lz = oz + dz * t_lo;
  double best = kInfinity;
  double best_a = 0.0, best_b = 0.0;
  auto try_plane = [&](double a, double b, bool upper) {
    // Plane h = h00 + a fx + b fy; ray at t_lo + u: solve lz + dz u = h00 + a (lx + dx u) + b (ly + dy u).
    const double den = dz - a * dx - b * dy;
    if (den == 0.0) return;
    const double u = (h00 + a * lx + b * ly - lz) / den;
    const double t = t_lo + u;
    if (!(t >= t_lo - kSegmentSlack && t <= t_hi + kSegmentSlack)) return;
    const double fx = lx + dx * u, fy = ly + dy * u;
    if (upper ? (fx - fy < -kDiagonalSlack) : (fy - fx < -kDiagonalSlack)) return;
    if (t < best) {
      best = t;
      best_a = a;
      best_b = b;
    }
  };
  try_plane(h10 - h00, h11 - h10, true);   // fx >= fy
  try_plane(h11 - h01, h01 - h00, false);  // fx <  fy
  if (!(best < kInfinity)) return false;
  hit.distance = std::max(best, 0.0);
  hit.normal = world_normal(best_a, best_b);
  hit.from_below = dz - best_a * dx - best_b * dy > 0.0;
  return true;
}

bool TerrainSurface::cast_local(double ox, double oy, double oz, double dx, double dy, double dz, double t_max,
                                TerrainHit& hit) const {
  // Clip the ray to the map's rectangle and to the height range of the samples.
  double t0 = 0.0, t1 = t_max;
  auto clip = [&](double o, double d, double lo, double hi) {
    if (d == 0.0) return o >= lo && o <= hi;
    double ta = (lo - o) / d, tb = (hi - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    return t0 <= t1;
  };
  if (!clip(ox, dx, 0.5, w_ + 0.5) || !clip(oy, dy, 0.5, h_ + 0.5) || !clip(oz, dz, min_h_, max_h_)) return false;

  const int top = static_cast<int>(levels_.size());
  const float* pyramid = pyramid_.data();
  const std::size_t* offset = level_offset_.data();  // level k's (min, max) pairs, k >= 1
  const int* width = level_width_.data();
  // Start a few levels up: the sensor is usually close to the ground, so the top levels (whole
  // map) would only be descended through; a ray in open space climbs from there at every step.
  int level = std::min(kStartLevel, top);
  // Positions inside the clipped domain are >= 0 up to rounding, so truncation is floor here
  // (the clamps absorb a rounding step below 0).
  int cx = std::clamp(static_cast<int>(ox + dx * t0), 0, w_);
  int cy = std::clamp(static_cast<int>(oy + dy * t0), 0, h_);
  const bool mx = dx != 0.0, my = dy != 0.0;
  const double idx = mx ? 1.0 / dx : 0.0, idy = my ? 1.0 / dy : 0.0;
  const int ix = dx > 0.0 ? 1 : 0, iy = dy > 0.0 ? 1 : 0;
  double t = t0;
  for (;;) {
    const int bx = cx >> level, by = cy >> level;
    const double tx = mx ? (static_cast<double>((bx + ix) << level) - ox) * idx : kInfinity;
    const double ty = my ? (static_cast<double>((by + iy) << level) - oy) * idy : kInfinity;
    const bool exit_x = tx <= ty;
    const double te = exit_x ? tx : ty;
    const double tseg = te < t1 ? te : t1;
    if (level > 0) {
      const float* r = pyramid + offset[level] + 2 * (static_cast<std::size_t>(by) * static_cast<std::size_t>(width[level]) + static_cast<std::size_t>(bx));
      const double za = oz + dz * t, zb = oz + dz * tseg;
      const double zlo = za < zb ? za : zb, zhi = za < zb ? zb : za;
      if (!(zlo > r[1] || zhi < r[0])) {
        --level;
        continue;
      }
    } else {
      if (test_cell(cx, cy, ox, oy, oz, dx, dy, dz, t, tseg, hit)) return true;
    }
    if (te >= t1) return false;
    if (exit_x) {
      cx = ((bx + ix) << level) - (1 - ix);
      const int lo = by << level, hi = std::min(((by + 1) << level) - 1, h_);
      cy = std::clamp(static_cast<int>(oy + dy * te), lo, hi);
      if (cx < 0 || cx > w_) return false;
    } else {
      cy = ((by + iy) << level) - (1 - iy);
      const int lo = bx << level, hi = std::min(((bx + 1) << level) - 1, w_);
      cx = std::clamp(static_cast<int>(ox + dx * te), lo, hi);
      if (cy < 0 || cy > h_) return false;
    }
    if (te > t) t = te;
    // Climb while the step crossed into a new block of the level above.
    for (int px = bx >> 1, py = by >> 1; level < top && ((cx >> (level + 1)) != px || (cy >> (level + 1)) != py);
         px >>= 1, py >>= 1)
      ++level;
  }
}

}  // namespace starnav
