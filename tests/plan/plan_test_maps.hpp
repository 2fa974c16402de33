#pragma once
// Random small maps and an independent reference Dijkstra for the planner tests (docs/benchmarks.md).
// Written from scratch here, sharing nothing with src/starnav/plan: a std::priority_queue over an
// adjacency function of its own.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav::plantest {

inline constexpr double kInfDistance = std::numeric_limits<double>::infinity();

// blocked[y * w + x] != 0 for an obstacle.
struct Map {
  int w = 0, h = 0;
  std::vector<std::uint8_t> blocked;

  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h; }
  bool free(int x, int y) const { return inside(x, y) && !blocked[static_cast<std::size_t>(y) * w + x]; }
  void set(int x, int y, bool b) { blocked[static_cast<std::size_t>(y) * w + x] = b ? 1 : 0; }
  int index(int x, int y) const { return y * w + x; }

  OccupancyGrid grid(double resolution = 1.0) const {
    GridGeometry g;
    g.width = w;
    g.height = h;
    g.resolution = resolution;
    OccupancyGrid o(g);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) o(x, y) = free(x, y) ? kFreeOccupancy : kOccupiedOccupancy;
    return o;
  }
};

inline Map random_obstacles(Rng& rng, int w, int h, double density) {
  Map m{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, 0)};
  for (auto& b : m.blocked) b = rng.bernoulli(density) ? 1 : 0;
  return m;
}

// Rooms of `room` cells separated by one-cell walls, each wall between two rooms with one door,
// some doors closed.
inline Map rooms(Rng& rng, int w, int h, int room) {
  Map m{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, 0)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (x % (room + 1) == room || y % (room + 1) == room) m.set(x, y, true);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool vertical_wall = x % (room + 1) == room && y % (room + 1) != room;
      const bool horizontal_wall = y % (room + 1) == room && x % (room + 1) != room;
      if ((vertical_wall && y % (room + 1) == static_cast<int>(rng.uniform_int(0, room - 1))) ||
          (horizontal_wall && x % (room + 1) == static_cast<int>(rng.uniform_int(0, room - 1))))
        if (rng.bernoulli(0.8)) m.set(x, y, false);
    }
  return m;
}

// A perfect maze (recursive backtracker) on odd cells, corridors `corridor` cells wide, with a
// few extra openings so that there are loops.
inline Map maze(Rng& rng, int cells_x, int cells_y, int corridor) {
  const int pitch = corridor + 1;
  Map m{cells_x * pitch + 1, cells_y * pitch + 1, {}};
  m.blocked.assign(static_cast<std::size_t>(m.w) * m.h, 1);
  auto open_cell = [&](int cx, int cy) {
    for (int y = 0; y < corridor; ++y)
      for (int x = 0; x < corridor; ++x) m.set(cx * pitch + 1 + x, cy * pitch + 1 + y, false);
  };
  auto open_between = [&](int cx, int cy, int dx, int dy) {
    for (int k = 0; k < corridor; ++k) {
      if (dx != 0) m.set(cx * pitch + 1 + (dx > 0 ? corridor : -1), cy * pitch + 1 + k, false);
      else m.set(cx * pitch + 1 + k, cy * pitch + 1 + (dy > 0 ? corridor : -1), false);
    }
  };
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(cells_x) * cells_y, 0);
  std::vector<std::pair<int, int>> stack{{0, 0}};
  visited[0] = 1;
  open_cell(0, 0);
  const int dirs[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!stack.empty()) {
    const auto [cx, cy] = stack.back();
    int options[4], n = 0;
    for (int d = 0; d < 4; ++d) {
      const int nx = cx + dirs[d][0], ny = cy + dirs[d][1];
      if (nx >= 0 && ny >= 0 && nx < cells_x && ny < cells_y && !visited[static_cast<std::size_t>(ny) * cells_x + nx])
        options[n++] = d;
    }
    if (n == 0) {
      stack.pop_back();
      continue;
    }
    const int d = options[rng.uniform_int(0, n - 1)];
    const int nx = cx + dirs[d][0], ny = cy + dirs[d][1];
    visited[static_cast<std::size_t>(ny) * cells_x + nx] = 1;
    open_cell(nx, ny);
    open_between(cx, cy, dirs[d][0], dirs[d][1]);
    stack.push_back({nx, ny});
  }
  for (int k = 0; k < cells_x * cells_y / 8; ++k) {
    const int cx = static_cast<int>(rng.uniform_int(0, cells_x - 2)), cy = static_cast<int>(rng.uniform_int(0, cells_y - 1));
    open_between(cx, cy, 1, 0);
  }
  return m;
}

// One of the map kinds above, chosen by `kind` (0..5), about `size` cells across.
inline Map any_map(Rng& rng, int kind, int size) {
  switch (kind % 6) {
    case 0: return random_obstacles(rng, size, size + 3, 0.1);
    case 1: return random_obstacles(rng, size + 5, size, 0.25);
    case 2: return random_obstacles(rng, size, size, 0.4);
    case 3: return rooms(rng, size + 2, size, 3 + static_cast<int>(rng.uniform_int(0, 3)));
    case 4: return maze(rng, size / 3, size / 4 + 1, 1 + static_cast<int>(rng.uniform_int(0, 1)));
    default: return random_obstacles(rng, size, 1 + size / 4, 0.15);  // a thin strip
  }
}

// The moves of the reference graph: (dx, dy, length).
inline void for_each_move(const Map& m, int connectivity, int x, int y, const std::function<void(int, int, double)>& f) {
  static const int card[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  static const int diag[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  if (!m.free(x, y)) return;
  for (const auto& d : card)
    if (m.free(x + d[0], y + d[1])) f(x + d[0], y + d[1], 1.0);
  if (connectivity == 8)
    for (const auto& d : diag)
      if (m.free(x + d[0], y + d[1]) && m.free(x + d[0], y) && m.free(x, y + d[1]))
        f(x + d[0], y + d[1], std::sqrt(2.0));
}

// Shortest distances from (sx, sy) to every cell; `step_cost(to_index, length)` scales moves.
inline std::vector<double> reference_dijkstra(
    const Map& m, int connectivity, int sx, int sy,
    const std::function<double(int, double)>& step_cost = [](int, double len) { return len; }) {
  std::vector<double> dist(static_cast<std::size_t>(m.w) * m.h, kInfDistance);
  if (!m.free(sx, sy)) return dist;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[m.index(sx, sy)] = 0.0;
  queue.push({0.0, m.index(sx, sy)});
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for_each_move(m, connectivity, i % m.w, i / m.w, [&](int nx, int ny, double len) {
      const int j = m.index(nx, ny);
      const double nd = d + step_cost(j, len);
      if (nd < dist[j]) {
        dist[j] = nd;
        queue.push({nd, j});
      }
    });
  }
  return dist;
}

// A random free cell, or (-1, -1) when there is none.
inline Cell random_free_cell(Rng& rng, const Map& m) {
  for (int tries = 0; tries < 200; ++tries) {
    const int x = static_cast<int>(rng.uniform_int(0, m.w - 1)), y = static_cast<int>(rng.uniform_int(0, m.h - 1));
    if (m.free(x, y)) return {x, y};
  }
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x)
      if (m.free(x, y)) return {x, y};
  return {-1, -1};
}

// Exact test (doubled integer coordinates) of whether the segment between the centres of two
// cells touches the closed square of cell (cx, cy): bounding boxes overlap and the square's
// corners are not all strictly on one side of the line.
inline bool segment_touches_cell(Cell a, Cell b, int cx, int cy) {
  const long long ax = 2LL * a.x + 1, ay = 2LL * a.y + 1, bx = 2LL * b.x + 1, by = 2LL * b.y + 1;
  const long long lo_x = 2LL * cx, hi_x = 2LL * cx + 2, lo_y = 2LL * cy, hi_y = 2LL * cy + 2;
  if (std::max(ax, bx) < lo_x || std::min(ax, bx) > hi_x || std::max(ay, by) < lo_y || std::min(ay, by) > hi_y)
    return false;
  int positive = 0, negative = 0;
  const long long corners[4][2] = {{lo_x, lo_y}, {hi_x, lo_y}, {lo_x, hi_y}, {hi_x, hi_y}};
  for (const auto& c : corners) {
    const long long cross = (bx - ax) * (c[1] - ay) - (by - ay) * (c[0] - ax);
    if (cross > 0) ++positive;
    else if (cross < 0) ++negative;
  }
  return !(positive == 4 || negative == 4);
}

// The any-angle rule: every cell whose closed square the segment touches is free.
inline bool segment_free(const Map& m, Cell a, Cell b) {
  for (int y = std::min(a.y, b.y) - 1; y <= std::max(a.y, b.y) + 1; ++y)
    for (int x = std::min(a.x, b.x) - 1; x <= std::max(a.x, b.x) + 1; ++x)
      if (segment_touches_cell(a, b, x, y) && !m.free(x, y)) return false;
  return true;
}

}  // namespace starnav::plantest
