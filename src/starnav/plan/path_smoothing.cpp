#include "starnav/plan/path_smoothing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "starnav/plan/line_of_sight.hpp"

namespace starnav {

namespace {

// Whether the segment between the centres of cells a and b touches the closed square of cell c:
// exact, in doubled integer coordinates (centres odd, cell edges even). Bounding boxes must
// overlap and the square's corners must not all lie strictly on one side of the line.
bool segment_touches_square(Cell a, Cell b, Cell c) {
  const std::int64_t ax = 2 * std::int64_t{a.x} + 1, ay = 2 * std::int64_t{a.y} + 1;
  const std::int64_t bx = 2 * std::int64_t{b.x} + 1, by = 2 * std::int64_t{b.y} + 1;
  const std::int64_t lx = 2 * std::int64_t{c.x}, hx = lx + 2, ly = 2 * std::int64_t{c.y}, hy = ly + 2;
  if (std::max(ax, bx) < lx || std::min(ax, bx) > hx || std::max(ay, by) < ly || std::min(ay, by) > hy) return false;
  int positive = 0, negative = 0;
  for (const auto& [px, py] : {std::array<std::int64_t, 2>{lx, ly}, {hx, ly}, {lx, hy}, {hx, hy}}) {
    const std::int64_t cross = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
    positive += cross > 0;
    negative += cross < 0;
  }
  return positive != 4 && negative != 4;
}

// The shadow of a blocked cell's square seen from an anchor's centre A: the cone between the rays
// from A through the square's two outermost corners (narrower than pi, since A lies outside the
// square), beyond the square's farthest corner. Every ray inside the cone meets the (convex)
// square no farther than that corner, so a segment from A to any point of the region touches the
// square. distance() is a lower bound on how far a point of the region lies from its boundary:
// path vertices closer to that point than this, along the path, are in the region too.
class Shadow {
 public:
  Shadow() = default;
  Shadow(Cell anchor, Cell blocked) : ax_(anchor.x + 0.5), ay_(anchor.y + 0.5) {
    const double cx = blocked.x + 0.5 - ax_, cy = blocked.y + 0.5 - ay_;  // towards the square's centre
    // Corners ordered by their angle from the centre's direction, through its tangent (every
    // corner lies less than 90 degrees off that direction: |c|^2 > (|cx| + |cy|) / 2 for a
    // centre c at least one cell away).
    double lo = 0.0, hi = 0.0;
    for (const auto& [dx, dy] : {std::array<double, 2>{-0.5, -0.5}, {0.5, -0.5}, {-0.5, 0.5}, {0.5, 0.5}}) {
      const double vx = cx + dx, vy = cy + dy;
      const double angle = (cx * vy - cy * vx) / (cx * vx + cy * vy);  // tangent of the angle
      if (angle <= lo) lo = angle, u1x_ = vx, u1y_ = vy;
      if (angle >= hi) hi = angle, u2x_ = vx, u2y_ = vy;
      far_ = std::max(far_, std::sqrt(vx * vx + vy * vy));
    }
    inv1_ = 1.0 / std::sqrt(u1x_ * u1x_ + u1y_ * u1y_);
    inv2_ = 1.0 / std::sqrt(u2x_ * u2x_ + u2y_ * u2y_);
  }
  // Distance from cell c's centre to the region's boundary, or a negative number outside it.
  double distance(Cell c) const {
    const double qx = c.x + 0.5 - ax_, qy = c.y + 0.5 - ay_;
    const double d1 = (u1x_ * qy - u1y_ * qx) * inv1_;  // left of the clockwise-most ray
    const double d2 = (qx * u2y_ - qy * u2x_) * inv2_;  // right of the counter-clockwise-most ray
    const double d = std::min(d1, d2);
    if (!(d > 0.0)) return d;
    return std::min(d, std::sqrt(qx * qx + qy * qy) - far_);
  }

 private:
  double ax_ = 0, ay_ = 0;
  double u1x_ = 0, u1y_ = 0, u2x_ = 0, u2y_ = 0, inv1_ = 0, inv2_ = 0;
  double far_ = 0;
};

}  // namespace

std::vector<Cell> remove_redundant_nodes(const GridSearchMap& map, std::span<const Cell> path) {
  std::vector<Cell> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  const std::size_t last = path.size() - 1;
  // Blocked cells met by recent line tests from the current anchor. A candidate whose segment
  // touches one is refused without walking it (line_of_sight's rule: every cell whose closed
  // square the segment touches must be free); when the candidate lies well inside that cell's
  // shadow, the earlier path vertices within the shadow's margin are refused in one step. Both
  // shortcuts only ever refuse vertices that are not in sight, so the kept vertex is still the
  // farthest one in sight.
  constexpr std::size_t kRemembered = 4;
  constexpr double kMargin = 1e-6;  // floating-point safety on the shadow's distances
  std::array<Cell, kRemembered> blockers{};
  std::array<Shadow, kRemembered> shadows{};
  // Arc length from the first vertex, to find the vertices within a shadow's margin.
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double dx = path[i].x - path[i - 1].x, dy = path[i].y - path[i - 1].y;
    along[i] = along[i - 1] + std::sqrt(dx * dx + dy * dy);
  }
  std::size_t anchor = 0;
  while (anchor < last) {
    const Cell& a = path[anchor];
    std::size_t known = 0;          // blockers[0] is the most recently useful one
    std::size_t next = anchor + 1;  // the next vertex is always in sight
    std::size_t j = last;
    while (j > anchor + 1) {
      std::size_t hit = known;
      for (std::size_t k = 0; k < known; ++k)
        if (segment_touches_square(a, path[j], blockers[k])) {
          hit = k;
          break;
        }
      if (hit == known) {
        std::int64_t blocker = 0;
        if (line_of_sight(map, a.x, a.y, path[j].x, path[j].y, &blocker)) {
          next = j;
          break;
        }
        known = std::min(known + 1, kRemembered);
        hit = known - 1;
        blockers[hit] = map.cell(static_cast<std::uint32_t>(blocker));
        shadows[hit] = Shadow(a, blockers[hit]);
      }
      if (hit != 0) {
        std::rotate(blockers.begin(), blockers.begin() + static_cast<std::ptrdiff_t>(hit),
                    blockers.begin() + static_cast<std::ptrdiff_t>(hit) + 1);
        std::rotate(shadows.begin(), shadows.begin() + static_cast<std::ptrdiff_t>(hit),
                    shadows.begin() + static_cast<std::ptrdiff_t>(hit) + 1);
      }
      // path[j] is hidden; so is every earlier vertex the path reaches within the margin (the
      // path from there to path[j] is shorter than the margin, hence so is the straight line).
      // Vertices are at least one cell apart, so a margin below one cell hides nothing more.
      const double margin = shadows[0].distance(path[j]) - kMargin;
      const double reach = along[j] - margin;
      --j;
      if (margin >= 1.0)
        while (j > anchor + 1 && along[j] > reach) --j;
    }
    out.push_back(path[next]);
    anchor = next;
  }
  return out;
}

}  // namespace starnav
