#include "starnav/sim/building_generator.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"


namespace starnav {

namespace {

struct KindLayout {
  int nx = 0, ny = 0;          // corridor lines along x (vertical corridors) and y
  double span_x = 0, span_y = 0;  // from the first centre line to the last
  bool atrium = false;
};

KindLayout layout_of(BuildingKind k) {
  switch (k) {
    case BuildingKind::Grid: return {4, 3, 150.0, 72.0, false};
    case BuildingKind::Ladder: return {7, 2, 160.0, 70.0, false};
    case BuildingKind::Courtyard: return {3, 3, 150.0, 80.0, true};
  }
  return {};
}

class Carver {
 public:
  explicit Carver(OccupancyGrid& map) : map_(&map) {}
  // Frees every cell whose centre lies inside the box.
  void free(const AxisBox& b) {
    const double r = map_->resolution();
    const int ix0 = std::max(0, static_cast<int>(std::ceil(b.x0 / r - 0.5)));
    const int iy0 = std::max(0, static_cast<int>(std::ceil(b.y0 / r - 0.5)));
    const int ix1 = std::min(map_->width() - 1, static_cast<int>(std::floor(b.x1 / r - 0.5)));
    const int iy1 = std::min(map_->height() - 1, static_cast<int>(std::floor(b.y1 / r - 0.5)));
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) (*map_)(ix, iy) = kFreeOccupancy;
  }

 private:
  OccupancyGrid* map_;
};

AxisBox box_of(const Vec2& a, const Vec2& b) {
  return {std::min(a.x(), b.x()), std::min(a.y(), b.y()), std::max(a.x(), b.x()), std::max(a.y(), b.y())};
}

struct RoomShape {
  double width = 0, depth = 0, wall = 0, door_width = 0, door_offset = 0;  // door_offset: from the room's start
  double corridor_half = 0;
};

// Rooms side by side along a wall facing a corridor: the wall's corridor face starts at `start`
// and runs `length` along `along`; the rooms lie on the `inward` side (away from the corridor).
void line_rooms(const Vec2& start, const Vec2& along, const Vec2& inward, double length, const RoomShape& s,
                std::vector<BuildingRoom>& rooms) {
  const double pitch = s.width + s.wall;
  const int n = static_cast<int>(std::floor((length - s.wall) / pitch));
  if (n < 1) return;
  const double first = (length - (n * pitch + s.wall)) / 2.0 + s.wall;
  const auto at = [&](double a, double d) { return Vec2{start.x() + along.x() * a + inward.x() * d, start.y() + along.y() * a + inward.y() * d}; };
  for (int k = 0; k < n; ++k) {
    const double a0 = first + k * pitch;
    BuildingRoom room;
    room.interior = box_of(at(a0, s.wall), at(a0 + s.width, s.wall + s.depth));
    const double door0 = a0 + s.door_offset;
    room.door = box_of(at(door0, -0.01), at(door0 + s.door_width, s.wall + 0.01));
    room.outside = at(door0 + s.door_width / 2.0, -s.corridor_half);
    rooms.push_back(room);
  }
}

}  // namespace

const char* building_kind_name(BuildingKind k) {
  switch (k) {
    case BuildingKind::Grid: return "grid";
    case BuildingKind::Ladder: return "ladder";
    case BuildingKind::Courtyard: return "courtyard";
  }
  return "?";
}

BuildingKind parse_building_kind(const std::string& text, const std::string& field) {
  for (BuildingKind k : {BuildingKind::Grid, BuildingKind::Ladder, BuildingKind::Courtyard})
    if (text == building_kind_name(k)) return k;
  throw Error("unknown building kind '" + text + "' (grid, ladder, courtyard)", {}, 0, field);
}

double route_length_m(const std::vector<Vec2>& route) {
  double length = 0.0;
  for (std::size_t i = 0; i < route.size(); ++i) {
    const Vec2& a = route[i];
    const Vec2& b = route[(i + 1) % route.size()];
    length += std::hypot(b.x() - a.x(), b.y() - a.y());
  }
  return length;
}

BuildingFloor generate_building(const BuildingOptions& o) {
  if (!(o.resolution_m > 0.0) || o.resolution_m > 0.5) throw Error("must be in (0, 0.5] m", {}, 0, "resolution_m");
  if (!(o.room_visit_probability >= 0.0 && o.room_visit_probability <= 1.0))
    throw Error("must be in [0, 1]", {}, 0, "room_visit_probability");
  if (!(o.shut_door_probability >= 0.0 && o.shut_door_probability <= 1.0))
    throw Error("must be in [0, 1]", {}, 0, "shut_door_probability");
  Rng rng(o.seed);
  const KindLayout layout = layout_of(o.kind);
  BuildingFloor f;
  f.kind = o.kind;
  f.wall_m = 0.2;
  f.corridor_width_m = rng.uniform(2.2, 3.0);
  RoomShape shape;
  shape.wall = f.wall_m;
  shape.width = rng.uniform(3.5, 5.0);
  shape.depth = rng.uniform(4.0, 6.0);
  shape.door_width = 1.2;
  shape.door_offset = rng.uniform(0.3, shape.width - shape.door_width - 0.3);
  shape.corridor_half = f.corridor_width_m / 2.0;
  f.room_size_m = {shape.width, shape.depth};
  const double half = f.corridor_width_m / 2.0;
  const double outer = half + 2.0 * f.wall_m + shape.depth + 0.5;  // corridor edge, rooms, solid margin
  // Centre lines: the outer ones fixed, the inner ones spread evenly and moved by up to 3 m.
  const auto lines = [&](int n, double span) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      double p = span * i / (n - 1);
      if (i > 0 && i < n - 1) p += rng.uniform(-3.0, 3.0);
      v[static_cast<std::size_t>(i)] = outer + p;
    }
    return v;
  };
  f.corridor_x = lines(layout.nx, layout.span_x);
  f.corridor_y = lines(layout.ny, layout.span_y);
  const double width_m = layout.span_x + 2.0 * outer, height_m = layout.span_y + 2.0 * outer;
  GridGeometry g;
  g.resolution = o.resolution_m;
  g.width = static_cast<int>(std::ceil(width_m / o.resolution_m));
  g.height = static_cast<int>(std::ceil(height_m / o.resolution_m));
  f.map = OccupancyGrid(g, kOccupiedOccupancy);
  Carver carve(f.map);

  const double xa = f.corridor_x.front() - half, xb = f.corridor_x.back() + half;
  const double ya = f.corridor_y.front() - half, yb = f.corridor_y.back() + half;
  for (double x : f.corridor_x) carve.free({x - half, ya, x + half, yb});
  for (double y : f.corridor_y) carve.free({xa, y - half, xb, y + half});

  // Blocks between neighbouring corridors, rooms on their four sides (corners left solid).
  const double corner = f.wall_m + shape.depth;
  for (std::size_t j = 0; j + 1 < f.corridor_y.size(); ++j)
    for (std::size_t i = 0; i + 1 < f.corridor_x.size(); ++i) {
      const AxisBox b{f.corridor_x[i] + half, f.corridor_y[j] + half, f.corridor_x[i + 1] - half, f.corridor_y[j + 1] - half};
      f.blocks.push_back(b);
      line_rooms({b.x0 + corner, b.y0}, Vec2(1, 0), Vec2(0, 1), b.width() - 2 * corner, shape, f.rooms);
      line_rooms({b.x0 + corner, b.y1}, Vec2(1, 0), Vec2(0, -1), b.width() - 2 * corner, shape, f.rooms);
      line_rooms({b.x0, b.y0 + corner}, Vec2(0, 1), Vec2(1, 0), b.height() - 2 * corner, shape, f.rooms);
      line_rooms({b.x1, b.y0 + corner}, Vec2(0, 1), Vec2(-1, 0), b.height() - 2 * corner, shape, f.rooms);
    }
  // The outer strips beyond the outer corridors.
  line_rooms({xa, ya}, Vec2(1, 0), Vec2(0, -1), xb - xa, shape, f.rooms);
  line_rooms({xa, yb}, Vec2(1, 0), Vec2(0, 1), xb - xa, shape, f.rooms);
  line_rooms({xa, ya}, Vec2(0, 1), Vec2(-1, 0), yb - ya, shape, f.rooms);
  line_rooms({xb, ya}, Vec2(0, 1), Vec2(1, 0), yb - ya, shape, f.rooms);
  for (BuildingRoom& room : f.rooms) {
    room.open = !rng.bernoulli(o.shut_door_probability);
    carve.free(room.interior);
    if (room.open) carve.free(room.door);
  }
  if (layout.atrium) {
    // Reaches the rooms' depth into the four blocks round the middle crossing, a wall short of them.
    const double cx = f.corridor_x[f.corridor_x.size() / 2], cy = f.corridor_y[f.corridor_y.size() / 2];
    const double a = half + shape.depth;
    carve.free({cx - a, cy - a, cx + a, cy + a});
  }

  // The route: the outer ring once, then every block's ring in serpentine order (alternating
  // direction), each corridor leg with some of its open rooms entered on the way.
  const auto junction = [&](std::size_t i, std::size_t j) { return Vec2{f.corridor_x[i], f.corridor_y[j]}; };
  const std::size_t nx = f.corridor_x.size(), ny = f.corridor_y.size();
  std::vector<Vec2> corners;
  for (std::size_t i = 0; i < nx; ++i) corners.push_back(junction(i, 0));
  for (std::size_t j = 1; j < ny; ++j) corners.push_back(junction(nx - 1, j));
  for (std::size_t i = nx - 1; i-- > 0;) corners.push_back(junction(i, ny - 1));
  for (std::size_t j = ny - 1; j-- > 0;) corners.push_back(junction(0, j));  // ends at the start
  bool clockwise = false;
  for (std::size_t j = 0; j + 1 < ny; ++j)
    for (std::size_t k = 0; k + 1 < nx; ++k) {
      const std::size_t i = j % 2 == 0 ? k : nx - 2 - k;
      std::vector<Vec2> ring = {junction(i, j), junction(i + 1, j), junction(i + 1, j + 1), junction(i, j + 1)};
      if (clockwise) std::reverse(ring.begin(), ring.end());
      clockwise = !clockwise;
      const Vec2 here = corners.back();
      std::size_t first = 0;
      for (std::size_t c = 1; c < 4; ++c)
        if (std::hypot(ring[c].x() - here.x(), ring[c].y() - here.y()) < std::hypot(ring[first].x() - here.x(), ring[first].y() - here.y())) first = c;
      for (std::size_t c = 0; c <= 4; ++c) corners.push_back(ring[(first + c) % 4]);
    }
  // Drop repeated points; the lap closes from the last point back to the first.
  std::vector<Vec2> legs;
  for (const Vec2& p : corners)
    if (legs.empty() || std::hypot(p.x() - legs.back().x(), p.y() - legs.back().y()) > 1e-9) legs.push_back(p);
  while (legs.size() > 1 && std::hypot(legs.back().x() - legs.front().x(), legs.back().y() - legs.front().y()) < 1e-9) legs.pop_back();
  for (std::size_t k = 0; k < legs.size(); ++k) {
    const Vec2 a = legs[k], b = legs[(k + 1) % legs.size()];
    f.route.push_back(a);
    const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
    const bool straight = std::abs(a.x() - b.x()) < 1e-9 || std::abs(a.y() - b.y()) < 1e-9;
    if (!straight || len < 1e-9) continue;
    std::vector<std::pair<double, const BuildingRoom*>> visits;
    for (const BuildingRoom& room : f.rooms) {
      if (!room.open) continue;
      const double s = ((room.outside.x() - a.x()) * (b.x() - a.x()) + (room.outside.y() - a.y()) * (b.y() - a.y())) / len;
      const double off = std::abs((room.outside.x() - a.x()) * (b.y() - a.y()) - (room.outside.y() - a.y()) * (b.x() - a.x())) / len;
      if (s > 1.0 && s < len - 1.0 && off < 1e-6 && rng.bernoulli(o.room_visit_probability)) visits.emplace_back(s, &room);
    }
    std::sort(visits.begin(), visits.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
    for (const auto& [s, room] : visits) {
      const Vec2 centre{(room->interior.x0 + room->interior.x1) / 2.0, (room->interior.y0 + room->interior.y1) / 2.0};
      f.route.push_back(room->outside);
      f.route.push_back(centre);
      f.route.push_back(room->outside);
    }
  }
  f.start = Pose2(f.route[0].x(), f.route[0].y(), std::atan2(f.route[1].y() - f.route[0].y(), f.route[1].x() - f.route[0].x()));
  return f;
}

}  // namespace starnav

namespace starnav {

BuildingRoute building_route(const BuildingFloor& floor, double length_m) {
  if (!(length_m > 0.0) || !std::isfinite(length_m)) throw Error("must be > 0", {}, 0, "length_m");
  BuildingRoute r;
  const double lap = route_length_m(floor.route);
  if (length_m >= lap) {
    r.waypoints = floor.route;
    r.laps = static_cast<int>(std::ceil(length_m / lap - 1e-9));
    return r;
  }
  double done = 0.0;
  r.waypoints.push_back(floor.route.front());
  for (std::size_t i = 1; i < floor.route.size() && done < length_m; ++i) {
    const Vec2& a = floor.route[i - 1];
    const Vec2& b = floor.route[i];
    done += std::hypot(b.x() - a.x(), b.y() - a.y());
    r.waypoints.push_back(b);
  }
  if (r.waypoints.size() < 2) r.waypoints.push_back(floor.route[1]);
  return r;
}

std::vector<double> building_wheel_scale_errors(const BuildingScenarioOptions& o) {
  if (!(o.wheel_scale_error >= 0.0 && o.wheel_scale_error <= 0.5)) throw Error("must be in [0, 0.5]", {}, 0, "wheel_scale_error");
  // A stream of its own, so the layout drawn from the same seed does not move with it.
  Rng rng = Rng(o.seed).fork(0x5CA1E);
  const double left = rng.uniform(-o.wheel_scale_error, o.wheel_scale_error);
  const double right = rng.uniform(-o.wheel_scale_error, o.wheel_scale_error);
  return {left, right};
}

std::string building_scenario_yaml(const BuildingFloor& f, const BuildingRoute& route, const BuildingScenarioOptions& o) {
  std::ostringstream y;
  const double lap = route_length_m(route.waypoints);
  const double driven = lap * route.laps;
  y << "# A generated large building (starnav slam make-benchmark; docs/slam.md, \"Large buildings\"): kind "
    << building_kind_name(f.kind) << ", " << format_fixed(f.map.width() * f.map.resolution(), 1) << " m x "
    << format_fixed(f.map.height() * f.map.resolution(), 1) << " m, " << f.blocks.size() << " loops, " << f.rooms.size()
    << " identical rooms of " << format_fixed(f.room_size_m.x(), 2) << " m x " << format_fixed(f.room_size_m.y(), 2) << " m.\n";
  y << "# The route: " << route.waypoints.size() << " waypoints, " << route.laps << " lap(s) of about " << format_fixed(lap, 0)
    << " m of straight legs (" << format_fixed(driven, 0) << " m in all).\n";
  y << "name: " << o.name << "\n";
  y << "description: SLAM benchmark of scale - a differential robot with a SICK LMS151 and slipping wheels drives a generated building\n\n";
  y << "world:\n  occupancy_map: {file: " << o.map_file << ", wall_height_m: 2.0}\n\n";
  // A Pioneer-class base: 0.195 m half track, 0.11 m wheels, 1 m/s top speed.
  y << "robot:\n  drive: differential\n  half_track_m: 0.195\n  half_wheelbase_m: 0.15\n  wheel_radius_m: 0.11\n"
       "  body_length_m: 0.45\n  body_width_m: 0.40\n  body_height_m: 0.25\n  ground_clearance_m: 0.06\n"
       "  max_wheel_speed_radps: 9.0\n  max_wheel_accel_radps2: 20.0\n  actuator_lag_s: 0.0\n  max_step_m: 0.05\n";
  y << "  start: {x_m: " << format_fixed(f.start.x, 4) << ", y_m: " << format_fixed(f.start.y, 4)
    << ", yaw_deg: " << format_fixed(f.start.yaw * 180.0 / 3.14159265358979323846, 4) << "}\n\n";
  // The LMS151's datasheet: 270 deg at 0.5 deg, 0.5-50 m, 12 mm statistical error; logged at a
  // benchmark log's rate.
  y << "sensors:\n  lidar:\n    preset: sick_lms151\n    rate_hz: " << format_fixed(o.scan_rate_hz, 3)
    << "\n    mount: {x_m: 0.12, y_m: 0.0, z_m: 0.35}\n    noise_sigma_m: 0.012\n";
  const std::vector<double> scale = building_wheel_scale_errors(o);
  y << "  encoders:\n    rate_hz: 50.0\n    ticks_per_rev: 2048\n    slip_sigma: 0.05\n    scale_error: [" << format_fixed(scale[0], 6)
    << ", " << format_fixed(scale[1], 6) << "]\n  bumper: true\n\n";
  y << "sim:\n  dt_s: 0.01\n  seed: " << o.seed << "\n  duration_s: " << format_fixed(std::ceil(3.0 * driven / o.speed_mps + 600.0), 0) << "\n\n";
  y << "route:\n  speed_mps: " << format_fixed(o.speed_mps, 3) << "\n  laps: " << route.laps << "\n  clearance_m: 0.4\n  waypoints_m:\n";
  for (const Vec2& p : route.waypoints) y << "    - [" << format_fixed(p.x(), 4) << ", " << format_fixed(p.y(), 4) << "]\n";
  return y.str();
}

}  // namespace starnav
