#include "starnav/harness/local_planning_pictures.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

OccupancyGrid crop_map(const OccupancyGrid& map, const Vec2& centre, double side_m) {
  const GridGeometry& g = map.geometry();
  const int n = std::max(1, static_cast<int>(std::ceil(side_m / g.resolution)));
  const Vec2 c = g.world_to_cell_continuous(centre);
  const int x0 = static_cast<int>(std::floor(c.x())) - n / 2, y0 = static_cast<int>(std::floor(c.y())) - n / 2;
  GridGeometry w;
  w.resolution = g.resolution;
  w.width = n;
  w.height = n;
  const Vec2 corner = g.grid_to_world({x0 * g.resolution, y0 * g.resolution});
  w.origin = Pose2(corner.x(), corner.y(), g.origin.yaw);
  OccupancyGrid out(w, kUnknownOccupancy);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (map.contains(x0 + x, y0 + y)) out(x, y) = map(x0 + x, y0 + y);
  return out;
}

viz::MapPicture controller_step_picture(const ControllerSnapshot& s, const std::string& title) {
  viz::PictureOptions opts;
  opts.title = title;
  viz::MapPicture pic(s.local_map, opts);
  if (s.path.size() >= 2) pic.add_polyline(s.path, {{0, 0, 0, 255}, 1.2, 0.7, true}, "path");
  // Costs of the valid candidates, for shading (cheap dark blue, dear light).
  double lo = 1e300, hi = -1e300;
  for (const ControlCandidate& x : s.step.candidates)
    if (x.status == CandidateStatus::Valid) {
      lo = std::min(lo, x.cost);
      hi = std::max(hi, x.cost);
    }
  const auto line_of = [&](const ControlCandidate& x) {
    std::vector<Vec2> line{s.step.pose.translation()};
    for (const Pose2& p : x.trajectory) line.push_back(p.translation());
    return line;
  };
  bool first_valid = true, first_collides = true;
  for (const ControlCandidate& x : s.step.candidates) {
    if (x.status == CandidateStatus::Rejected) continue;  // infeasible or refused by a critic: not drawn
    if (x.status == CandidateStatus::Collides) {
      pic.add_polyline(line_of(x), {{213, 94, 0, 255}, 0.6, 0.35, false}, first_collides ? "collides" : "");
      first_collides = false;
    } else {
      const double f = hi > lo ? (x.cost - lo) / (hi - lo) : 0.0;
      const auto shade = static_cast<std::uint8_t>(40 + 180 * f);
      pic.add_polyline(line_of(x), {{shade, shade, 255, 255}, 0.7, 0.6, false}, first_valid ? "valid (darker: cheaper)" : "");
      first_valid = false;
    }
  }
  const BodyTwist& u = s.step.command;
  const std::string command = "(" + format_fixed(u.vx, 2) + ", " + format_fixed(u.vy, 2) + ", " + format_fixed(u.wz, 2) + ")";
  if (s.step.chosen >= 0 && static_cast<std::size_t>(s.step.chosen) < s.step.candidates.size())
    pic.add_polyline(line_of(s.step.candidates[static_cast<std::size_t>(s.step.chosen)]), {{0, 158, 115, 255}, 3.0, 1.0, false},
                     "chosen " + command);
  // The body's outline at the step's pose.
  const double hl = 0.5 * s.footprint.length_m, hw = 0.5 * s.footprint.width_m;
  std::vector<Vec2> outline;
  for (const Vec2& k : {Vec2(hl, hw), Vec2(-hl, hw), Vec2(-hl, -hw), Vec2(hl, -hw), Vec2(hl, hw)})
    outline.push_back(s.step.pose.transform(k));
  pic.add_polyline(std::move(outline), {{0, 0, 0, 255}, 1.6, 1.0, false},
                   s.step.chosen >= 0 ? "robot" : "robot, command " + command);
  // The controller's own points, one colour each (Okabe-Ito).
  static const viz::Rgba kColours[] = {{230, 159, 0, 255}, {86, 180, 233, 255}, {204, 121, 167, 255}, {240, 228, 66, 255}};
  std::size_t k = 0;
  for (const auto& [name, point] : s.step.points)
    pic.add_points({point}, {kColours[k++ % 4], 5.0, {0, 0, 0, 255}, 1.0, 1.0}, name);
  return pic;
}

viz::LinePlot speed_profile_plot(const std::vector<TrajectorySample>& trajectory, const std::string& title) {
  viz::PlotOptions o;
  o.title = title;
  o.x_label = "t (s)";
  o.y_label = "vx, vy (m/s); wz (rad/s)";
  viz::LinePlot plot(o);
  std::vector<Vec2> vx, vy, wz;
  for (const TrajectorySample& s : trajectory) {
    vx.emplace_back(s.t_s, s.twist.vx);
    vy.emplace_back(s.t_s, s.twist.vy);
    wz.emplace_back(s.t_s, s.twist.wz);
  }
  plot.add_series(std::move(vx), {{0, 114, 178, 255}, 1.6, false, false}, "vx");
  plot.add_series(std::move(vy), {{0, 158, 115, 255}, 1.6, false, false}, "vy");
  plot.add_series(std::move(wz), {{213, 94, 0, 255}, 1.2, false, false}, "wz");
  return plot;
}

}  // namespace starnav
