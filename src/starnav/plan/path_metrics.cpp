#include "starnav/plan/path_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

ClearanceField::ClearanceField(const GridGeometry& geometry, std::vector<double> distance)
    : geometry_(geometry), distance_(std::move(distance)) {
  if (distance_.size() != geometry_.cell_count())
    throw Error("clearance field has " + std::to_string(distance_.size()) + " values for " +
                std::to_string(geometry_.cell_count()) + " cells");
}

ClearanceField ClearanceField::of_grid(const OccupancyGrid& grid, const OccupancyThresholds& thresholds,
                                       bool unknown_is_obstacle) {
  return ClearanceField(grid.geometry(), obstacle_distance_m(grid, thresholds, unknown_is_obstacle));
}

double ClearanceField::at(const Vec2& world) const {
  const auto c = geometry_.world_to_cell(world);
  if (!c) return std::numeric_limits<double>::quiet_NaN();
  return distance_[geometry_.index(c->x, c->y)];
}

std::vector<Vec2> cell_centres(std::span<const Cell> cells, const GridGeometry& geometry) {
  std::vector<Vec2> out;
  out.reserve(cells.size());
  for (const Cell& c : cells) out.push_back(geometry.cell_center(c));
  return out;
}

PathMetrics compute_path_metrics(std::span<const Vec2> points, const ClearanceField* clearance) {
  PathMetrics m;
  m.vertices = points.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.clearance_min = nan;
  m.clearance_mean = nan;

  // Length and heading changes.
  bool have_heading = false;
  double heading = 0.0, squared_turns = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const Vec2 d = points[i] - points[i - 1];
    const double len = d.norm();
    m.length += len;
    if (len == 0.0) continue;
    const double h = std::atan2(d.y(), d.x());
    if (have_heading) {
      const double turn = std::abs(angle_diff(h, heading));
      if (turn > kTurnEpsilonRad) {
        ++m.turning_points;
        m.turn_total_rad += turn;
        m.turn_max_rad = std::max(m.turn_max_rad, turn);
        squared_turns += turn * turn;
      }
    }
    heading = h;
    have_heading = true;
  }
  m.smoothness = m.length > 0.0 ? squared_turns / m.length : 0.0;

  // Clearance: samples every resolution / 4 of arc length, and the last point.
  if (clearance && !clearance->empty() && !points.empty()) {
    const double spacing = clearance->geometry().resolution / 4.0;
    double sum = 0.0, lo = std::numeric_limits<double>::infinity();
    std::size_t count = 0;
    auto sample = [&](const Vec2& p) {
      const double c = clearance->at(p);
      if (std::isnan(c)) return;
      lo = std::min(lo, c);
      sum += c;
      ++count;
    };
    double done = 0.0;    // arc length up to the start of the current segment
    std::uint64_t k = 0;  // next sample at k * spacing
    for (std::size_t i = 1; i < points.size(); ++i) {
      const Vec2 d = points[i] - points[i - 1];
      const double len = d.norm();
      for (;; ++k) {
        const double s = static_cast<double>(k) * spacing;
        if (s >= done + len) break;
        sample(points[i - 1] + d * ((s - done) / len));
      }
      done += len;
    }
    sample(points.back());
    if (count > 0) {
      m.clearance_min = lo;
      m.clearance_mean = std::isinf(lo) ? lo : sum / static_cast<double>(count);
    }
  }
  return m;
}

}  // namespace starnav
