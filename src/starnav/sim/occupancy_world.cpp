#include "starnav/sim/occupancy_world.hpp"

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "starnav/core/error.hpp"

namespace starnav {

Obstacle occupancy_walls(const OccupancyGrid& grid, double occupied_percent, double wall_height_m, const std::string& name) {
  if (!(std::isfinite(wall_height_m) && wall_height_m > 0)) throw Error("must be > 0", {}, 0, "wall_height_m");
  struct Rect {
    int x0, x1, y0, y1;  // cells [x0, x1) x [y0, y1)
  };
  std::vector<Rect> done;
  std::map<std::pair<int, int>, Rect> open;  // rectangles still growing, by their column span
  for (int y = 0; y < grid.height(); ++y) {
    std::map<std::pair<int, int>, Rect> next;
    for (int x = 0; x < grid.width();) {
      if (grid(x, y) < 0 || grid(x, y) < occupied_percent) {
        ++x;
        continue;
      }
      int end = x;
      while (end < grid.width() && grid(end, y) >= 0 && grid(end, y) >= occupied_percent) ++end;
      const std::pair<int, int> span{x, end};
      const auto it = open.find(span);
      if (it != open.end()) {
        Rect r = it->second;
        r.y1 = y + 1;
        next.emplace(span, r);
        open.erase(it);
      } else {
        next.emplace(span, Rect{x, end, y, y + 1});
      }
      x = end;
    }
    for (const auto& [span, r] : open) done.push_back(r);
    open.swap(next);
    if (done.size() + open.size() > kMaxOccupancyWallBoxes)
      throw Error("the map's occupied cells make more than " + std::to_string(kMaxOccupancyWallBoxes) + " wall boxes", {}, 0, "occupancy_map");
  }
  for (const auto& [span, r] : open) done.push_back(r);
  Obstacle o;
  o.name = name;
  const double res = grid.resolution();
  const Pose2& origin = grid.origin();
  for (const Rect& r : done) {
    const Vec2 local(0.5 * (r.x0 + r.x1) * res, 0.5 * (r.y0 + r.y1) * res);
    const Vec2 c = origin.transform(local);
    Box b;
    b.center = Vec3(c.x(), c.y(), 0.5 * wall_height_m);
    b.size = Vec3((r.x1 - r.x0) * res, (r.y1 - r.y0) * res, wall_height_m);
    b.yaw = origin.yaw;
    o.parts.push_back(b);
  }
  return o;
}

}  // namespace starnav
