#include "starnav/plan/inflation.hpp"

#include <cmath>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

void validate_inflation(const InflationOptions& o) {
  auto check = [](double v, const char* field, const char* what) {
    if (!std::isfinite(v) || v < 0.0) throw Error(std::string("must be ") + what, {}, 0, field);
  };
  check(o.radius_m, "inflate", "a finite radius >= 0 (metres)");
  check(o.cost_radius_m, "inflate_cost_radius", "a finite radius >= 0 (metres)");
  check(o.cost_scale, "inflate_cost", "a finite scaling factor >= 0 (1/m)");
  check(o.cost_weight, "inflate_cost_weight", "a finite weight >= 0");
  if (o.cost_radius_m > 0.0 && o.cost_radius_m <= o.radius_m)
    throw Error("the outer radius of the cost band must exceed the hard radius (--inflate)", {}, 0,
                "inflate_cost_radius");
}

double inflation_cost_multiplier(double d_m, const InflationOptions& o) {
  if (!o.graded() || !(d_m > o.radius_m) || d_m > o.cost_radius_m) return 1.0;
  return 1.0 + o.cost_weight * std::exp(-o.cost_scale * (d_m - o.radius_m));
}

InflatedMap inflate_obstacles(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free,
                              const InflationOptions& options) {
  InflatedMap out;
  ObstacleInflator().inflate(grid, thresholds, unknown_is_free, options, out);
  return out;
}

void ObstacleInflator::inflate(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free,
                               const InflationOptions& options, InflatedMap& out) {
  validate_inflation(options);
  out.width = grid.width();
  out.height = grid.height();
  out.resolution = grid.resolution();
  grid.blocked_mask(out.blocked, thresholds, unknown_is_free);
  const std::size_t n = out.blocked.size();
  out.obstacle_cells = 0;
  out.inflated_cells = 0;
  for (const std::uint8_t b : out.blocked) out.obstacle_cells += b != 0;

  transform_.compute(out.blocked, out.width, out.height);
  const std::vector<double>& d2 = transform_.squared_cells();
  // One pass over the cells: clearance, the hard radius, the band (squared distances compared
  // first, so exp runs only inside the band).
  out.clearance_m.resize(n);
  const double radius_cells = inflation_radius_cells(options.radius_m, out.resolution);
  const bool hard = options.hard(), graded = options.graded();
  const double band_cells = inflation_radius_cells(options.cost_radius_m, out.resolution);
  if (graded) out.multiplier.assign(n, 1.0);
  else out.multiplier.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double d_m = std::sqrt(d2[i]) * out.resolution;
    out.clearance_m[i] = d_m;
    if (out.blocked[i]) continue;
    if (hard && within_inflation_radius(d2[i], radius_cells)) {
      out.blocked[i] = 1;
      ++out.inflated_cells;
    } else if (graded && d2[i] <= inflation_limit_squared(band_cells)) {
      out.multiplier[i] = inflation_cost_multiplier(d_m, options);
    }
  }
}

OccupancyGrid inflated_grid(const OccupancyGrid& grid, const InflatedMap& inflated) {
  OccupancyGrid out = grid;
  auto data = out.data();
  // Cells blocked only by inflation become occupied; the original obstacles keep their values.
  for (std::size_t i = 0; i < data.size(); ++i)
    if (inflated.blocked[i] && inflated.clearance_m[i] > 0.0) data[i] = kOccupiedOccupancy;
  return out;
}

}  // namespace starnav
