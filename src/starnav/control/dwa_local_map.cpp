#include "starnav/control/dwa_local_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace starnav {

namespace {
constexpr double kUnreached = std::numeric_limits<double>::infinity();
}

void DwaLocalMap::build(const OccupancyGrid& map, const Vec2& centre, double half_m, double pad_m,
                        const OccupancyThresholds& thresholds) {
  const GridGeometry& g = map.geometry();
  const double res = g.resolution;
  const Vec2 c = g.world_to_cell_continuous(centre);
  const int half = static_cast<int>(std::ceil(half_m / res));
  pad_ = static_cast<int>(std::ceil(pad_m / res)) + 1;
  const int ix0 = static_cast<int>(std::floor(c.x())) - half;
  const int iy0 = static_cast<int>(std::floor(c.y())) - half;
  geometry_ = GridGeometry{};
  geometry_.resolution = res;
  geometry_.width = 2 * half + 1;
  geometry_.height = 2 * half + 1;
  const Vec2 corner = g.grid_to_world({ix0 * res, iy0 * res});
  geometry_.origin = Pose2(corner.x(), corner.y(), g.origin.yaw);
  cos_ = std::cos(g.origin.yaw);
  sin_ = std::sin(g.origin.yaw);
  inv_resolution_ = 1.0 / res;
  padded_width_ = geometry_.width + 2 * pad_;
  padded_height_ = geometry_.height + 2 * pad_;

  mask_.assign(static_cast<std::size_t>(padded_width_) * static_cast<std::size_t>(padded_height_), 0);
  const std::span<const std::int8_t> data = map.data();
  for (int py = 0; py < padded_height_; ++py) {
    const int my = iy0 - pad_ + py;
    std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    if (my < 0 || my >= g.height) {
      std::fill(row, row + padded_width_, std::uint8_t{1});
      continue;
    }
    for (int px = 0; px < padded_width_; ++px) {
      const int mx = ix0 - pad_ + px;
      row[px] = (mx < 0 || mx >= g.width || thresholds.classify(data[g.index(mx, my)]) == CellState::Occupied) ? 1 : 0;
    }
  }
  row_columns_.clear();
  row_start_.assign(static_cast<std::size_t>(padded_height_) + 1, 0);
  for (int py = 0; py < padded_height_; ++py) {
    const std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    for (int px = 0; px < padded_width_; ++px)
      if (row[px]) row_columns_.push_back(px);
    row_start_[static_cast<std::size_t>(py) + 1] = row_columns_.size();
  }
  transform_.compute(mask_, padded_width_, padded_height_, true);
  const std::vector<double>& sq = transform_.squared_cells();
  const std::vector<std::int32_t>& near = transform_.nearest();
  clearance_.resize(geometry_.cell_count());
  nearest_.resize(geometry_.cell_count());
  for (int y = 0; y < geometry_.height; ++y)
    for (int x = 0; x < geometry_.width; ++x) {
      const std::size_t i = geometry_.index(x, y);
      const std::size_t j = padded_index(x, y);
      clearance_[i] = std::sqrt(sq[j]) * res;
      nearest_[i] = near[j];
    }
}

Vec2 DwaLocalMap::nearest_obstacle(std::size_t i) const {
  const std::int32_t j = nearest_[i];
  const int px = j % padded_width_, py = j / padded_width_;
  return cell_center(px - pad_, py - pad_);
}

void DwaLocalMap::wavefront(std::span<const Cell> seeds, double pass_clearance_m, std::vector<double>& out) const {
  out.assign(geometry_.cell_count(), kUnreached);
  using Entry = std::pair<double, std::int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (const Cell& s : seeds) {
    if (!contains(s.x, s.y)) continue;
    const std::size_t i = index(s.x, s.y);
    if (out[i] > 0.0) {
      out[i] = 0.0;
      open.emplace(0.0, static_cast<std::int32_t>(i));
    }
  }
  const double res = geometry_.resolution;
  const double diag = res * std::sqrt(2.0);
  const int w = geometry_.width, h = geometry_.height;
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > out[static_cast<std::size_t>(i)]) continue;
    const int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const std::size_t n = index(nx, ny);
        if (!(clearance_[n] > 0.0 && clearance_[n] >= pass_clearance_m)) continue;  // obstacles never pass
        const double nd = d + (dx != 0 && dy != 0 ? diag : res);
        if (nd < out[n]) {
          out[n] = nd;
          open.emplace(nd, static_cast<std::int32_t>(n));
        }
      }
  }
}

double FootprintModel::bounding_radius_m() const {
  return circle ? radius_m : std::hypot(half_length_m, half_width_m);
}

double FootprintModel::inscribed_radius_m() const {
  return circle ? radius_m : std::min(half_length_m, half_width_m);
}

FootprintChecker::FootprintChecker(const FootprintModel& model, double grow_m)
    : model_(model), grow_m_(grow_m), bounding_m_(model.bounding_radius_m()) {
  if (model_.circle) {
    cover_ = {Vec2::Zero()};
    cover_radius_m_ = model_.radius_m;
    return;
  }
  // k discs centred along the long axis at the middles of k equal slices of the rectangle; more
  // discs hug it closer but cost a lookup each (three for a near-square body).
  const bool along_x = model_.half_length_m >= model_.half_width_m;
  const double hl = along_x ? model_.half_length_m : model_.half_width_m;
  const double hw = along_x ? model_.half_width_m : model_.half_length_m;
  const int k = std::clamp(static_cast<int>(std::ceil(hl / hw)) + 1, 1, 8);
  const double slice = 2.0 * hl / k;
  for (int i = 0; i < k; ++i) {
    const double a = -hl + slice * (i + 0.5);
    cover_.push_back(along_x ? Vec2(a, 0.0) : Vec2(0.0, a));
  }
  cover_radius_m_ = std::hypot(0.5 * slice, hw);
}

FootprintTest FootprintChecker::quick_test(const DwaLocalMap& map, const Pose2& pose, const Vec2& heading,
                                           double extra_m) const {
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  // Every obstacle centre lies at least d - |q - c| from a point q whose cell (centre c) has
  // clearance d: clear when that exceeds `radius`.
  const auto clear_within = [&](const Vec2& q, std::size_t i, const Cell& cell, double radius) {
    const double d = map.clearance_m(i);
    if (!std::isfinite(d)) return true;
    const double room = d - radius;
    return room > 0.0 && (q - map.cell_center(cell.x, cell.y)).squaredNorm() < room * room;
  };
  const Cell centre = map.cell_of(pose.translation());
  if (!map.contains(centre.x, centre.y)) return FootprintTest::Collides;
  // One lookup settles open space.
  if (clear_within(pose.translation(), map.index(centre.x, centre.y), centre, bounding_m_ + grow))
    return FootprintTest::Clear;
  const double c = heading.x(), s = heading.y();
  bool clear = true;
  for (const Vec2& o : cover_) {
    const Vec2 q(pose.x + c * o.x() - s * o.y(), pose.y + s * o.x() + c * o.y());
    const Cell cell = map.cell_of(q);
    if (!map.contains(cell.x, cell.y)) {
      clear = false;  // beyond the window's distances: the exact test decides
      continue;
    }
    const std::size_t i = map.index(cell.x, cell.y);
    if (clear_within(q, i, cell, cover_radius_m_ + grow)) continue;
    clear = false;
    if (holds(pose, heading, map.nearest_obstacle(i), grow)) return FootprintTest::Collides;
  }
  return clear ? FootprintTest::Clear : FootprintTest::Unsure;
}

bool FootprintChecker::exact_test(const DwaLocalMap& map, const Pose2& pose, const Vec2& heading, double extra_m) const {
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  bool hit = false;
  map.for_each_obstacle_near(pose.translation(), bounding_m_ + grow,
                             [&](const Vec2& o) { hit = hit || holds(pose, heading, o, grow); });
  return hit;
}

bool FootprintChecker::collides(const DwaLocalMap& map, const Pose2& pose, double extra_m) const {
  const Cell c = map.cell_of(pose.translation());
  if (!map.contains(c.x, c.y)) return true;
  const Vec2 heading(std::cos(pose.yaw), std::sin(pose.yaw));
  switch (quick_test(map, pose, heading, extra_m)) {
    case FootprintTest::Clear: return false;
    case FootprintTest::Collides: return true;
    case FootprintTest::Unsure: break;
  }
  return exact_test(map, pose, heading, extra_m);
}

bool FootprintChecker::collides_brute_force(const DwaLocalMap& map, const Pose2& pose, double extra_m) const {
  const Cell c = map.cell_of(pose.translation());
  if (!map.contains(c.x, c.y)) return true;
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  const Vec2 heading(std::cos(pose.yaw), std::sin(pose.yaw));
  bool hit = false;
  map.for_each_obstacle_near(pose.translation(), 1e9, [&](const Vec2& o) { hit = hit || holds(pose, heading, o, grow); });
  return hit;
}

}  // namespace starnav
