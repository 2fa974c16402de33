#include "starnav/harness/navigation_pictures.hpp"

#include "starnav/io/file_bytes.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/core/error.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sim/outline.hpp"
#include "starnav/sim/primitives.hpp"

namespace starnav {

namespace {

// More plans than this and the legends list only a summary entry (the labels on the map stay).
constexpr std::size_t kLegendPlans = 12;

const viz::Rgba kBlack{0, 0, 0, 255};
const viz::Rgba kRawBlocked{213, 0, 0, 255};
const viz::Rgba kBand{255, 140, 150, 255};
const viz::Rgba kStart{0, 158, 115, 255};  // bluish green
const viz::Rgba kGoal{213, 94, 0, 255};    // vermillion
const viz::Rgba kStaticObstacle{60, 60, 60, 255};
const viz::Rgba kUnobserved{250, 250, 250, 255};
const viz::Rgba kFootprint{0, 114, 178, 255};  // blue
const viz::Rgba kReversal{240, 228, 66, 255};  // yellow

// Plans take the Okabe-Ito colours without vermillion (the goal; close to the red blocked cells)
// and yellow (unreadable on white), so P_k looks the same in both pictures.
viz::Rgba plan_colour(std::size_t k) {
  static constexpr std::array<std::size_t, 5> kOrder{1, 4, 3, 5, 2};
  return viz::categorical_colour(kOrder[k % kOrder.size()]);
}

std::string plan_name(const NavPlan& p) {
  std::string s = "P";  // built in steps: g++ 12 warns (-Wrestrict, a false positive) on "P" + to_string
  s += std::to_string(p.id);
  return s;
}

std::string plan_legend(const NavigationPictureData& d, std::size_t k, bool with_cause) {
  const NavPlan& p = d.plans[k];
  if (d.plans.size() <= kLegendPlans) return with_cause && !p.cause.empty() ? plan_name(p) + " (" + p.cause + ")" : plan_name(p);
  if (k == 0) return "planned paths P" + std::to_string(p.id) + "..P" + std::to_string(d.plans.back().id);
  return {};
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string title_suffix(const NavigationPictureData& d) {
  std::string s = " (";
  if (!d.status.empty()) s += d.status + ", ";
  return s + "t = " + fixed(d.end_time_s, 1) + " s)";
}

std::vector<Vec2> circle_points(const Vec2& c, double r, int n = 72) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    pts.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
  }
  return pts;
}


// The base picture: observed cells grey, darker the higher their mid height (the paper's scenes
// are light, and coloured paths stay readable on grey; a height ramp would compete with them), or
// one grey in 2D mode where heights are all 0; unobserved cells near white. The two ends of the
// grey scale get (empty) legend entries with their heights.
viz::MapPicture base_picture(const LayeredCostmap& map, viz::PictureOptions opts) {
  constexpr int kLow = 12, kHigh = 60;  // occupancy values: grey 224 .. 102
  opts.plot_background = kUnobserved;
  opts.occupancy.unknown = kUnobserved;
  // Observed by evidence (in 2D mode the elevation layer may stay empty).
  const ElevationMap* e = map.heights();  // 3D nodes; none in 2D mode
  const bool heights = e != nullptr;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  bool any = false;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      if (!map.observed(x, y)) continue;
      any = true;
      if (heights && e->observed_at(x, y)) lo = std::min(lo, e->height_at(x, y)), hi = std::max(hi, e->height_at(x, y));
    }
  const bool shaded = heights && hi - lo > 1e-9;
  OccupancyGrid grey(map.geometry(), kUnknownOccupancy);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      if (!map.observed(x, y)) continue;
      const double t = shaded && e->observed_at(x, y) ? (e->height_at(x, y) - lo) / (hi - lo) : 0.0;
      grey(x, y) = static_cast<std::int8_t>(std::lround(kLow + t * (kHigh - kLow)));
    }
  viz::MapPicture pic(grey, opts);
  const auto grey_of = [&](int v) { return viz::occupancy_colour(static_cast<std::int8_t>(v), opts.occupancy); };
  if (shaded) {
    pic.add_cells({}, grey_of(kLow), 1.0, "observed, lowest (" + fixed(lo, 2) + " m)");
    pic.add_cells({}, grey_of(kHigh), 1.0, "observed, highest (" + fixed(hi, 2) + " m)");
  } else if (any) {
    pic.add_cells({}, grey_of(kLow), 1.0, "observed");
  }
  return pic;
}

// Errors raised while drawing (bad coordinates, too large a picture) name the file too.
template <typename F>
void naming_file(const std::string& path, F&& f) {
  try {
    f();
  } catch (const Error& e) {
    if (e.file().empty()) throw e.with_file(path);
    throw;
  }
}

// The plans' labels, readable however many plans start close together. Plans whose paths start
// within a label's height of each other on the picture share one label naming them all ("P3..P7,
// P12"; dark grey when it names several, else the plan's colour). Each label then takes the first
// free place around its start, nearest first: beside the first leg (where the replan happened),
// then the other directions and farther out, never over another label, the start or the goal,
// or outside the plot; one placed away from its start gets a thin leader line to it. Placement is
// in the SVG's pixels, a deterministic greedy search in plan order.
void add_plan_labels(viz::MapPicture& pic, const NavigationPictureData& d) {
  constexpr double kFontPx = 14.0;
  constexpr double kCharPx = 0.62 * kFontPx;  // a sans-serif digit or capital, with the halo's share
  const viz::PictureLayout L = pic.svg_layout();
  struct Group {
    Vec2 anchor;  // picture pixels: the first plan's start
    Vec2 away;    // unit vector: left of the first plan's first leg, on the picture
    std::vector<std::size_t> plans;
  };
  std::vector<Group> groups;
  for (std::size_t k = 0; k < d.plans.size(); ++k) {
    const NavPlan& p = d.plans[k];
    if (p.points.size() < 2) continue;
    const Vec2 a = L.to_picture(p.points.front());
    const auto near = std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return (g.anchor - a).norm() < kFontPx; });
    if (near != groups.end()) {
      near->plans.push_back(k);
      continue;
    }
    Vec2 leg = L.to_picture(p.points[1]) - a;
    leg = leg.norm() > 0.0 ? Vec2(leg / leg.norm()) : Vec2(1.0, 0.0);
    groups.push_back({a, Vec2(leg.y(), -leg.x()), {k}});  // left of the leg with y pointing down
  }
  struct Box {
    double x0, y0, x1, y1;
    bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  };
  std::vector<Box> taken;
  for (const Vec2& marker : {d.start.translation(), d.goal}) {
    const Vec2 m = L.to_picture(marker);
    taken.push_back({m.x() - 7.0, m.y() - 7.0, m.x() + 7.0, m.y() + 7.0});
  }
  const Box plot{L.plot_x, L.plot_y, L.plot_x + L.plot_w, L.plot_y + L.plot_h};
  for (const Group& g : groups) {
    // The text: the plans' ids, runs of consecutive ones as ranges.
    std::string text;
    for (std::size_t i = 0; i < g.plans.size();) {
      std::size_t j = i;
      while (j + 1 < g.plans.size() && d.plans[g.plans[j + 1]].id == d.plans[g.plans[j]].id + 1) ++j;
      if (!text.empty()) text += ", ";
      text += plan_name(d.plans[g.plans[i]]);
      if (j > i) {
        text += j == i + 1 ? ", " : "..";
        text += plan_name(d.plans[g.plans[j]]);
      }
      i = j + 1;
    }
    const double w = kCharPx * static_cast<double>(text.size()) + 4.0, h = kFontPx + 2.0;
    const auto box_at = [&](const Vec2& c) { return Box{c.x() - w / 2, c.y() - h / 2, c.x() + w / 2, c.y() + h / 2}; };
    const auto fits = [&](const Box& b) {
      return b.x0 >= plot.x0 && b.x1 <= plot.x1 && b.y0 >= plot.y0 && b.y1 <= plot.y1 &&
             std::none_of(taken.begin(), taken.end(), [&](const Box& t) { return t.overlaps(b); });
    };
    // Candidates nearest first: eight directions (from beside the first leg round both ways) on
    // rings that grow until one fits; the first ring keeps the label's edge clear of the start.
    const double first_ring = 0.5 * std::hypot(w, h) + 4.0;
    const double base_angle = std::atan2(g.away.y(), g.away.x());
    std::optional<Vec2> centre;
    double ring = first_ring;
    for (int r = 0; r < 12 && !centre; ++r, ring += h + 2.0) {
      for (const int step : {0, 1, -1, 2, -2, 3, -3, 4}) {
        const double a = base_angle + step * std::numbers::pi / 4;
        const Vec2 c = g.anchor + ring * Vec2(std::cos(a), std::sin(a));
        if (fits(box_at(c))) {
          centre = c;
          break;
        }
      }
    }
    if (!centre) centre = g.anchor + first_ring * g.away;  // no room anywhere near: beside its start, as before
    taken.push_back(box_at(*centre));
    const viz::Rgba colour = g.plans.size() == 1 ? plan_colour(g.plans.front()) : viz::Rgba{64, 64, 64, 255};
    if ((*centre - g.anchor).norm() > first_ring + 1.0) {
      // The leader: from the start to the box's edge.
      const Vec2 to = *centre - g.anchor;
      const double reach = std::min(w / 2 / std::max(std::abs(to.x()), 1e-9), h / 2 / std::max(std::abs(to.y()), 1e-9));
      const Vec2 edge = *centre - std::min(1.0, reach) * to;
      pic.add_polyline({L.to_world(g.anchor), L.to_world(edge)}, {colour, 0.8, 0.8, false});
    }
    // The text's baseline sits a third of the font below the box's centre.
    pic.add_text(L.to_world(*centre + Vec2(0.0, 0.35 * kFontPx)), text, {colour, kFontPx, viz::TextAnchor::Middle, true});
  }
}

}  // namespace

void add_obstacle_outlines(viz::MapPicture& pic, std::span<const Obstacle> obstacles, double end_time_s,
                           const ObstacleOutlineStyle& style) {
  bool labelled_fixed = false, labelled_appearing = false;
  for (const Obstacle& o : obstacles) {
    if (o.appear > end_time_s) continue;  // never there during the run
    const bool dynamic = o.moving() || o.appear > 0.0 || std::isfinite(o.disappear);
    const double t = std::max(o.appear, 0.0);
    const Vec3 offset = o.offset_at(t);
    std::string label;
    if (dynamic && !labelled_appearing) label = style.appearing_label, labelled_appearing = true;
    if (!dynamic && !labelled_fixed) label = style.fixed_label, labelled_fixed = true;
    const viz::LineStyle& line = dynamic ? style.appearing : style.fixed;
    for (const Primitive& part : o.parts) {
      const PrimitiveOutline f = primitive_outline(part, offset);
      if (!f.polygon.empty()) pic.add_polyline(f.polygon, line, label);
      else pic.add_circle(f.centre, f.radius, line, std::nullopt, label);
      label.clear();
    }
    if (o.moving()) {
      std::vector<Vec2> path;
      const double t_end = std::max(t, std::min(o.disappear, end_time_s));
      for (int i = 0; i <= 50; ++i) path.push_back(o.anchor_at(t + (t_end - t) * i / 50.0).head<2>());
      pic.add_polyline(path, style.motion);
    }
  }
}

FootprintTrail footprint_trail(std::span<const TrajectorySample> trajectory, const FootprintModel& body, double spacing_m,
                               double moving_mps) {
  FootprintTrail t;
  const auto outline = [&](const TrajectorySample& s) {
    const Pose2 pose(s.position.x(), s.position.y(), s.rpy.z());
    std::vector<Vec2> pts;
    const auto at = [&](double u, double v) { pts.push_back(pose.transform(Vec2(u, v))); };
    if (body.circle) {
      constexpr int kSides = 24;
      for (int i = 0; i <= kSides; ++i) {
        const double a = 2.0 * std::numbers::pi * i / kSides;
        at(body.center_x_m + body.radius_m * std::cos(a), body.radius_m * std::sin(a));
      }
    } else {
      const double x0 = body.center_x_m - body.half_length_m, x1 = body.center_x_m + body.half_length_m;
      const double w = body.half_width_m;
      at(x0, -w), at(x1, -w), at(x1, w), at(x0, w), at(x0, -w);
    }
    t.outlines.push_back(std::move(pts));
  };
  if (trajectory.empty()) return t;
  outline(trajectory.front());
  double travelled = 0.0;
  int direction = 0;  // +1 forward, -1 reversing, 0 not yet moving
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const TrajectorySample& s = trajectory[i];
    travelled += (s.position.head<2>() - trajectory[i - 1].position.head<2>()).norm();
    const double vx = s.twist.vx;
    const int d = vx > moving_mps ? 1 : vx < -moving_mps ? -1 : 0;
    if (d != 0 && direction != 0 && d != direction) {
      t.reversals.push_back(s.position.head<2>());
      outline(s);
      travelled = 0.0;
    } else if (travelled >= spacing_m) {
      outline(s);
      travelled = 0.0;
    }
    if (d != 0) direction = d;
  }
  if (trajectory.size() > 1) outline(trajectory.back());
  return t;
}

NavigationPictureData navigation_picture_data(const NavigationRun& run) {
  const Simulation& sim = run.simulation();
  const Navigator& nav = run.navigator();
  NavigationPictureData d;
  d.name = run.spec().name;
  d.status = nav_status_name(nav.status());
  d.end_time_s = sim.trajectory().empty() ? sim.time() : sim.trajectory().back().t_s;
  d.map = &nav.map();
  d.plans = nav.plans();
  // A point every 5 mm of travel (and the last): the drawn line is the same at any print size,
  // the file a tenth of the size (the robot spends much of its time turning in place).
  for (const TrajectorySample& s : sim.trajectory()) {
    const Vec2 p = s.position.head<2>();
    if (d.trajectory.empty() || (p - d.trajectory.back()).norm() >= 0.005) d.trajectory.push_back(p);
  }
  if (!sim.trajectory().empty()) {
    const Vec2 last = sim.trajectory().back().position.head<2>();
    if (d.trajectory.back() != last) d.trajectory.push_back(last);
  }
  d.start = run.spec().start;
  d.goal = nav.goal();
  d.goal_tolerance_m = nav.config().goal_tolerance_m;
  d.obstacles = sim.world().obstacles();
  const bool pose_plans = std::any_of(d.plans.begin(), d.plans.end(), [](const NavPlan& p) { return !p.poses.empty(); });
  if (pose_plans) {
    FootprintTrail trail = footprint_trail(sim.trajectory(), body_footprint_model(run.spec().vehicle.robot));
    d.footprints = std::move(trail.outlines);
    d.reversals = std::move(trail.reversals);
  }
  return d;
}

viz::MapPicture navigation_scene_picture(const NavigationPictureData& d) {
  if (d.map == nullptr) throw Error("navigation picture without a map", {}, 0, "map");
  const LayeredCostmap& map = *d.map;
  const GridGeometry& g = map.geometry();
  viz::PictureOptions opts;
  opts.title = d.name + ": navigation scene" + title_suffix(d);
  viz::MapPicture pic = base_picture(map, opts);

  // Detected obstacles and the band the planners avoid besides them.
  std::vector<Cell> raw, band;
  for (std::size_t i = 0; i < g.cell_count(); ++i) {
    if (map.raw_blocked()[i]) raw.push_back(g.cell_of_index(i));
    else if (map.blocked()[i]) band.push_back(g.cell_of_index(i));
  }
  pic.add_cells(band, kBand, 0.7, "expansion band");
  pic.add_cells(raw, kRawBlocked, 0.9, "detected obstacle (raw blocked)");

  const viz::LineStyle fixed{kStaticObstacle, 1.0, 1.0, false}, appearing{kStaticObstacle, 1.0, 1.0, true};
  add_obstacle_outlines(pic, d.obstacles, d.end_time_s,
                        {fixed, appearing, {kStaticObstacle, 0.8, 1.0, true}, "true obstacle",
                         "true obstacle, dynamic (where it appeared)"});

  // Sizes in world units that scale with the map, so arrows read the same at any extent.
  const double span = std::max(g.width, g.height) * g.resolution;

  for (std::size_t k = 0; k < d.plans.size(); ++k) {
    const NavPlan& p = d.plans[k];
    if (p.points.size() < 2) continue;  // a failed plan has no path to draw
    pic.add_polyline(p.points, {plan_colour(k), 2.0, 0.9, false}, plan_legend(d, k, true));
  }
  for (std::size_t k = 0; k < d.footprints.size(); ++k)
    pic.add_polyline(d.footprints[k], {kFootprint, 1.0, 0.8, false}, k == 0 ? "robot's outline along the way" : "");
  if (!d.trajectory.empty()) pic.add_polyline(d.trajectory, {kBlack, 3.0, 1.0, false}, "executed trajectory");
  if (!d.reversals.empty())
    pic.add_points(d.reversals, {kReversal, 5.0, kBlack, 1.0, 1.0}, "change of driving direction");
  if (d.goal_tolerance_m > 0.0) pic.add_circle(d.goal, d.goal_tolerance_m, {kBlack, 1.0, 1.0, true}, std::nullopt, "goal tolerance");
  pic.add_pose(d.start, 0.06 * span, {kBlack, 1.5, 1.0, false});
  pic.add_points({d.start.translation()}, {kStart, 5.0, kBlack, 1.0, 1.0}, "start");
  pic.add_points({d.goal}, {kGoal, 5.0, kBlack, 1.0, 1.0}, "goal");
  add_plan_labels(pic, d);
  return pic;
}

viz::LinePlot navigation_overlay_plot(const NavigationPictureData& d) {
  struct Series {
    std::vector<Vec2> points;
    viz::SeriesStyle style;
    std::string label;
  };
  std::vector<Series> series;
  for (std::size_t k = 0; k < d.plans.size(); ++k) {
    const NavPlan& p = d.plans[k];
    if (p.points.size() < 2) continue;
    series.push_back({p.points, {plan_colour(k), 1.4, false, false}, plan_legend(d, k, false)});
  }
  if (!d.trajectory.empty()) series.push_back({d.trajectory, {kBlack, 2.8, false, false}, "executed"});
  if (d.goal_tolerance_m > 0.0)
    series.push_back({circle_points(d.goal, d.goal_tolerance_m), {{90, 90, 90, 255}, 1.0, true, false}, "goal tolerance"});
  series.push_back({{d.start.translation()}, {kStart, 0.0, false, true}, "start"});
  series.push_back({{d.goal}, {kGoal, 0.0, false, true}, "goal"});

  // Explicit ranges: LinePlot pads only y, and its legend sits inside the plot at the top right.
  // The data's box gets a margin all round and room on the right as wide as the legend (its
  // layout: a 20 px line, the label right-aligned 32 px from the plot's edge).
  viz::PlotOptions opts{.title = d.name + ": planned vs executed" + title_suffix(d),
                        .x_label = "x [m]",
                        .y_label = "y [m]",
                        .equal_aspect = true};
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  std::size_t longest = 0;
  for (const Series& s : series) {
    for (const Vec2& p : s.points) {
      if (!p.allFinite()) continue;
      xlo = std::min(xlo, p.x()), xhi = std::max(xhi, p.x());
      ylo = std::min(ylo, p.y()), yhi = std::max(yhi, p.y());
    }
    longest = std::max(longest, s.label.size());
  }
  if (std::isfinite(xlo) && std::isfinite(ylo)) {
    const double m = 0.06 * std::max({xhi - xlo, yhi - ylo, 0.5});
    xlo -= m, xhi += m, ylo -= m, yhi += m;
    const double plot_px = opts.width_px - (5.5 * opts.font_px + 10.0) - 20.0;  // LinePlot's plot width
    const double legend_px = 45.0 + 0.6 * opts.font_px * static_cast<double>(longest);
    xhi = xlo + (xhi - xlo) * plot_px / std::max(plot_px - legend_px, 0.5 * plot_px);
    opts.x_range = std::pair{xlo, xhi};
    opts.y_range = std::pair{ylo, yhi};
  }
  viz::LinePlot plot(opts);
  for (Series& s : series) plot.add_series(std::move(s.points), s.style, std::move(s.label));
  return plot;
}

void write_navigation_scene(const NavigationPictureData& data, const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".svg" && ext != ".png") throw Error("the scene picture must be .svg or .png", path);
  naming_file(path, [&] {
    const viz::MapPicture pic = navigation_scene_picture(data);
    if (ext == ".png") pic.write_png(path);
    else pic.write_svg(path);
  });
}

void write_navigation_scene(const NavigationRun& run, const std::string& path) {
  write_navigation_scene(navigation_picture_data(run), path);
}

viz::MapPicture navigation_overlay_raster(const NavigationPictureData& d) {
  if (!d.map) throw Error("no map to draw", "", 0, "map");
  // The plot's layers on a blank picture of the map's extent: the raster writer draws PNG.
  viz::PictureOptions opts;
  opts.title = d.name + ": planned vs executed" + title_suffix(d);
  opts.plot_background = {255, 255, 255, 255};
  viz::MapPicture pic(d.map->geometry(), opts);
  for (std::size_t k = 0; k < d.plans.size(); ++k) {
    const NavPlan& p = d.plans[k];
    if (p.points.size() < 2) continue;
    pic.add_polyline(p.points, {plan_colour(k), 1.4, 1.0, false}, plan_legend(d, k, false));
  }
  if (!d.trajectory.empty()) pic.add_polyline(d.trajectory, {kBlack, 2.8, 1.0, false}, "executed");
  if (d.goal_tolerance_m > 0.0) pic.add_circle(d.goal, d.goal_tolerance_m, {{90, 90, 90, 255}, 1.0, 1.0, true}, std::nullopt, "goal tolerance");
  pic.add_points({d.start.translation()}, {kStart, 5.0, kBlack, 1.0, 1.0}, "start");
  pic.add_points({d.goal}, {kGoal, 5.0, kBlack, 1.0, 1.0}, "goal");
  return pic;
}

void write_navigation_overlay(const NavigationPictureData& data, const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".svg" && ext != ".png") throw Error("the overlay picture must be .svg or .png", path);
  naming_file(path, [&] {
    if (ext == ".png") navigation_overlay_raster(data).write_png(path);
    else navigation_overlay_plot(data).write_svg(path);
  });
}

void write_navigation_overlay(const NavigationRun& run, const std::string& path) {
  write_navigation_overlay(navigation_picture_data(run), path);
}

}  // namespace starnav
