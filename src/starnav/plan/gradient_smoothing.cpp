#include "starnav/plan/gradient_smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Slack (cells) by which a segment's extent is grown before the cells it touches are listed, so
// that rounding can never let it slip past a cell it touches exactly (at an edge or a corner).
constexpr double kTouchSlackCells = 1e-9;

// E's two parts at samples p against input samples o (cells).
double energy(const std::vector<Vec2>& p, const std::vector<Vec2>& o, double w_data, double w_smooth) {
  double e = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) e += w_data * (p[i] - o[i]).squaredNorm();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) e += w_smooth * (p[i - 1] - 2.0 * p[i] + p[i + 1]).squaredNorm();
  return e;
}

// Visits every cell whose closed square meets the segment a-b (continuous cell coordinates; a
// point when a == b: its cell, both cells on an edge, all four at a corner), the segment grown by
// kTouchSlackCells. Returns false as soon as `visit` does, and when a coordinate is not finite or
// any part lies off a width x height map; true otherwise.
template <class Visit>
bool visit_touched_cells(int width, int height, const Vec2& a, const Vec2& b, Visit&& visit) {
  if (!a.allFinite() || !b.allFinite()) return false;
  const double left = std::min(a.x(), b.x()), right = std::max(a.x(), b.x());
  const double xmin = left - kTouchSlackCells, xmax = right + kTouchSlackCells;
  const double ymin = std::min(a.y(), b.y()) - kTouchSlackCells, ymax = std::max(a.y(), b.y()) + kTouchSlackCells;
  // This also bounds the loops below by the map's size.
  if (xmin < 0.0 || ymin < 0.0 || xmax > width || ymax > height) return false;
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  // Columns whose closed square [i, i+1] meets [xmin, xmax]; in each, the rows the segment's y
  // spans over the part of the column it crosses.
  const int i0 = std::max(0, static_cast<int>(std::ceil(xmin)) - 1);
  const int i1 = std::min(width - 1, static_cast<int>(std::floor(xmax)));
  for (int i = i0; i <= i1; ++i) {
    double lo = ymin, hi = ymax;
    if (dx != 0.0) {
      const double y0 = a.y() + (std::clamp(static_cast<double>(i), left, right) - a.x()) / dx * dy;
      const double y1 = a.y() + (std::clamp(static_cast<double>(i + 1), left, right) - a.x()) / dx * dy;
      lo = std::min(y0, y1) - kTouchSlackCells;
      hi = std::max(y0, y1) + kTouchSlackCells;
    }
    const int j0 = std::max(0, static_cast<int>(std::ceil(lo)) - 1);
    const int j1 = std::min(height - 1, static_cast<int>(std::floor(hi)));
    for (int j = j0; j <= j1; ++j)
      if (!visit(i, j)) return false;
  }
  return true;
}

// The segment between two points in continuous cell coordinates touches only passable cells.
bool cells_clear(const GridSearchMap& map, const Vec2& a, const Vec2& b) {
  return visit_touched_cells(map.width(), map.height(), a, b,
                             [&](int x, int y) { return map.passable(map.state(x, y)); });
}

}  // namespace

void validate_gradient_smoothing(const GradientSmoothingOptions& o) {
  if (!(std::isfinite(o.weight_data) && o.weight_data > 0.0))
    throw Error("must be a finite weight > 0", {}, 0, "smooth_weight_data");
  if (!(std::isfinite(o.weight_smooth) && o.weight_smooth >= 0.0))
    throw Error("must be a finite weight >= 0", {}, 0, "smooth_weight_smooth");
  if (!(std::isfinite(o.spacing_m) && o.spacing_m >= 0.0))
    throw Error("must be a finite spacing >= 0 (0: the map's resolution)", {}, 0, "smooth_spacing");
  if (!(std::isfinite(o.min_clearance_m) && o.min_clearance_m >= 0.0))
    throw Error("must be a finite distance >= 0", {}, 0, "smooth_clearance");
  if (o.max_iterations < 0 || o.max_iterations > 1000000)
    throw Error("must be in 0 .. 1000000", {}, 0, "smooth_iterations");
  if (!(std::isfinite(o.tolerance_m) && o.tolerance_m >= 0.0))
    throw Error("must be a finite distance >= 0", {}, 0, "smooth_tolerance");
}

std::vector<Vec2> resample_polyline(std::span<const Vec2> path, double spacing) {
  if (!(spacing > 0.0)) throw Error("must be > 0", {}, 0, "spacing");
  std::vector<Vec2> out;
  if (path.empty()) return out;
  out.push_back(path[0]);
  for (std::size_t k = 1; k < path.size(); ++k) {
    const Vec2 a = path[k - 1], b = path[k];
    const double len = (b - a).norm();
    if (!(len > 0.0)) continue;  // a repeated vertex
    const auto pieces = static_cast<std::size_t>(std::max(1.0, std::ceil(len / spacing - 1e-9)));
    for (std::size_t s = 1; s <= pieces; ++s)
      out.push_back(s == pieces ? b : Vec2(a + (b - a) * (static_cast<double>(s) / static_cast<double>(pieces))));
  }
  return out;
}

bool segment_clear(const GridSearchMap& map, const GridGeometry& geometry, const Vec2& a, const Vec2& b) {
  return cells_clear(map, geometry.world_to_cell_continuous(a), geometry.world_to_cell_continuous(b));
}

GradientSmoothingResult smooth_path_gradient(std::span<const Vec2> path, const GridSearchMap& map,
                                             const GridGeometry& geometry, const ClearanceField* clearance,
                                             const GradientSmoothingOptions& options) {
  validate_gradient_smoothing(options);
  if (options.min_clearance_m > 0.0 && (clearance == nullptr || clearance->empty()))
    throw Error("needs a clearance field", {}, 0, "smooth_clearance");
  if (clearance && !clearance->empty() &&
      (clearance->geometry().width != geometry.width || clearance->geometry().height != geometry.height))
    throw Error("the clearance field's grid differs from the map's", {}, 0, "clearance");
  if (map.width() != geometry.width || map.height() != geometry.height)
    throw Error("the search map's size differs from the geometry's", {}, 0, "map");

  // Work in continuous cell coordinates: the step, tolerance and energy are then map-independent.
  const double res = geometry.resolution;
  const double spacing = options.spacing_m > 0.0 ? options.spacing_m / res : 1.0;
  std::vector<Vec2> cells;
  cells.reserve(path.size());
  for (const Vec2& w : path) cells.push_back(geometry.world_to_cell_continuous(w));
  const std::vector<Vec2> o = resample_polyline(cells, spacing);
  std::vector<Vec2> p = o;
  const double wd = options.weight_data, ws = options.weight_smooth;
  const double tolerance = options.tolerance_m / res;

  // A point's clearance: the least over the cells whose closed square holds it (the same cells
  // the segment test counts), so that rounding cannot pick the kinder cell; -inf off the map.
  auto clearance_at = [&](const Vec2& c) {
    if (!clearance) return std::numeric_limits<double>::infinity();
    double least = std::numeric_limits<double>::infinity();
    const bool on_map = visit_touched_cells(geometry.width, geometry.height, c, c, [&](int x, int y) {
      least = std::min(least, clearance->at(Cell{x, y}));
      return true;
    });
    return on_map ? least : -std::numeric_limits<double>::infinity();
  };
  // What each sample's clearance may not fall below: min(min_clearance, its input's).
  std::vector<double> floor_m(o.size(), 0.0);
  if (options.min_clearance_m > 0.0)
    for (std::size_t i = 0; i < o.size(); ++i) floor_m[i] = std::min(options.min_clearance_m, clearance_at(o[i]));

  GradientSmoothingResult result;
  result.energy_input = energy(o, o, wd, ws);
  const std::size_t n = p.size();
  if (n >= 3) {
    for (int it = 0; it < options.max_iterations; ++it) {
      ++result.iterations;
      double largest = 0.0;
      for (std::size_t i = 1; i + 1 < n; ++i) {
        // The minimiser of E over p_i: w_data pulls to o_i; the curvature terms centred at i-1,
        // i and i+1 pull to 2 p_{i-1} - p_{i-2}, the neighbours' midpoint (weight 4) and
        // 2 p_{i+1} - p_{i+2}; the outer two exist only when i-1 and i+1 are interior.
        Vec2 num = wd * o[i] + ws * 2.0 * (p[i - 1] + p[i + 1]);
        double den = wd + 4.0 * ws;
        if (i >= 2) {
          num += ws * (2.0 * p[i - 1] - p[i - 2]);
          den += ws;
        }
        if (i + 2 < n) {
          num += ws * (2.0 * p[i + 1] - p[i + 2]);
          den += ws;
        }
        const Vec2 target = num / den;
        Vec2 step = target - p[i];
        for (int tries = 0; tries < 4; ++tries, step *= 0.5) {
          const Vec2 candidate = p[i] + step;
          if (step.norm() <= tolerance * 1e-3) break;  // nothing worth trying
          if (options.min_clearance_m > 0.0 && !(clearance_at(candidate) >= floor_m[i])) continue;
          if (!cells_clear(map, p[i - 1], candidate) || !cells_clear(map, candidate, p[i + 1])) continue;
          largest = std::max(largest, step.norm());
          p[i] = candidate;
          break;
        }
      }
      if (largest <= tolerance) break;
    }
  }
  result.energy_output = energy(p, o, wd, ws);
  result.points.reserve(n);
  for (const Vec2& c : p) result.points.push_back(geometry.grid_to_world(c * res));
  // The endpoints exactly as given (no round trip through cell coordinates).
  if (!path.empty() && !result.points.empty()) {
    result.points.front() = path.front();
    result.points.back() = path.back();
  }
  return result;
}

}  // namespace starnav
