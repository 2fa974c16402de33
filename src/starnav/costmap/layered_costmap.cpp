#include "starnav/costmap/layered_costmap.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {
constexpr std::uint32_t kNoParent = std::numeric_limits<std::uint32_t>::max();
}

LayeredCostmap::LayeredCostmap(const GridGeometry& geometry, const NodeMapParams& params,
                               std::vector<std::unique_ptr<CostmapLayer>> layers)
    : geometry_(geometry), params_(params), layers_(std::move(layers)) {
  validate_geometry(geometry_, "geometry");
  if (geometry_.y_down) throw Error("a navigation map must be metric (y up)", {}, 0, "geometry");
  params_.validate();
  for (const auto& l : layers_)
    if (!l) throw Error("a costmap layer is missing", {}, 0, "navigation.layers");
  const std::size_t n = geometry_.cell_count();
  obstacles_.assign(n, 0);
  observed_.assign(n, 0);
  occupancy_ = OccupancyGrid(geometry_, kUnknownOccupancy);
  raw_occupancy_ = OccupancyGrid(geometry_, kUnknownOccupancy);
  clearance_ = std::make_unique<ObstacleDistanceField>(geometry_, &obstacles_, params_.clearance_range_m);
  rebuild();
}

LayeredCostmap::LayeredCostmap(LayeredCostmap&& other) noexcept
    : geometry_(other.geometry_),
      params_(other.params_),
      layers_(std::move(other.layers_)),
      obstacles_(std::move(other.obstacles_)),
      observed_(std::move(other.observed_)),
      blocked_(std::move(other.blocked_)),
      occupancy_(std::move(other.occupancy_)),
      raw_occupancy_(std::move(other.raw_occupancy_)),
      inflation_(std::move(other.inflation_)),
      clearance_(std::move(other.clearance_)) {
  if (clearance_) clearance_->rebind(&obstacles_);
}

LayeredCostmap& LayeredCostmap::operator=(LayeredCostmap&& other) noexcept {
  geometry_ = other.geometry_;
  params_ = other.params_;
  layers_ = std::move(other.layers_);
  obstacles_ = std::move(other.obstacles_);
  observed_ = std::move(other.observed_);
  blocked_ = std::move(other.blocked_);
  occupancy_ = std::move(other.occupancy_);
  raw_occupancy_ = std::move(other.raw_occupancy_);
  inflation_ = std::move(other.inflation_);
  clearance_ = std::move(other.clearance_);
  if (clearance_) clearance_->rebind(&obstacles_);
  return *this;
}

LayeredCostmap::~LayeredCostmap() = default;

const ElevationMap* LayeredCostmap::heights() const {
  for (const auto& l : layers_)
    if (const ElevationMap* h = l->heights()) return h;
  return nullptr;
}

const ObstacleDistanceField& LayeredCostmap::clearance() const { return *clearance_; }

std::optional<double> LayeredCostmap::speed_limit_mps(std::span<const Vec2> area) const {
  std::optional<double> lowest;
  for (const auto& l : layers_)
    if (const std::optional<double> limit = l->speed_limit_mps(area); limit && (!lowest || *limit < *lowest)) lowest = limit;
  return lowest;
}

void LayeredCostmap::recompose(const CellRect& rect) {
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      obstacles_[i] = 0;
      observed_[i] = 0;
    }
  for (const auto& l : layers_) l->contribute(rect, obstacles_, observed_);
}

void LayeredCostmap::rebuild() {
  for (const auto& l : layers_) l->recompute();
  const CellRect all{0, 0, geometry_.width, geometry_.height};
  recompose(all);
  blocked_ = inflate_mask(obstacles_, geometry_.width, geometry_.height,
                          inflation_radius_cells(params_.barrier_distance_m, geometry_.resolution));
  for (std::size_t i = 0; i < geometry_.cell_count(); ++i) {
    occupancy_.data()[i] = occupancy_value(i);
    raw_occupancy_.data()[i] = raw_occupancy_value(i);
  }
  clearance_->mark_changed(all);
}

std::int8_t LayeredCostmap::raw_occupancy_value(std::size_t i) const {
  if (obstacles_[i]) return kOccupiedOccupancy;
  return observed_[i] ? kFreeOccupancy : kUnknownOccupancy;
}

std::int8_t LayeredCostmap::occupancy_value(std::size_t i) const {
  if (blocked_[i]) return kOccupiedOccupancy;
  return observed_[i] ? kFreeOccupancy : kUnknownOccupancy;
}

CostmapUpdate LayeredCostmap::integrate(const LidarScan& scan, double no_return_clear_m) {
  if (!std::isfinite(no_return_clear_m) || no_return_clear_m < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "no_return_clear_m");
  if (!(no_return_clear_m > 0.0)) return integrate(scan.sensor_pose.position, scan.points_world);
  pass_ends_.clear();
  const Eigen::Matrix3d r = scan.sensor_pose.rotation();
  for (int j = 0; j < scan.lines; ++j)
    for (int b = 0; b < scan.beams; ++b) {
      if (std::isfinite(scan.range(j, b))) continue;
      const double phi = scan.elevations[static_cast<std::size_t>(j)], theta = scan.azimuths[static_cast<std::size_t>(b)];
      const Vec3 dir(std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta), std::sin(phi));
      pass_ends_.push_back(scan.sensor_pose.position + no_return_clear_m * (r * dir));
    }
  return integrate(scan.sensor_pose.position, scan.points_world, pass_ends_);
}

CostmapUpdate LayeredCostmap::integrate(const Vec3& origin, std::span<const Vec3> points, std::span<const Vec3> pass_ends) {
  CostmapUpdate update;
  CostmapScanStats stats;
  changed_.clear();
  const CostmapScan scan{origin, points, pass_ends};
  for (const auto& l : layers_) l->on_scan(scan, changed_, stats);
  update.returns_used = stats.returns_used;
  update.cells_hit = stats.cells_hit;
  update.cells_contradicted = stats.cells_contradicted;
  update.cells_cleared = stats.cells_cleared;
  update.cells_changed = stats.cells_changed;
  // Every rectangle's master cells first, so that the expansions read final obstacles; then the
  // expansions; then the view differences (no transient values are reported).
  // The obstacle cells before, so that the distance field hears of the cells that flipped only
  // (most of a scan's changes are evidence and heights, not obstacles).
  before_.clear();
  for (const CellRect& r : changed_)
    for (int y = r.y0; y < r.y1; ++y)
      before_.insert(before_.end(), obstacles_.begin() + static_cast<std::ptrdiff_t>(geometry_.index(r.x0, y)),
                     obstacles_.begin() + static_cast<std::ptrdiff_t>(geometry_.index(r.x1 - 1, y)) + 1);
  for (const CellRect& r : changed_) recompose(r);
  std::size_t k = 0;
  for (const CellRect& r : changed_) {
    CellRect flipped{r.x1, r.y1, r.x0, r.y0};
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x, ++k)
        if ((before_[k] != 0) != (obstacles_[geometry_.index(x, y)] != 0))
          flipped = {std::min(flipped.x0, x), std::min(flipped.y0, y), std::max(flipped.x1, x + 1), std::max(flipped.y1, y + 1)};
    clearance_->mark_changed(flipped);
  }
  for (const CellRect& r : changed_)
    inflation_.update(obstacles_, geometry_.width, geometry_.height,
                      inflation_radius_cells(params_.barrier_distance_m, geometry_.resolution), r, blocked_);
  for (const CellRect& r : changed_) refresh_views(r, update);
  std::sort(update.occupancy_changed.begin(), update.occupancy_changed.end(),
            [&](const Cell& a, const Cell& b) { return geometry_.index(a.x, a.y) < geometry_.index(b.x, b.y); });
  return update;
}

void LayeredCostmap::refresh_views(const CellRect& obstacles_changed, CostmapUpdate& update) {
  const double rc = inflation_radius_cells(params_.barrier_distance_m, geometry_.resolution);
  const CellRect region = obstacles_changed.grown(inflation_margin_cells(rc), geometry_.width, geometry_.height);
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      raw_occupancy_.data()[i] = raw_occupancy_value(i);
      const std::int8_t v = occupancy_value(i);
      if (occupancy_.data()[i] == v) continue;
      occupancy_.data()[i] = v;
      update.occupancy_changed.push_back({x, y});
      CellRect& b = update.bounds;
      if (b.empty()) b = {x, y, x + 1, y + 1};
      else b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x + 1), std::max(b.y1, y + 1)};
    }
}

std::optional<Cell> LayeredCostmap::escape_cell(Cell start, std::vector<Cell>* path) const {
  if (path) path->clear();
  if (!geometry_.contains(start)) return std::nullopt;
  const std::vector<std::uint8_t>& raw = obstacles_;
  const std::size_t s = geometry_.index(start.x, start.y);
  if (raw[s]) return std::nullopt;
  if (!blocked_[s]) {
    if (path) path->push_back(start);
    return start;
  }
  // Dijkstra from start through cells that are not obstacles; the first settled cell outside the
  // band is the cheapest way out (ties: lower cost first, then lower index).
  const std::size_t n = geometry_.cell_count();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(n, kInf);
  std::vector<std::uint32_t> parent(n, kNoParent);
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  dist[s] = 0.0;
  open.push({0.0, static_cast<std::uint32_t>(s)});
  const double diag = std::sqrt(2.0);
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > dist[u]) continue;
    if (!blocked_[u]) {
      const Cell out = geometry_.cell_of_index(u);
      if (path) {
        for (std::uint32_t v = u; v != kNoParent; v = parent[v]) path->push_back(geometry_.cell_of_index(v));
        std::reverse(path->begin(), path->end());
      }
      return out;
    }
    const Cell c = geometry_.cell_of_index(u);
    for (int k = 0; k < kMoveCount; ++k) {
      const int nx = c.x + kMoveDx[k], ny = c.y + kMoveDy[k];
      if (!geometry_.contains(nx, ny) || raw[geometry_.index(nx, ny)]) continue;
      if (move_is_diagonal(k) && (raw[geometry_.index(c.x + kMoveDx[k], c.y)] || raw[geometry_.index(c.x, c.y + kMoveDy[k])]))
        continue;  // no corner cutting past an obstacle
      const std::uint32_t v = static_cast<std::uint32_t>(geometry_.index(nx, ny));
      const double nd = d + (move_is_diagonal(k) ? diag : 1.0);
      if (nd < dist[v]) {
        dist[v] = nd;
        parent[v] = u;
        open.push({nd, v});
      }
    }
  }
  return std::nullopt;
}

}  // namespace starnav
