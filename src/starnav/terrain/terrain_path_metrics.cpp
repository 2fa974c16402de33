#include "starnav/terrain/terrain_path_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

bool terrain_height_at(const TerrainAnalysis& t, const Vec2& world, double& z) {
  const GridGeometry& g = t.geometry();
  const Vec2 c = g.world_to_cell_continuous(world);
  // Cell centres sit at integer + 0.5; shift so that they sit at integers.
  const double cx = std::clamp(c.x() - 0.5, 0.0, static_cast<double>(g.width - 1));
  const double cy = std::clamp(c.y() - 0.5, 0.0, static_cast<double>(g.height - 1));
  if (!std::isfinite(cx) || !std::isfinite(cy)) return false;
  const int x0 = static_cast<int>(std::floor(cx)), y0 = static_cast<int>(std::floor(cy));
  const int x1 = std::min(x0 + 1, g.width - 1), y1 = std::min(y0 + 1, g.height - 1);
  const double fx = cx - x0, fy = cy - y0;
  const int xs[4] = {x0, x1, x0, x1};
  const int ys[4] = {y0, y0, y1, y1};
  const double ws[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  double sum = 0.0, wsum = 0.0;
  bool any = false;
  for (int i = 0; i < 4; ++i) {
    if (!t.observed(xs[i], ys[i])) continue;
    any = true;
    sum += ws[i] * t.z(xs[i], ys[i]);
    wsum += ws[i];
  }
  if (!any) return false;
  if (wsum > 0.0) {
    z = sum / wsum;
  } else {
    // Only observed corners with weight 0 (the point sits on the far side): take their mean.
    double s = 0.0;
    int n = 0;
    for (int i = 0; i < 4; ++i)
      if (t.observed(xs[i], ys[i])) s += t.z(xs[i], ys[i]), ++n;
    z = s / n;
  }
  return true;
}

Attitude footprint_attitude(const TerrainAnalysis& t, const Vec2& centre, double heading, const Footprint& fp) {
  Attitude att;
  const Vec2 f(std::cos(heading), std::sin(heading));
  const Vec2 l(-f.y(), f.x());
  const double hl = 0.5 * fp.length_m, hw = 0.5 * fp.width_m;
  double z_fl, z_fr, z_rl, z_rr;
  if (!terrain_height_at(t, centre + hl * f + hw * l, z_fl) || !terrain_height_at(t, centre + hl * f - hw * l, z_fr) ||
      !terrain_height_at(t, centre - hl * f + hw * l, z_rl) || !terrain_height_at(t, centre - hl * f - hw * l, z_rr))
    return att;
  const Vec3 corners[4] = {Vec3(hl, hw, z_fl), Vec3(hl, -hw, z_fr), Vec3(-hl, hw, z_rl), Vec3(-hl, -hw, z_rr)};
  const PlaneFit plane = fit_plane(corners);
  return plane.valid ? attitude_from_slopes(plane.px, plane.py) : att;
}

TerrainPathMetrics terrain_path_metrics(const TerrainAnalysis& t, const std::vector<Cell>& path, const Footprint& fp,
                                        std::vector<AttitudeSample>* samples) {
  if (!(fp.length_m > 0.0) || !(fp.width_m > 0.0) || !std::isfinite(fp.length_m) || !std::isfinite(fp.width_m))
    throw Error("footprint length and width must be finite and > 0", {}, 0, "footprint");
  TerrainPathMetrics m;
  m.nodes = path.size();
  if (samples) samples->clear();
  if (path.empty()) return m;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (!t.contains(path[i].x, path[i].y))
      throw Error("path cell " + std::to_string(i) + " (" + std::to_string(path[i].x) + ", " +
                      std::to_string(path[i].y) + ") outside the map",
                  {}, 0, "path");
    if (i > 0 && (std::abs(path[i].x - path[i - 1].x) > 1 || std::abs(path[i].y - path[i - 1].y) > 1))
      throw Error("path cells " + std::to_string(i - 1) + " and " + std::to_string(i) + " are not neighbours", {}, 0,
                  "path");
  }
  double a_sum = 0.0, h_sum = 0.0, s_sum = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Cell c = path[i];
    if (t.observed(c.x, c.y)) {
      s_sum += t.ruggedness(c.x, c.y);
      ++m.cells_measured;
    }
    if (i == 0) continue;
    const Cell p = path[i - 1];
    const int k = move_index(c.x - p.x, c.y - p.y);
    if (k < 0) continue;  // a repeated cell: no move
    ++m.moves;
    const MoveTerrain mv = t.move(p.x, p.y, k);
    m.length_2d_m += mv.length;
    if (mv.known) {
      m.lv_m += std::hypot(mv.length, mv.h);
      a_sum += mv.a;
      h_sum += mv.h;
      ++m.moves_measured;
    } else {
      m.lv_m += mv.length;
    }
  }
  if (m.moves_measured > 0) {
    m.av_rad = a_sum / static_cast<double>(m.moves_measured);
    m.hv_m = h_sum / static_cast<double>(m.moves_measured);
  }
  if (m.cells_measured > 0) m.sv_m2 = s_sum / static_cast<double>(m.cells_measured);

  // Attitude along the path.
  const GridGeometry& g = t.geometry();
  double roll_sum = 0.0, pitch_sum = 0.0, tilt_sum = 0.0, roll_abs = 0.0, pitch_abs = 0.0;
  double roll_max = 0.0, pitch_max = 0.0, tilt_max = 0.0, s_along = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Vec2 here = g.cell_center(path[i]);
    const Vec2 prev = g.cell_center(path[i > 0 ? i - 1 : i]);
    const Vec2 next = g.cell_center(path[i + 1 < path.size() ? i + 1 : i]);
    if (i > 0) s_along += (here - prev).norm();
    Vec2 dir = next - prev;
    double heading = 0.0;
    if (dir.squaredNorm() > 0.0) heading = std::atan2(dir.y(), dir.x());
    const Attitude att = footprint_attitude(t, here, heading, fp);
    if (samples) samples->push_back({s_along, here, heading, att});
    if (!att.valid) continue;
    ++m.attitude_nodes;
    roll_sum += att.roll;
    pitch_sum += att.pitch;
    tilt_sum += att.tilt;
    roll_abs += std::abs(att.roll);
    pitch_abs += std::abs(att.pitch);
    roll_max = std::max(roll_max, std::abs(att.roll));
    pitch_max = std::max(pitch_max, std::abs(att.pitch));
    tilt_max = std::max(tilt_max, att.tilt);
  }
  if (m.attitude_nodes > 0) {
    const double n = static_cast<double>(m.attitude_nodes);
    m.roll_mean_deg = rad_to_deg(std::abs(roll_sum / n));
    m.pitch_mean_deg = rad_to_deg(std::abs(pitch_sum / n));
    m.tilt_mean_deg = rad_to_deg(tilt_sum / n);
    m.roll_mean_abs_deg = rad_to_deg(roll_abs / n);
    m.pitch_mean_abs_deg = rad_to_deg(pitch_abs / n);
    m.roll_max_deg = rad_to_deg(roll_max);
    m.pitch_max_deg = rad_to_deg(pitch_max);
    m.tilt_max_deg = rad_to_deg(tilt_max);
  }
  return m;
}

}  // namespace starnav
