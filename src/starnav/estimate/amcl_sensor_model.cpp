#include "starnav/estimate/amcl_sensor_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

namespace {

// Squared distance, in cells^2, from every cell centre to the union of the occupied squares
// (mask != 0), +inf without any. The squared distance from a centre to the square of the cell
// (dx, dy) cells away is g(dx) + g(dy), g(t) = max(0, |t| - 1/2)^2, so the transform separates:
//  1. per column, the distance c in cells to the nearest occupied cell of that column, giving
//     f(q) = g(c) for each column q of the row;
//  2. per row, D(p) = min_q g(p - q) + f(q). g is not a parabola, but for q < p it equals
//     (p - 1/2 - q)^2 and for q > p it equals (p + 1/2 - q)^2, and the same expressions are never
//     smaller than g(p - q) for the other q. So D(p) = min(f(p), E(p - 1/2), E(p + 1/2)) with E
//     the lower envelope of the parabolas (x - q)^2 + f(q) (Felzenszwalb & Huttenlocher), exactly.
std::vector<double> amcl_surface_distance_sq(const std::vector<std::uint8_t>& occupied, int w, int h) {
  constexpr int kNoneInColumn = std::numeric_limits<int>::max();
  const std::size_t uw = static_cast<std::size_t>(w);
  std::vector<int> column(occupied.size(), kNoneInColumn);
  for (std::size_t y = 0; y < static_cast<std::size_t>(h); ++y)
    for (std::size_t x = 0; x < uw; ++x) {
      const std::size_t i = y * uw + x;
      if (occupied[i]) column[i] = 0;
      else if (y > 0 && column[i - uw] != kNoneInColumn) column[i] = column[i - uw] + 1;
    }
  for (std::size_t y = static_cast<std::size_t>(h) - 1; y-- > 0;)
    for (std::size_t x = 0; x < uw; ++x) {
      const std::size_t i = y * uw + x;
      if (column[i + uw] != kNoneInColumn && column[i + uw] + 1 < column[i]) column[i] = column[i + uw] + 1;
    }

  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> out(occupied.size(), kInf);
  std::vector<double> f(uw);
  std::vector<int> site(uw);
  std::vector<double> start(uw + 1);
  for (std::size_t y = 0; y < static_cast<std::size_t>(h); ++y) {
    const int* c = column.data() + y * uw;
    int k = -1;  // index of the last parabola of the envelope
    for (int q = 0; q < w; ++q) {
      if (c[q] == kNoneInColumn) continue;
      const double half = c[q] == 0 ? 0.0 : c[q] - 0.5;
      f[static_cast<std::size_t>(q)] = half * half;
      if (k < 0) {
        k = 0;
        site[0] = q;
        start[0] = -kInf;
        start[1] = kInf;
        continue;
      }
      const double fq = f[static_cast<std::size_t>(q)] + static_cast<double>(q) * q;
      double s = 0.0;
      for (;;) {
        const int v = site[static_cast<std::size_t>(k)];
        s = (fq - (f[static_cast<std::size_t>(v)] + static_cast<double>(v) * v)) / (2.0 * (q - v));
        if (s > start[static_cast<std::size_t>(k)]) break;
        --k;  // start[0] = -inf, so k stays >= 0
      }
      ++k;
      site[static_cast<std::size_t>(k)] = q;
      start[static_cast<std::size_t>(k)] = s;
      start[static_cast<std::size_t>(k) + 1] = kInf;
    }
    if (k < 0) continue;  // no occupied cell in any column: the row stays +inf
    double* row = out.data() + y * uw;
    for (int p = 0; p < w; ++p)
      if (c[p] != kNoneInColumn) row[p] = f[static_cast<std::size_t>(p)];
    for (const double shift : {-0.5, 0.5}) {
      std::size_t j = 0;
      for (int p = 0; p < w; ++p) {
        const double x = p + shift;
        while (start[j + 1] < x) ++j;
        const double dx = x - site[j];
        row[p] = std::min(row[p], dx * dx + f[static_cast<std::size_t>(site[j])]);
      }
    }
  }
  return out;
}

void amcl_require_weight(double v, const char* field) {
  require(std::isfinite(v) && v >= 0.0, field, "must be finite and >= 0");
}

}  // namespace

void PlanarScan::validate() const {
  require(ranges.size() == angles_rad.size(), "scan", "ranges and angles differ in size");
  require(std::isfinite(range_max_m) && std::isfinite(range_min_m) && range_min_m >= 0.0 && range_min_m < range_max_m,
          "scan", "needs 0 <= range_min < range_max < inf");
  for (const double a : angles_rad) require(std::isfinite(a), "scan", "beam angles must be finite");
  if (laser_in_base)
    require(std::isfinite(laser_in_base->x) && std::isfinite(laser_in_base->y) && std::isfinite(laser_in_base->yaw), "scan",
            "the laser's mount must be finite");
}

std::vector<ModelBeam> model_beams(const PlanarScan& scan, int max_beams, double range_min_m, double range_max_m) {
  require(max_beams >= 2, "amcl.max_beams", "must be >= 2");
  std::vector<ModelBeam> beams;
  const std::size_t n = std::min(scan.ranges.size(), scan.angles_rad.size());
  if (n == 0) return beams;
  const std::size_t step = std::max<std::size_t>(1, (n - 1) / static_cast<std::size_t>(max_beams - 1));
  beams.reserve((n - 1) / step + 1);
  for (std::size_t i = 0; i < n; i += step) {
    double r = scan.ranges[i];
    if (!(r > range_min_m && r < range_max_m)) r = range_max_m;  // also NaN
    beams.push_back({r, scan.angles_rad[i]});
  }
  return beams;
}

// ---------------------------------------------------------------------------------------------
// LikelihoodField

LikelihoodField::LikelihoodField(const OccupancyGrid& grid, const OccupancyThresholds& thresholds,
                                 const LikelihoodFieldConfig& config)
    : config_(config) {
  require_positive(config.max_dist_m, "amcl.laser_likelihood_max_dist_m");
  require_positive(config.sigma_hit_m, "amcl.sigma_hit_m");
  require_positive(config.range_max_m, "amcl.laser_max_range_m");
  amcl_require_weight(config.z_hit, "amcl.z_hit");
  amcl_require_weight(config.z_rand, "amcl.z_rand");
  require(std::isfinite(config.independent_beams) && config.independent_beams >= 0.0 &&
              config.independent_beams <= kMaxIndependentBeams,
          "amcl.search_independent_beams", "must lie in [0, " + format_number(kMaxIndependentBeams) + "]");
  if (config.independent_beams > 0.0)
    require(config.z_hit + config.z_rand > 0.0, "amcl.search_z_hit", "z_hit and z_rand are both 0: the tempered product is undefined");
  validate_geometry(grid.geometry(), "map");
  width_ = grid.width();
  height_ = grid.height();
  inv_resolution_ = 1.0 / grid.resolution();
  origin_ = grid.origin();

  const double res = grid.resolution();
  const double max_d = config.max_dist_m;
  distance_.resize(grid.cell_count());
  if (config.reference == FieldReference::Centre) {
    const std::vector<double> d = obstacle_distance_m(grid, thresholds, /*unknown_is_obstacle=*/false);
    for (std::size_t i = 0; i < d.size(); ++i) distance_[i] = static_cast<float>(std::min(d[i], max_d));
  } else {
    const std::vector<std::uint8_t> occupied = grid.blocked_mask(thresholds, /*unknown_is_free=*/true);
    const std::vector<double> d2 = amcl_surface_distance_sq(occupied, width_, height_);
    for (std::size_t i = 0; i < d2.size(); ++i) distance_[i] = static_cast<float>(std::min(std::sqrt(d2[i]) * res, max_d));
  }
  fill_terms();
}

void LikelihoodField::set_range_max(double range_max_m) {
  require_positive(range_max_m, "amcl.laser_max_range_m");
  if (range_max_m == config_.range_max_m && !term_.empty()) return;
  config_.range_max_m = range_max_m;
  fill_terms();
}

double LikelihoodField::term_at_distance(double d_m) const {
  const auto pz_at = [this](double d) {
    return config_.z_hit * std::exp(-(d * d) / (2.0 * config_.sigma_hit_m * config_.sigma_hit_m)) +
           config_.z_rand / config_.range_max_m;
  };
  const double pz = pz_at(std::min(d_m, config_.max_dist_m));
  if (config_.independent_beams > 0.0) return std::log(pz / pz_at(0.0));
  return pz * pz * pz;
}

void LikelihoodField::fill_terms() {
  term_.resize(distance_.size());
  for (std::size_t i = 0; i < distance_.size(); ++i) term_[i] = static_cast<float>(term_at_distance(distance_[i]));
  // Off the map the same rounding as a stored cell at max_dist.
  far_term_ = static_cast<float>(term_at_distance(config_.max_dist_m));
}

double LikelihoodField::distance_m(const Vec2& world) const {
  const Vec2 g = origin_.inverse_transform(world) * inv_resolution_;
  if (g.x() >= 0.0 && g.x() < width_ && g.y() >= 0.0 && g.y() < height_)
    return distance_[static_cast<std::size_t>(g.y()) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(g.x())];
  return config_.max_dist_m;
}

double LikelihoodField::term(const Vec2& world) const {
  const Vec2 g = origin_.inverse_transform(world) * inv_resolution_;
  if (g.x() >= 0.0 && g.x() < width_ && g.y() >= 0.0 && g.y() < height_)
    return term_[static_cast<std::size_t>(g.y()) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(g.x())];
  return far_term_;
}

double LikelihoodField::weight(const Pose2& pose, const Pose2& laser_in_base, std::span<const ModelBeam> beams) const {
  double p = 0.0;
  weigh(std::span<const Pose2>(&pose, 1), laser_in_base, beams, std::span<double>(&p, 1));
  return p;
}

void LikelihoodField::weigh(std::span<const Pose2> poses, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
                            std::span<double> out) const {
  require(out.size() == poses.size(), "amcl", "likelihood output size differs from the particle count");
  // The used beams' end points in the laser frame, in cells, once per scan.
  beam_x_.clear();
  beam_y_.clear();
  for (const ModelBeam& b : beams) {
    if (!(b.range_m < config_.range_max_m)) continue;  // non-returns carry no information here (Nav2)
    beam_x_.push_back(b.range_m * std::cos(b.bearing_rad) * inv_resolution_);
    beam_y_.push_back(b.range_m * std::sin(b.bearing_rad) * inv_resolution_);
  }
  const std::size_t nb = beam_x_.size();
  const bool product = config_.independent_beams > 0.0;
  const double k_per_beam = nb ? config_.independent_beams / static_cast<double>(nb) : 0.0;
  const double* bx = beam_x_.data();
  const double* by = beam_y_.data();
  const float* term = term_.data();
  const double far = far_term_;
  const double wd = width_, hd = height_;
  const std::size_t w = static_cast<std::size_t>(width_);
  // Grid frame = origin^-1 * world; the laser's heading in it is yaw + (mount yaw - origin yaw).
  const double co = std::cos(origin_.yaw), so = std::sin(origin_.yaw);
  const double kyaw = laser_in_base.yaw - origin_.yaw;
  const double ck = std::cos(kyaw), sk = std::sin(kyaw);
  const double mx = laser_in_base.x, my = laser_in_base.y;
  for (std::size_t n = 0; n < poses.size(); ++n) {
    const Pose2& p = poses[n];
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    const double dx = p.x + c * mx - s * my - origin_.x;
    const double dy = p.y + s * mx + c * my - origin_.y;
    // The laser in the grid frame, in cells, and its heading's cosine and sine.
    const double gx = (co * dx + so * dy) * inv_resolution_;
    const double gy = (-so * dx + co * dy) * inv_resolution_;
    const double ca = c * ck - s * sk, sa = s * ck + c * sk;
    double sum = 0.0;
    for (std::size_t j = 0; j < nb; ++j) {
      const double cx = gx + ca * bx[j] - sa * by[j];
      const double cy = gy + sa * bx[j] + ca * by[j];
      // Non-negative, so truncation is floor; NaN fails the test and counts as off the map.
      if (cx >= 0.0 && cx < wd && cy >= 0.0 && cy < hd)
        sum += term[static_cast<std::size_t>(cy) * w + static_cast<std::size_t>(cx)];
      else
        sum += far;
    }
    out[n] = product ? (nb ? std::exp(k_per_beam * sum) : 1.0) : 1.0 + sum;
  }
}

// ---------------------------------------------------------------------------------------------
// BeamModel

BeamModel::BeamModel(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, const BeamModelConfig& config)
    : config_(config), geometry_(grid.geometry()) {
  require_positive(config.sigma_hit_m, "amcl.sigma_hit_m");
  require_positive(config.lambda_short, "amcl.lambda_short");
  amcl_require_weight(config.z_hit, "amcl.z_hit");
  amcl_require_weight(config.z_short, "amcl.z_short");
  amcl_require_weight(config.z_max, "amcl.z_max");
  amcl_require_weight(config.z_rand, "amcl.z_rand");
  validate_geometry(geometry_, "map");
  blocked_ = grid.blocked_mask(thresholds, /*unknown_is_free=*/false);
}

double BeamModel::expected_range(const Pose2& laser, double range_max_m) const {
  const double res = geometry_.resolution;
  const Vec2 g = geometry_.world_to_grid(laser.translation()) / res;  // continuous cell coordinates
  int ix = GridGeometry::floor_to_int(g.x()), iy = GridGeometry::floor_to_int(g.y());
  const auto stops = [&](int x, int y) {
    return !geometry_.contains(x, y) || blocked_[geometry_.index(x, y)] != 0;
  };
  if (stops(ix, iy)) return 0.0;
  const double a = laser.yaw - geometry_.origin.yaw;
  const double dx = std::cos(a), dy = std::sin(a);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Amanatides & Woo: t (in cells along the ray) at which the ray leaves the current cell in x and y.
  const int step_x = dx > 0.0 ? 1 : -1, step_y = dy > 0.0 ? 1 : -1;
  const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : kInf;
  const double delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;
  double next_x = dx > 0.0 ? (ix + 1 - g.x()) * delta_x : dx < 0.0 ? (g.x() - ix) * delta_x : kInf;
  double next_y = dy > 0.0 ? (iy + 1 - g.y()) * delta_y : dy < 0.0 ? (g.y() - iy) * delta_y : kInf;
  const double t_max = range_max_m / res;
  for (;;) {
    double t;
    if (next_x < next_y) {
      t = next_x;
      ix += step_x;
      next_x += delta_x;
    } else {
      t = next_y;
      iy += step_y;
      next_y += delta_y;
    }
    if (t >= t_max) return range_max_m;
    if (stops(ix, iy)) return t * res;
  }
}

double BeamModel::beam_probability(double z, double z_expected, double range_max_m) const {
  const double e = z - z_expected;
  double pz = config_.z_hit * std::exp(-(e * e) / (2.0 * config_.sigma_hit_m * config_.sigma_hit_m));
  if (e < 0.0) pz += config_.z_short * config_.lambda_short * std::exp(-config_.lambda_short * z);
  if (z >= range_max_m) pz += config_.z_max;
  else pz += config_.z_rand / range_max_m;
  return pz;
}

double BeamModel::weight(const Pose2& pose, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
                         double range_max_m) const {
  const Pose2 laser = pose.compose(laser_in_base);
  double p = 1.0;
  for (const ModelBeam& b : beams) {
    const double expected = expected_range(Pose2(laser.x, laser.y, laser.yaw + b.bearing_rad), range_max_m);
    const double pz = beam_probability(b.range_m, expected, range_max_m);
    p += pz * pz * pz;
  }
  return p;
}

void BeamModel::weigh(std::span<const Pose2> poses, const Pose2& laser_in_base, std::span<const ModelBeam> beams,
                      double range_max_m, std::span<double> out) const {
  require(out.size() == poses.size(), "amcl", "likelihood output size differs from the particle count");
  for (std::size_t n = 0; n < poses.size(); ++n) out[n] = weight(poses[n], laser_in_base, beams, range_max_m);
}

}  // namespace starnav
