#include "starnav/slam/occupancy_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

float log_odds(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }


}  // namespace

const ParamTable<OccupancyMappingParams>& occupancy_mapping_params() {
  static const ParamTable<OccupancyMappingParams> table = [] {
    using C = OccupancyMappingParams;
    ParamTable<C> t;
    t.real("resolution_m", &C::resolution_m, closed(0.005, 10.0), "m", "cell size of the map");
    t.real("hit_probability", &C::hit_probability, open(0.5, 1.0), "", "occupancy probability a reading gives its cell");
    t.real("miss_probability", &C::miss_probability, open(0.0, 0.5), "", "occupancy probability a beam gives the cells it crosses");
    t.real("clamp_min_probability", &C::clamp_min_probability, open(0.0, 0.5), "", "lowest probability a cell can reach");
    t.real("clamp_max_probability", &C::clamp_max_probability, open(0.5, 1.0), "", "highest probability a cell can reach");
    t.real("max_range_m", &C::max_range_m, closed(0.0, 1000.0), "m", "readings beyond it are cut to it and clear only (0: no cut)");
    t.real("no_return_clear_m", &C::no_return_clear_m, closed(0.0, 1000.0), "m",
           "a beam that returned nothing clears the cells up to this distance (0: dropped)");
    return t;
  }();
  return table;
}

void OccupancyMappingParams::validate() const {
  require(std::isfinite(resolution_m) && resolution_m >= 0.005 && resolution_m <= 10.0, "resolution_m", "must be in [0.005, 10] m");
  require(hit_probability > 0.5 && hit_probability < 1.0, "hit_probability", "must be in (0.5, 1)");
  require(miss_probability > 0.0 && miss_probability < 0.5, "miss_probability", "must be in (0, 0.5)");
  require(clamp_min_probability > 0.0 && clamp_min_probability < 0.5, "clamp_min_probability", "must be in (0, 0.5)");
  require(clamp_max_probability > 0.5 && clamp_max_probability < 1.0, "clamp_max_probability", "must be in (0.5, 1)");
  require(std::isfinite(max_range_m) && max_range_m >= 0.0 && max_range_m <= 1000.0, "max_range_m", "must be in [0, 1000] m");
  require(std::isfinite(no_return_clear_m) && no_return_clear_m >= 0.0 && no_return_clear_m <= 1000.0, "no_return_clear_m",
          "must be in [0, 1000] m");
  // Beams without a return clear this far whatever the scene: a scan all round covers a square
  // twice as wide, which the map must hold.
  const double reach = max_range_m > 0.0 ? std::min(no_return_clear_m, max_range_m) : no_return_clear_m;
  const double side = 2.0 * std::ceil(reach / resolution_m) + 1.0;
  if (reach > 0.0 && side * side > static_cast<double>(kMaxOccupancyMapCells))
    throw Error("no_return_clear_m " + format_number(no_return_clear_m) + " m" +
                    (reach < no_return_clear_m ? " (cut to max_range_m " + format_number(max_range_m) + " m)" : std::string()) +
                    " over resolution_m " + format_number(resolution_m) + " m: one scan's beams without a return span " +
                    format_number(side) + " x " + format_number(side) + " cells, more than the " + std::to_string(kMaxOccupancyMapCells) +
                    " a map may have: lower no_return_clear_m or coarsen resolution_m",
                {}, 0, "no_return_clear_m");
}

OccupancyMapper::OccupancyMapper(const OccupancyMappingParams& params) : params_(params) {
  params_.validate();
  hit_ = log_odds(params_.hit_probability);
  miss_ = log_odds(params_.miss_probability);
  lo_ = log_odds(params_.clamp_min_probability);
  hi_ = log_odds(params_.clamp_max_probability);
}

void OccupancyMapper::check_reach(const Vec2& from, const Vec2& to) const {
  // In cell units, as doubles: nothing is converted to an integer before it is known to fit.
  const double r = params_.resolution_m;
  const double fx = std::floor(std::min(from.x(), to.x()) / r), fy = std::floor(std::min(from.y(), to.y()) / r);
  const double tx = std::floor(std::max(from.x(), to.x()) / r) + 1, ty = std::floor(std::max(from.y(), to.y()) / r) + 1;
  const auto where = [&] {
    const Vec2& far = std::max(std::abs(from.x()), std::abs(from.y())) > std::max(std::abs(to.x()), std::abs(to.y())) ? from : to;
    return "a pose or reading at (" + format_number(far.x()) + ", " + format_number(far.y()) + ") m lies far outside the mapped area";
  };
  if (!(std::abs(fx) <= kMaxLatticeIndex && std::abs(fy) <= kMaxLatticeIndex && std::abs(tx) <= kMaxLatticeIndex &&
        std::abs(ty) <= kMaxLatticeIndex))
    throw Error(where() + ": a map of " + format_number(r) + " m cells reaches at most " + format_number(kMaxLatticeIndex * r) +
                    " m from the origin",
                {}, 0, "resolution_m");
  // The least box the map would cover with this segment (the cells it has, the segment's).
  const double bx0 = w_ ? std::min(static_cast<double>(x0_), fx) : fx, by0 = h_ ? std::min(static_cast<double>(y0_), fy) : fy;
  const double bx1 = w_ ? std::max(static_cast<double>(x0_ + w_), tx) : tx, by1 = h_ ? std::max(static_cast<double>(y0_ + h_), ty) : ty;
  if ((bx1 - bx0) * (by1 - by0) > static_cast<double>(kMaxOccupancyMapCells))
    throw Error(where() + ": the map would grow to " + format_number(bx1 - bx0) + " x " + format_number(by1 - by0) +
                    " cells, more than the " + std::to_string(kMaxOccupancyMapCells) + " a map may have",
                {}, 0, "resolution_m");
}

OccupancyMapper::Cell& OccupancyMapper::cell(std::int64_t ix, std::int64_t iy) {
  if (ix < x0_ || iy < y0_ || ix >= x0_ + w_ || iy >= y0_ + h_) {
    // Grow with a margin (half the new extent, at least 64 cells) so that a robot exploring in
    // one direction reallocates a logarithmic number of times; no margin where it would pass the
    // cell limit (check_reach has made sure the cells themselves fit).
    const std::int64_t tx0 = w_ ? std::min(x0_, ix) : ix, ty0 = h_ ? std::min(y0_, iy) : iy;
    const std::int64_t tx1 = w_ ? std::max(x0_ + w_, ix + 1) : ix + 1, ty1 = h_ ? std::max(y0_ + h_, iy + 1) : iy + 1;
    std::int64_t nx0 = tx0, ny0 = ty0, nx1 = tx1, ny1 = ty1;
    const std::int64_t mx = std::max<std::int64_t>(64, (nx1 - nx0) / 2), my = std::max<std::int64_t>(64, (ny1 - ny0) / 2);
    if (nx0 < x0_ || !w_) nx0 -= mx;
    if (nx1 > x0_ + w_ || !w_) nx1 += mx;
    if (ny0 < y0_ || !h_) ny0 -= my;
    if (ny1 > y0_ + h_ || !h_) ny1 += my;
    if (nx1 - nx0 > kMaxOccupancyMapCells / (ny1 - ny0)) nx0 = tx0, ny0 = ty0, nx1 = tx1, ny1 = ty1;
    const std::int64_t nw = nx1 - nx0, nh = ny1 - ny0;
    std::vector<Cell> grown(static_cast<std::size_t>(nw * nh));
    for (std::int64_t y = 0; y < h_; ++y)
      std::copy_n(cells_.begin() + y * w_, w_, grown.begin() + ((y + y0_ - ny0) * nw + (x0_ - nx0)));
    cells_ = std::move(grown);
    x0_ = nx0, y0_ = ny0, w_ = nw, h_ = nh;
  }
  return cells_[static_cast<std::size_t>((iy - y0_) * w_ + (ix - x0_))];
}

void OccupancyMapper::update(std::int64_t ix, std::int64_t iy, bool hit) {
  Cell& c = cell(ix, iy);
  if (c.last_scan == scans_) {
    // Updated by this scan already: only a hit replacing a pass-through changes it.
    if (!hit || c.last_hit) return;
    c.log_odds = c.before_scan;
  } else {
    c.before_scan = c.log_odds;
    if (track_) touched_.push_back({ix, iy, c.observed()});
  }
  c.last_scan = scans_;
  c.last_hit = hit;
  c.log_odds = std::clamp(c.log_odds + (hit ? hit_ : miss_), lo_, hi_);
}

void OccupancyMapper::trace(const Vec2& from, const Vec2& to, bool hit) {
  check_reach(from, to);
  std::int64_t ex = 0, ey = 0;
  for_each_cell_on_segment(from, to, params_.resolution_m, [&](std::int64_t ix, std::int64_t iy, bool last) {
    if (last) ex = ix, ey = iy;
    else update(ix, iy, false);
  });
  update(ex, ey, hit);
}

template <class Range, class Angle>
void OccupancyMapper::add_beams(const Pose2& sensor_pose, std::size_t beams, Range range, Angle angle, double range_min,
                                double range_max) {
  if (!std::isfinite(sensor_pose.x) || !std::isfinite(sensor_pose.y) || !std::isfinite(sensor_pose.yaw))
    throw Error("sensor pose is not finite", {}, 0, "pose");
  ++scans_;
  const Vec2 origin = sensor_pose.translation();
  for (std::size_t i = 0; i < beams; ++i) {
    double d = range(i);
    if (std::isnan(d) || d < range_min || d <= 0.0) continue;
    bool hit = true;
    if (d >= range_max) {
      if (params_.no_return_clear_m <= 0.0) continue;
      d = params_.no_return_clear_m;
      hit = false;
    }
    if (params_.max_range_m > 0.0 && d > params_.max_range_m) {
      d = params_.max_range_m;
      hit = false;
    }
    const double a = angle(i);
    trace(origin, origin + d * Vec2(std::cos(a), std::sin(a)), hit);
  }
  if (track_) collect_changes();
}

void OccupancyMapper::add_rays(const Pose2& sensor_pose, double angle_min, double angle_increment,
                               const std::vector<float>& ranges, double range_min, double range_max) {
  add_beams(
      sensor_pose, ranges.size(), [&](std::size_t i) { return static_cast<double>(ranges[i]); },
      [&](std::size_t i) { return sensor_pose.yaw + angle_min + static_cast<double>(i) * angle_increment; }, range_min, range_max);
}

void OccupancyMapper::add_scan(const Pose2& sensor_pose, const ScanMessage& scan) {
  const auto range = [&](std::size_t i) { return scan.ranges_m[i]; };
  if (scan.angles_rad.empty())
    add_beams(
        sensor_pose, scan.ranges_m.size(), range,
        [&](std::size_t i) { return sensor_pose.yaw + scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad; },
        scan.range_min_m, scan.range_max_m);
  else
    add_beams(sensor_pose, scan.ranges_m.size(), range, [&](std::size_t i) { return sensor_pose.yaw + scan.angles_rad[i]; },
              scan.range_min_m, scan.range_max_m);
}

namespace {

// A log-odds value as the map stores it: the probability of occupancy in whole percent.
std::int8_t occupancy_percent(float log_odds) {
  const double p = 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(log_odds)));
  return static_cast<std::int8_t>(std::lround(100.0 * p));
}

// The class the written map file gives a cell: its percent as write_ros_map writes it with the
// default thresholds (map_saver's rule: free at <= rint(19.6) = 20 %, occupied at >= 65 %), so
// replaying the changes gives the written map's classes exactly, on the thresholds too.
std::int8_t trinary_class(float log_odds) {
  const int v = occupancy_percent(log_odds);
  return v >= 65 ? 100 : (v <= 20 ? 0 : -1);
}

}  // namespace

void OccupancyMapper::collect_changes() {
  changes_.clear();
  for (const Touched& t : touched_) {
    const Cell& c = cells_[static_cast<std::size_t>((t.iy - y0_) * w_ + (t.ix - x0_))];
    const std::int8_t before = t.observed_before ? trinary_class(c.before_scan) : std::int8_t{-1};
    const std::int8_t after = trinary_class(c.log_odds);
    if (after != before) changes_.push_back({t.ix, t.iy, after});
  }
  touched_.clear();
}

void OccupancyMapper::add_scan(const Pose2& sensor_pose, const LogScan& scan) {
  add_rays(sensor_pose, scan.angle_min_rad, scan.angle_increment_rad, scan.ranges_m, scan.range_min_m, scan.range_max_m);
}

double OccupancyMapper::log_odds_at(const Vec2& world) const {
  const std::int64_t ix = static_cast<std::int64_t>(std::floor(world.x() / params_.resolution_m));
  const std::int64_t iy = static_cast<std::int64_t>(std::floor(world.y() / params_.resolution_m));
  if (ix < x0_ || iy < y0_ || ix >= x0_ + w_ || iy >= y0_ + h_) return 0.0;
  return cells_[static_cast<std::size_t>((iy - y0_) * w_ + (ix - x0_))].log_odds;
}

OccupancyGrid OccupancyMapper::grid() const {
  // The bounding box of the observed cells.
  std::int64_t bx0 = std::numeric_limits<std::int64_t>::max(), by0 = bx0, bx1 = std::numeric_limits<std::int64_t>::min(), by1 = bx1;
  for (std::int64_t y = 0; y < h_; ++y)
    for (std::int64_t x = 0; x < w_; ++x)
      if (cells_[static_cast<std::size_t>(y * w_ + x)].observed()) {
        bx0 = std::min(bx0, x), bx1 = std::max(bx1, x);
        by0 = std::min(by0, y), by1 = std::max(by1, y);
      }
  GridGeometry g;
  g.resolution = params_.resolution_m;
  if (bx1 < bx0) {
    g.width = g.height = 1;
    return OccupancyGrid(g, kUnknownOccupancy);
  }
  g.width = static_cast<int>(bx1 - bx0 + 1);
  g.height = static_cast<int>(by1 - by0 + 1);
  g.origin = Pose2(static_cast<double>(x0_ + bx0) * g.resolution, static_cast<double>(y0_ + by0) * g.resolution, 0.0);
  OccupancyGrid out(g, kUnknownOccupancy);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Cell& c = cells_[static_cast<std::size_t>((by0 + y) * w_ + (bx0 + x))];
      if (!c.observed()) continue;
      out(x, y) = occupancy_percent(c.log_odds);
    }
  return out;
}

}  // namespace starnav
