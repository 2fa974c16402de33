#include "starnav/costmap/node_height_layer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

constexpr int kTile = 32;  // cells per side of the tiles the incremental refresh works in
constexpr std::uint32_t kNoCell = std::numeric_limits<std::uint32_t>::max();

}  // namespace

void NodeMapParams::validate() const {
  li.validate();
  if (!std::isfinite(barrier_distance_m) || barrier_distance_m < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "barrier_distance_m");
  if (!std::isfinite(clear_margin_m) || clear_margin_m < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "clear_margin_m");
  if (hit_gain < 1 || hit_gain > 255) throw Error("must be in 1..255", {}, 0, "hit_gain");
  if (miss_loss < 1 || miss_loss > 255) throw Error("must be in 1..255", {}, 0, "miss_loss");
  // A cell hit in a scan must stay observed whatever else happened to it in that scan.
  if (miss_loss > hit_gain) throw Error("must be <= hit_gain", {}, 0, "miss_loss");
  if (evidence_max < hit_gain || evidence_max > 255) throw Error("must be in hit_gain..255", {}, 0, "evidence_max");
  if (!std::isfinite(clearance_range_m) || !(clearance_range_m > 0.0) || clearance_range_m > 100.0)
    throw Error("must be in (0, 100]", {}, 0, "clearance_range_m");
}

NodeHeightLayer::NodeHeightLayer(const GridGeometry& geometry, const NodeMapParams& params)
    : geometry_(geometry), params_(params) {
  validate_geometry(geometry_, "geometry");
  if (geometry_.y_down) throw Error("a navigation map must be metric (y up)", {}, 0, "geometry");
  params_.validate();
  const std::size_t n = geometry_.cell_count();
  evidence_.assign(n, 0);
  lo_.assign(n, 0.0);
  hi_.assign(n, 0.0);
  hit_stamp_.assign(n, 0);
  miss_stamp_.assign(n, 0);
  touch_stamp_.assign(n, 0);
  const int tiles_x = (geometry_.width + kTile - 1) / kTile, tiles_y = (geometry_.height + kTile - 1) / kTile;
  tile_dirty_.assign(static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y), 0);
  elevation_ = ElevationMap(geometry_);
  recompute();
}

void NodeHeightLayer::recompute() {
  if (params_.mode != NodeMapMode::Nodes3D) return;
  TerrainAnalysisOptions options;
  options.unobserved = UnobservedPolicy::FreeFlat;  // unknown cells are free for planning
  options.li = params_.li;
  options.robot_radius_m = 0.0;  // the costmap expands the obstacles (incrementally)
  analysis_.compute(elevation_, options);
}

void NodeHeightLayer::contribute(const CellRect& rect, std::span<std::uint8_t> obstacles,
                                 std::span<std::uint8_t> observed) const {
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      if (obstacle(i)) obstacles[i] = 1;
      if (evidence_[i] > 0) observed[i] = 1;
    }
}

void NodeHeightLayer::touch(std::uint32_t i) {
  if (touch_stamp_[i] == scan_) return;
  touch_stamp_[i] = scan_;
  touched_.push_back({i, lo_[i], hi_[i], evidence_[i] > 0});
}

// Amanatides & Woo (1987) over the cells of the segment a -> b (continuous cell coordinates),
// clipped to the grid; stops before `end_cell`. z runs linearly from za to zb along the segment.
void NodeHeightLayer::walk_beam(const Vec2& a, const Vec2& b, double za, double zb, std::uint32_t end_cell) {
  const double w = geometry_.width, h = geometry_.height;
  const Vec2 d = b - a;
  // Liang-Barsky clip of t in [0, 1] to [0, w] x [0, h].
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x(), w - a.x(), a.y(), h - a.y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0.0) t0 = std::max(t0, r);
    else t1 = std::min(t1, r);
  }
  if (!(t0 < t1)) return;
  const Vec2 s = a + t0 * d;
  int x = std::clamp(GridGeometry::floor_to_int(s.x()), 0, geometry_.width - 1);
  int y = std::clamp(GridGeometry::floor_to_int(s.y()), 0, geometry_.height - 1);
  const int step_x = d.x() > 0 ? 1 : (d.x() < 0 ? -1 : 0);
  const int step_y = d.y() > 0 ? 1 : (d.y() < 0 ? -1 : 0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double dt_x = step_x != 0 ? 1.0 / std::abs(d.x()) : kInf;
  const double dt_y = step_y != 0 ? 1.0 / std::abs(d.y()) : kInf;
  double next_x = step_x > 0 ? (x + 1 - a.x()) / d.x() : (step_x < 0 ? (x - a.x()) / d.x() : kInf);
  double next_y = step_y > 0 ? (y + 1 - a.y()) / d.y() : (step_y < 0 ? (y - a.y()) / d.y() : kInf);
  const bool planar = params_.mode == NodeMapMode::Lidar2D;
  const double margin = params_.clear_margin_m;
  double t_in = t0;
  const int max_steps = geometry_.width + geometry_.height + 2;
  for (int steps = 0; steps < max_steps; ++steps) {
    const std::uint32_t i = static_cast<std::uint32_t>(geometry_.index(x, y));
    if (i == end_cell) return;
    const double t_out = std::min({next_x, next_y, t1});
    if (evidence_[i] > 0 && miss_stamp_[i] != scan_) {
      bool contradicts = planar;
      if (!planar) {
        // The beam's highest point inside the cell must lie clearly below the cell's highest hit.
        const double z_top = std::max(za + t_in * (zb - za), za + t_out * (zb - za));
        contradicts = hi_[i] > z_top + margin;
      }
      if (contradicts) {
        miss_stamp_[i] = scan_;
        touch(i);
      }
    }
    if (t_out >= t1) return;
    t_in = t_out;
    if (next_x < next_y) {
      x += step_x;
      next_x += dt_x;
    } else {
      y += step_y;
      next_y += dt_y;
    }
    if (x < 0 || y < 0 || x >= geometry_.width || y >= geometry_.height) return;
  }
}

void NodeHeightLayer::on_scan(const CostmapScan& scan, std::vector<CellRect>& changed, CostmapScanStats& update) {
  const Vec3& origin = scan.origin;
  const std::span<const Vec3> points = scan.points;
  const std::span<const Vec3> pass_ends = scan.pass_ends;
  ++scan_;
  if (scan_ == 0) {  // stamps wrapped: forget them all
    std::fill(hit_stamp_.begin(), hit_stamp_.end(), 0);
    std::fill(miss_stamp_.begin(), miss_stamp_.end(), 0);
    std::fill(touch_stamp_.begin(), touch_stamp_.end(), 0);
    scan_ = 1;
  }
  touched_.clear();
  const bool planar = params_.mode == NodeMapMode::Lidar2D;
  const std::size_t hits_before = update.cells_hit;
  const bool origin_ok = origin.allFinite();
  const Vec2 origin_cell = geometry_.world_to_cell_continuous(origin.head<2>());

  // 1. Passes, judged against the map before this scan.
  if (params_.clear && any_evidence_ && origin_ok) {
    for (const Vec3& p : points) {
      if (!p.allFinite()) continue;
      const Vec2 c = geometry_.world_to_cell_continuous(p.head<2>());
      const std::optional<Cell> end = geometry_.world_to_cell(p.head<2>());
      const std::uint32_t end_cell = end ? static_cast<std::uint32_t>(geometry_.index(end->x, end->y)) : kNoCell;
      walk_beam(origin_cell, c, origin.z(), p.z(), end_cell);
    }
    for (const Vec3& p : pass_ends)
      if (p.allFinite())
        walk_beam(origin_cell, geometry_.world_to_cell_continuous(p.head<2>()), origin.z(), p.z(), kNoCell);
  }
  update.cells_contradicted += touched_.size();  // so far only passes touched cells

  // 2. Hits. A cell contradicted in this scan, or unobserved, restarts its heights from the scan's
  // own returns; any other cell accumulates.
  for (const Vec3& p : points) {
    if (!p.allFinite()) continue;
    const std::optional<Cell> cell = geometry_.world_to_cell(p.head<2>());
    if (!cell) continue;
    ++update.returns_used;
    const std::uint32_t i = static_cast<std::uint32_t>(geometry_.index(cell->x, cell->y));
    const double z = planar ? 0.0 : p.z();
    if (hit_stamp_[i] != scan_) {
      hit_stamp_[i] = scan_;
      touch(i);
      ++update.cells_hit;
      if (miss_stamp_[i] == scan_ || evidence_[i] == 0) {
        lo_[i] = hi_[i] = z;
        continue;
      }
    }
    lo_[i] = std::min(lo_[i], z);
    hi_[i] = std::max(hi_[i], z);
  }

  // 3. Evidence, and the cells whose state changed.
  const int tiles_x = (geometry_.width + kTile - 1) / kTile;
  dirty_tiles_.clear();
  for (const Touched& t : touched_) {
    const std::uint32_t i = t.index;
    int e = evidence_[i];
    if (hit_stamp_[i] == scan_) e += params_.hit_gain;
    if (miss_stamp_[i] == scan_) e -= params_.miss_loss;
    e = std::clamp(e, 0, params_.evidence_max);
    evidence_[i] = static_cast<std::uint8_t>(e);
    const bool now_observed = e > 0;
    if (!now_observed) {
      lo_[i] = hi_[i] = 0.0;
      if (t.old_observed) ++update.cells_cleared;
    }
    const bool changed = now_observed != t.old_observed || (now_observed && (lo_[i] != t.old_lo || hi_[i] != t.old_hi));
    if (!changed) continue;
    ++update.cells_changed;
    const Cell c = geometry_.cell_of_index(i);
    if (!planar) {
      if (now_observed) elevation_.set_cell(c.x, c.y, 0.5 * (lo_[i] + hi_[i]), lo_[i], hi_[i]);
      else elevation_.clear_cell(c.x, c.y);
    }
    const std::uint32_t tile = static_cast<std::uint32_t>((c.y / kTile) * tiles_x + c.x / kTile);
    if (!tile_dirty_[tile]) {
      tile_dirty_[tile] = 1;
      dirty_tiles_.push_back(tile);
    }
  }
  any_evidence_ = any_evidence_ || hits_before != update.cells_hit;

  // 4. The analysis over the dirty tiles, in tile order (deterministic); the tiles (grown by the
  // one cell the Li criteria read around each) are what changed.
  std::sort(dirty_tiles_.begin(), dirty_tiles_.end());
  for (const std::uint32_t tile : dirty_tiles_) {
    tile_dirty_[tile] = 0;
    const int tx = static_cast<int>(tile) % tiles_x, ty = static_cast<int>(tile) / tiles_x;
    const CellRect r{tx * kTile, ty * kTile, std::min(geometry_.width, (tx + 1) * kTile),
                     std::min(geometry_.height, (ty + 1) * kTile)};
    if (!planar) analysis_.update(elevation_, r);
    changed.push_back(planar ? r : r.grown(1, geometry_.width, geometry_.height));  // Li reads 8 neighbours
  }
}

CostmapLayerDef node_height_layer() {
  CostmapLayerDef d;
  d.info.role = Role::CostmapLayer;
  d.info.name = "node_height";
  d.info.section = "node_height";
  d.info.summary =
      "LiDAR returns into a grid of 3D nodes (Li 2019: walkable by height spread and slope) or, with a 2D LiDAR, marked "
      "cells; beams clear what they pass (its settings: navigation.map.*)";
  d.make = [](const CostmapLayerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<CostmapLayer> {
    if (!settings.empty()) param_unknown_key(settings.front(), {});
    return std::make_unique<NodeHeightLayer>(ctx.geometry, ctx.map);
  };
  return d;
}

}  // namespace starnav
