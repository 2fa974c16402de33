#include "starnav/terrain/terrain_analysis.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

const char* unobserved_policy_name(UnobservedPolicy p) {
  switch (p) {
    case UnobservedPolicy::Blocked: return "blocked";
    case UnobservedPolicy::FreeFlat: return "free_flat";
    case UnobservedPolicy::UnknownCost: return "unknown_cost";
  }
  return "?";
}

UnobservedPolicy parse_unobserved_policy(const std::string& name, const std::string& field) {
  if (name == "blocked") return UnobservedPolicy::Blocked;
  if (name == "free_flat") return UnobservedPolicy::FreeFlat;
  if (name == "unknown_cost") return UnobservedPolicy::UnknownCost;
  throw Error("unknown policy '" + name + "' (blocked, free_flat, unknown_cost)", {}, 0, field);
}

void LiNodeParams::validate() const {
  if (!std::isfinite(max_step_m) || !(max_step_m > 0.0)) throw Error("must be a finite number > 0", {}, 0, "max_step_m");
  if (!std::isfinite(max_slope_rad) || !(max_slope_rad > 0.0) || max_slope_rad >= kPi / 2)
    throw Error("must be in (0, pi/2)", {}, 0, "max_slope_rad");
}

void TerrainAnalysisOptions::validate() const {
  thresholds.validate();
  li.validate();
  if (!std::isfinite(robot_radius_m) || robot_radius_m < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "robot_radius_m");
}

const ParamTable<TerrainAnalysisOptions>& terrain_analysis_params() {
  static const ParamTable<TerrainAnalysisOptions> table = [] {
    using O = TerrainAnalysisOptions;
    ParamTable<O> t;
    t.choice(
        "unobserved", {"blocked", "free_flat", "unknown_cost"},
        [](O& o, const std::string& v) { o.unobserved = parse_unobserved_policy(v); },
        [](const O& o) { return std::string(unobserved_policy_name(o.unobserved)); }, "how unobserved cells are treated");
    t.real("h_y", [](O& o) -> double& { return o.thresholds.h_y; }, positive(), "m",
           "Liu obstacle: a height difference to a neighbour from this on");
    t.real("a_y", [](O& o) -> double& { return o.thresholds.a_y; }, open(0.0, kPi / 2), "rad",
           "Liu obstacle: a slope to a neighbour from this on");
    t.real("s_y", [](O& o) -> double& { return o.thresholds.s_y; }, positive(), "m^2",
           "Liu obstacle: a ruggedness (3x3 height variance) from this on");
    t.real("max_step_m", [](O& o) -> double& { return o.li.max_step_m; }, positive(), "m",
           "Li 2019: the largest step the robot climbs (a cell's height spread)");
    t.real("max_slope_deg", [](O& o) -> double& { return o.li.max_slope_rad; }, open(0.0, 90.0), "deg",
           "Li 2019: the steepest slope the robot climbs", kPi / 180.0);
    t.real("robot_radius_m", &O::robot_radius_m, non_negative(), "m", "obstacles are expanded by this radius (0: none)");
    return t;
  }();
  return table;
}

int move_index(int dx, int dy) {
  for (int k = 0; k < kMoveCount; ++k)
    if (kMoveDx[k] == dx && kMoveDy[k] == dy) return k;
  return -1;
}

BlockStats block_stats(const std::vector<double>& z, const std::vector<std::uint8_t>& observed, int width, int height,
                       double resolution, int x, int y) {
  BlockStats s;
  const std::size_t w = static_cast<std::size_t>(width);
  const int xa = std::max(0, x - 1), xb = std::min(width - 1, x + 1);
  const int ya = std::max(0, y - 1), yb = std::min(height - 1, y + 1);
  // Full interior block: closed forms (the plane fit over a full 3x3 block has
  // gx = (sum of the right column - sum of the left column) / (6 res), likewise gy).
  bool full = xa == x - 1 && xb == x + 1 && ya == y - 1 && yb == y + 1;
  if (full) {
    for (int j = ya; j <= yb && full; ++j)
      for (int i = xa; i <= xb; ++i)
        if (!observed[static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i)]) {
          full = false;
          break;
        }
  }
  if (full) {
    const double* r0 = z.data() + static_cast<std::size_t>(y - 1) * w + static_cast<std::size_t>(x - 1);
    const double* r1 = r0 + w;
    const double* r2 = r1 + w;
    const double sum = r0[0] + r0[1] + r0[2] + r1[0] + r1[1] + r1[2] + r2[0] + r2[1] + r2[2];
    const double mean = sum / 9.0;
    double var = 0.0;
    for (const double* r : {r0, r1, r2})
      for (int i = 0; i < 3; ++i) var += (r[i] - mean) * (r[i] - mean);
    s.count = 9;
    s.mean = mean;
    s.variance = var / 9.0;
    s.grad_x = ((r0[2] + r1[2] + r2[2]) - (r0[0] + r1[0] + r2[0])) / (6.0 * resolution);
    s.grad_y = ((r2[0] + r2[1] + r2[2]) - (r0[0] + r0[1] + r0[2])) / (6.0 * resolution);
    return s;
  }
  // General case: the observed cells of the clipped block.
  int n = 0;
  double sum = 0.0, sx = 0.0, sy = 0.0;
  for (int j = ya; j <= yb; ++j)
    for (int i = xa; i <= xb; ++i) {
      const std::size_t id = static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i);
      if (!observed[id]) continue;
      ++n;
      sum += z[id];
      sx += i - x;
      sy += j - y;
    }
  if (n == 0) return s;
  const double mean = sum / n, mx = sx / n, my = sy / n;
  double var = 0.0, cxx = 0.0, cxy = 0.0, cyy = 0.0, rx = 0.0, ry = 0.0;
  for (int j = ya; j <= yb; ++j)
    for (int i = xa; i <= xb; ++i) {
      const std::size_t id = static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i);
      if (!observed[id]) continue;
      const double dz = z[id] - mean, dx = (i - x) - mx, dy = (j - y) - my;
      var += dz * dz;
      cxx += dx * dx;
      cxy += dx * dy;
      cyy += dy * dy;
      rx += dx * dz;
      ry += dy * dz;
    }
  s.count = n;
  s.mean = mean;
  s.variance = var / n;
  // Least squares z = c + gx x + gy y: [cxx cxy; cxy cyy] (gx, gy) = (rx, ry), minimum-norm
  // (pseudo-inverse) when the points are collinear (slope 0 across the line), 0 for one point.
  const double trace = cxx + cyy;
  const double det = cxx * cyy - cxy * cxy;
  double gx = 0.0, gy = 0.0;
  if (trace > 0.0) {
    if (det > 1e-9 * trace * trace) {
      gx = (cyy * rx - cxy * ry) / det;
      gy = (cxx * ry - cxy * rx) / det;
    } else {
      // Rank 1: the matrix is trace * u u^T with u the unit direction of the points' line.
      double ux = cxx, uy = cxy;
      if (std::abs(cxy) < 1e-12 && cyy > cxx) ux = 0.0, uy = 1.0;
      else if (std::abs(cxy) < 1e-12) ux = 1.0, uy = 0.0;
      const double norm = std::hypot(ux, uy);
      ux /= norm;
      uy /= norm;
      const double t = (ux * rx + uy * ry) / trace;
      gx = ux * t;
      gy = uy * t;
    }
  }
  s.grad_x = gx / resolution;
  s.grad_y = gy / resolution;
  return s;
}

TerrainAnalysis::TerrainAnalysis(const ElevationMap& map, const TerrainAnalysisOptions& options) {
  compute(map, options);
}

void TerrainAnalysis::compute(const ElevationMap& map, const TerrainAnalysisOptions& options) {
  options.validate();
  if (map.cell_count() == 0) throw Error("elevation map is empty", {}, 0, "map");
  geometry_ = map.geometry();
  options_ = options;
  diagonal_length_ = geometry_.resolution * std::sqrt(2.0);
  const std::size_t n = geometry_.cell_count();
  z_.assign(n, 0.0);
  observed_.assign(n, 0);
  mid_.assign(n, 0.0);
  spread_.assign(n, 0.0);
  rugged_.assign(n, 0.0);
  grad_x_.assign(n, 0.0);
  grad_y_.assign(n, 0.0);
  obstacle_.assign(n, 0);
  li_blocked_.assign(n, 0);
  const CellRect all{0, 0, geometry_.width, geometry_.height};
  compute_cells(map, all);
  compute_block_stats(all);
  compute_masks(all);
  compute_expansion(all);
}

void TerrainAnalysis::update(const ElevationMap& map, CellRect changed) {
  const GridGeometry& g = map.geometry();
  if (g.width != geometry_.width || g.height != geometry_.height || g.resolution != geometry_.resolution)
    throw Error("update needs a map of the analysed geometry", {}, 0, "map");
  const int w = geometry_.width, h = geometry_.height;
  changed = changed.grown(0, w, h);
  if (changed.empty()) return;
  compute_cells(map, changed);
  // S and the plane fit of a cell read its 3x3 block; its masks read the block statistics and
  // the moves to its neighbours: one ring each.
  const CellRect stats = changed.grown(1, w, h);
  compute_block_stats(stats);
  const CellRect masks = changed.grown(1, w, h);
  compute_masks(masks);
  compute_expansion(masks);
}

void TerrainAnalysis::compute_cells(const ElevationMap& map, const CellRect& r) {
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const std::size_t i = index(x, y);
      const bool obs = map.observed_at_index(i);
      observed_[i] = obs ? 1 : 0;
      z_[i] = obs ? map.height_at_index(i) : 0.0;
      mid_[i] = obs ? 0.5 * (map.min_height_at(x, y) + map.max_height_at(x, y)) : 0.0;
      spread_[i] = obs ? map.max_height_at(x, y) - map.min_height_at(x, y) : 0.0;
    }
}

void TerrainAnalysis::compute_block_stats(const CellRect& r) {
  const int w = geometry_.width, h = geometry_.height;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const std::size_t i = index(x, y);
      if (!observed_[i]) {
        rugged_[i] = grad_x_[i] = grad_y_[i] = 0.0;
        continue;
      }
      const BlockStats s = block_stats(z_, observed_, w, h, geometry_.resolution, x, y);
      rugged_[i] = s.variance;
      grad_x_[i] = s.grad_x;
      grad_y_[i] = s.grad_y;
    }
}

MoveTerrain TerrainAnalysis::move(int x, int y, int k) const {
  MoveTerrain m;
  m.length = move_length(k);
  const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
  if (!contains(nx, ny)) return m;
  const std::size_t a = index(x, y), b = index(nx, ny);
  if (!observed_[a] || !observed_[b]) return m;
  m.known = true;
  m.h = std::abs(z_[b] - z_[a]);
  m.a = liu_slope(m.h, m.length);
  return m;
}

Vec3 TerrainAnalysis::normal(int x, int y) const {
  const std::size_t i = index(x, y);
  const double c = std::cos(geometry_.origin.yaw), s = std::sin(geometry_.origin.yaw);
  const double gx = c * grad_x_[i] - s * grad_y_[i];
  const double gy = s * grad_x_[i] + c * grad_y_[i];
  return Vec3(-gx, -gy, 1.0).normalized();
}

double TerrainAnalysis::cell_slope(int x, int y) const {
  const std::size_t i = index(x, y);
  return std::atan(std::hypot(grad_x_[i], grad_y_[i]));
}

namespace {

// Whether a move of height difference h and length l reaches a threshold: h >= h_y or
// atan(h / l) >= a_y. The atan is only evaluated within a relative 1e-12 of the slope limit
// h = l tan(a_y); elsewhere the comparison on h decides the same.
struct ThresholdTest {
  double h_y, a_y, limit_straight, limit_diagonal;
  ThresholdTest(const LiuCostParams& p, double resolution)
      : h_y(p.h_y), a_y(p.a_y), limit_straight(resolution * std::tan(p.a_y)),
        limit_diagonal(resolution * std::sqrt(2.0) * std::tan(p.a_y)) {}
  bool reached(double h, double l, bool diagonal) const {
    if (!(h < h_y)) return true;
    const double limit = diagonal ? limit_diagonal : limit_straight;
    if (h < limit * (1.0 - 1e-12)) return false;
    if (h > limit * (1.0 + 1e-12)) return true;
    return !(liu_slope(h, l) < a_y);
  }
};

// The Liu obstacle test of one cell (docs/terrain.md).
bool liu_obstacle_at(const TerrainAnalysis& t, int x, int y, const LiuCostParams& p, const ThresholdTest& test) {
  if (!t.observed(x, y)) return t.options().unobserved == UnobservedPolicy::Blocked;
  if (!(t.ruggedness(x, y) < p.s_y)) return true;
  const double z = t.z(x, y);
  for (int k = 0; k < kMoveCount; ++k) {
    const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
    if (!t.contains(nx, ny) || !t.observed(nx, ny)) continue;
    if (test.reached(std::abs(t.z(nx, ny) - z), t.move_length(k), move_is_diagonal(k))) return true;
  }
  return false;
}

}  // namespace

void TerrainAnalysis::compute_masks(const CellRect& r) {
  const double k_slope = std::tan(options_.li.max_slope_rad);
  const bool unobserved_blocked = options_.unobserved == UnobservedPolicy::Blocked;
  const ThresholdTest test(options_.thresholds, geometry_.resolution);
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const std::size_t i = index(x, y);
      obstacle_[i] = liu_obstacle_at(*this, x, y, options_.thresholds, test) ? 1 : 0;
      if (!observed_[i]) {
        li_blocked_[i] = unobserved_blocked ? 1 : 0;
        continue;
      }
      bool blocked = spread_[i] > options_.li.max_step_m;
      for (int k = 0; k < kMoveCount && !blocked; ++k) {
        const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
        if (!contains(nx, ny)) continue;
        const std::size_t j = index(nx, ny);
        if (!observed_[j]) continue;
        blocked = std::abs(mid_[i] - mid_[j]) > k_slope * move_length(k);
      }
      li_blocked_[i] = blocked ? 1 : 0;
    }
}

namespace {

}  // namespace

void TerrainAnalysis::compute_expansion(const CellRect& affected) {
  const int w = geometry_.width, h = geometry_.height;
  const double rc = inflation_radius_cells(options_.robot_radius_m, geometry_.resolution);
  const bool whole = affected.x0 == 0 && affected.y0 == 0 && affected.x1 == w && affected.y1 == h;
  if (whole || expanded_obstacle_.size() != z_.size()) {
    expanded_obstacle_ = inflate_mask(obstacle_, w, h, rc);
    expanded_li_ = inflate_mask(li_blocked_, w, h, rc);
    return;
  }
  inflation_.update(obstacle_, w, h, rc, affected, expanded_obstacle_);
  inflation_.update(li_blocked_, w, h, rc, affected, expanded_li_);
}

std::vector<std::uint8_t> liu_obstacle_mask(const TerrainAnalysis& analysis, const LiuCostParams& thresholds) {
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(analysis.width()) * static_cast<std::size_t>(analysis.height()));
  const ThresholdTest test(thresholds, analysis.resolution());
  for (int y = 0; y < analysis.height(); ++y)
    for (int x = 0; x < analysis.width(); ++x)
      mask[analysis.index(x, y)] = liu_obstacle_at(analysis, x, y, thresholds, test) ? 1 : 0;
  return mask;
}

}  // namespace starnav
