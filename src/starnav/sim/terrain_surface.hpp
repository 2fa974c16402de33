#pragma once
// The ground of the simulated world: an ElevationMap read as a continuous surface, with exact
// ray casting against it.
//
// Surface. The map's cell heights are samples at the cell centres. Between four neighbouring
// centres the surface is two planar triangles split along the diagonal from centre (i, j) to
// centre (i+1, j+1): with fx, fy in [0, 1] the position between the four centres,
//   fx >= fy:  h = h00 + (h10 - h00) fx + (h11 - h10) fy
//   fx <  fy:  h = h00 + (h11 - h01) fx + (h01 - h00) fy
// (piecewise linear, continuous, exact for any plane). In the half-cell strip between the outer
// centres and the map's edge the height is that of the nearest point of the centres' span (the
// edge samples are replicated), so the surface covers exactly the map's rectangle. Outside the
// map there is no ground. Unobserved cells are holes: every triangle touching one is absent.
//
// Ray casting walks the cells along the ray (2D DDA) over a min/max pyramid (level k holds the
// lowest and highest sample of each 2^k x 2^k block of triangle pairs) and skips every block the
// ray passes entirely above or below; in the cells it cannot skip it solves the ray against the
// two planes, so the hit is exact to rounding.
#include <cstdint>
#include <limits>
#include <vector>

#include "starnav/map/elevation_map.hpp"

namespace starnav {

struct TerrainHit {
  double distance = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();  // upward unit normal of the triangle hit
  bool from_below = false;     // the ray came from under the surface
};

class TerrainSurface {
 public:
  TerrainSurface() = default;
  // Throws Error when the map has no observed cell.
  explicit TerrainSurface(const ElevationMap& map);

  const GridGeometry& geometry() const { return geometry_; }
  double min_height() const { return min_h_; }
  double max_height() const { return max_h_; }

  // Surface height at a world point; NaN outside the map or over a hole.
  double height(double x, double y) const;
  // Upward unit normal at a world point (of the triangle containing it); zero where height is NaN.
  Vec3 normal(double x, double y) const;

  // First crossing of the surface by origin + s * dir, s in [0, max_range] (dir a unit vector).
  bool cast(const Vec3& origin, const Vec3& dir, double max_range, TerrainHit& hit) const;

  int pyramid_levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    int w = 0, h = 0;
    std::vector<float> range;  // (min, max) pairs per block, row-major; moved into pyramid_
  };
  // Samples padded by one replicated ring: padded sample (p, q) sits at s = (p, q) in the
  // "sample frame" s = grid_xy / resolution + 0.5; the pair of triangles (p, q) spans [p, p+1] x
  // [q, q+1]; the map covers s in [0.5, W + 0.5] x [0.5, H + 0.5].
  double sample(int p, int q) const { return s_[static_cast<std::size_t>(q) * static_cast<std::size_t>(sw_) + static_cast<std::size_t>(p)]; }
  bool cast_local(double ox, double oy, double oz, double dx, double dy, double dz, double t_max, TerrainHit& hit) const;
  bool test_cell(int cx, int cy, double ox, double oy, double oz, double dx, double dy, double dz, double t_lo,
                 double t_hi, TerrainHit& hit) const;
  Vec3 world_normal(double gx, double gy) const;  // from grid-frame slope components

  GridGeometry geometry_;
  int w_ = 0, h_ = 0;    // map cells
  int sw_ = 0, sh_ = 0;  // padded samples (w_ + 2, h_ + 2)
  std::vector<double> s_;
  std::vector<Level> levels_;  // levels_[k] covers blocks of 2^(k+1) x 2^(k+1) triangle pairs
  std::vector<float> pyramid_;             // every level's (min, max) pairs
  std::vector<std::size_t> level_offset_;  // [k]: start of level k (= levels_[k - 1]) in pyramid_
  std::vector<int> level_width_;           // [k]: blocks per row of level k
  double min_h_ = 0.0, max_h_ = 0.0;
  double cos_yaw_ = 1.0, sin_yaw_ = 0.0;
};

}  // namespace starnav
