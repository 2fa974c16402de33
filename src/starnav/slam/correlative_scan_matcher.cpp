#include "starnav/slam/correlative_scan_matcher.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <utility>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

namespace {

// Olson's angular step for points out to `d_max`: the farthest point moves at most one cell.
double angular_step(double resolution, double d_max) {
  d_max = std::max(d_max, resolution);
  return std::acos(std::max(-1.0, 1.0 - resolution * resolution / (2.0 * d_max * d_max)));
}

// The sizes of one search: angles and translations per axis (both odd: -n..n), and the top
// level's translation blocks per axis.
struct SearchSize {
  double angles = 0, translations = 0, blocks = 0;
  double step_rad = 0;
  double candidates() const { return angles * blocks * blocks; }
};

SearchSize search_size(double resolution, double d_max, double linear_m, double angular_rad, int depth) {
  SearchSize z;
  z.step_rad = angular_step(resolution, d_max);
  z.angles = 2.0 * std::ceil(angular_rad / z.step_rad) + 1.0;
  const double n_l = std::ceil(linear_m / resolution);
  z.translations = 2.0 * n_l + 1.0;
  z.blocks = std::floor(2.0 * n_l / std::ldexp(1.0, depth)) + 1.0;  // -n_l, -n_l + 2^depth, ... <= n_l
  return z;
}

// The field cell of a coordinate in cell units, clamped to +-2^30: a field has fewer than 2^26
// cells, so a clamped point is outside it, and adding the search window's offsets cannot overflow
// (a guess far from the reference is a miss, not undefined behaviour).
int field_cell(double v) {
  constexpr double kFar = 1073741824.0;
  if (!(v > -kFar)) return -static_cast<int>(kFar);  // also NaN
  if (v >= kFar) return static_cast<int>(kFar);
  return static_cast<int>(std::floor(v));
}

// The bounds of blocks 2, 4, ..., 2^depth cells wide (padded grids: level k starts at cell
// -(2^k - 1)), each from the one below in float and stored rounded up to 1/255.
std::vector<std::vector<std::uint8_t>> block_bounds(const std::vector<float>& fine, int w, int h, int depth) {
  std::vector<std::vector<std::uint8_t>> out;
  std::vector<float> below = fine;
  int below_pad = 0;
  for (int k = 1; k <= depth; ++k) {
    const int half = 1 << (k - 1), pad = (1 << k) - 1;
    const int bw = w + below_pad, wk = w + pad, hk = h + pad;
    const auto at = [&](int x, int y) -> float {  // level k-1 at unpadded cell (x, y)
      const int px = x + below_pad, py = y + below_pad;
      return px >= 0 && py >= 0 && px < bw && py < h + below_pad ? below[static_cast<std::size_t>(py) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(px)] : 0.0f;
    };
    std::vector<float> level(static_cast<std::size_t>(wk) * static_cast<std::size_t>(hk));
    std::vector<std::uint8_t> q(level.size());
    for (int py = 0; py < hk; ++py)
      for (int px = 0; px < wk; ++px) {
        const int x = px - pad, y = py - pad;
        const float m = std::max(std::max(at(x, y), at(x + half, y)), std::max(at(x, y + half), at(x + half, y + half)));
        const std::size_t i = static_cast<std::size_t>(py) * static_cast<std::size_t>(wk) + static_cast<std::size_t>(px);
        level[i] = m;
        q[i] = static_cast<std::uint8_t>(std::min(255.0f, std::ceil(m * 255.0f)));
      }
    out.push_back(std::move(q));
    below.swap(level);
    below_pad = pad;
  }
  return out;
}

// `points` (field coordinates, metres from the origin; empty: the obstacle cells' centres) are
// where the reference really is: a cell's value is measured to the nearest obstacle cell's point,
// not to its centre, so the field carries no half-cell bias.
CorrelativeScanMatcher::Field make_field(std::vector<std::uint8_t> mask, int w, int h, double resolution, const Vec2& origin,
                                         double sigma, int depth, const std::vector<Vec2>& points = {}) {
  CorrelativeScanMatcher::Field f;
  f.resolution = resolution;
  f.origin = origin;
  f.width = w;
  f.height = h;
  std::vector<std::int32_t> nearest;
  const std::vector<double> d2 = squared_distance_transform(mask, w, h, points.empty() ? nullptr : &nearest);
  f.fine.resize(d2.size());
  const double k = 1.0 / (2.0 * sigma * sigma);
  for (std::size_t i = 0; i < d2.size(); ++i) {
    if (!std::isfinite(d2[i])) {
      f.fine[i] = 0.0f;
      continue;
    }
    double d2m = d2[i] * resolution * resolution;
    if (!points.empty()) {
      const Vec2 centre((static_cast<double>(i % static_cast<std::size_t>(w)) + 0.5) * resolution,
                        (static_cast<double>(i / static_cast<std::size_t>(w)) + 0.5) * resolution);
      d2m = (centre - points[static_cast<std::size_t>(nearest[i])]).squaredNorm();
    }
    f.fine[i] = static_cast<float>(std::exp(-d2m * k));
  }
  f.bounds = block_bounds(f.fine, w, h, depth);
  return f;
}

struct Candidate {
  double score = -1.0;
  int angle = 0, ix = 0, iy = 0, level = 0;
};

// Depth-first branch and bound over (angle, x, y) lattice offsets from the guess: a candidate at
// level k stands for the 2^k x 2^k translations from (ix, iy); its score bounds theirs.
class BranchAndBound {
 public:
  // A leaf's score is its mean likelihood times exp(-(cell_weight (ix^2 + iy^2) + step_weight a^2))
  // (a prior around the guess; 1 when both weights are 0); bounds stay the plain likelihoods, which
  // are never below.
  BranchAndBound(const CorrelativeScanMatcher::Field& field, std::span<const Vec2> scan, const Pose2& guess, double step_a,
                 int n_a, double cell_weight, double step_weight)
      : f_(field), n_points_(scan.size()), n_a_(n_a), inv_n_(1.0 / static_cast<double>(scan.size())),
        cell_weight_(cell_weight), step_weight_(step_weight) {
    base_.resize(static_cast<std::size_t>(2 * n_a + 1) * n_points_ * 2);
    for (int a = -n_a; a <= n_a; ++a) {
      const double yaw = guess.yaw + a * step_a;
      const double cs = std::cos(yaw), sn = std::sin(yaw);
      int* b = &base_[static_cast<std::size_t>(a + n_a) * n_points_ * 2];
      for (std::size_t i = 0; i < n_points_; ++i) {
        const double x = guess.x + cs * scan[i].x() - sn * scan[i].y(), y = guess.y + sn * scan[i].x() + cs * scan[i].y();
        b[2 * i] = field_cell((x - f_.origin.x()) / f_.resolution);
        b[2 * i + 1] = field_cell((y - f_.origin.y()) / f_.resolution);
      }
    }
  }

  // The best leaf within +- n_l cells of the guess scoring at least `floor` (score -1 when none
  // does); with exclusion_cells > 0, among the leaves farther than that from `excluded`'s
  // translation (blocks wholly inside that disc are dropped unscored).
  // Angles are searched in [a_lo, a_hi] (the whole window by default).
  Candidate run(double floor, int n_l, const Candidate& excluded = {}, double exclusion_cells = 0.0, int a_lo = INT_MIN,
                int a_hi = INT_MAX) {
    best_ = Candidate{};
    floor_ = floor;
    n_l_ = n_l;
    excluded_ = excluded;
    exclusion2_ = exclusion_cells * exclusion_cells;
    const int top = f_.depth(), step = 1 << top;
    std::vector<Candidate> cands;
    for (int a = std::max(-n_a_, a_lo); a <= std::min(n_a_, a_hi); ++a)
      for (int x = -n_l_; x <= n_l_; x += step)
        for (int y = -n_l_; y <= n_l_; y += step) cands.push_back(scored(a, x, y, top));
    descend(cands);
    return best_;
  }

 private:
  Candidate scored(int a, int x, int y, int level) const {
    const int* b = &base_[static_cast<std::size_t>(a + n_a_) * n_points_ * 2];
    const int w = f_.width, h = f_.height;
    double s = 0.0;
    if (level == 0) {
      for (std::size_t i = 0; i < n_points_; ++i) {
        const int cx = b[2 * i] + x, cy = b[2 * i + 1] + y;
        if (cx >= 0 && cy >= 0 && cx < w && cy < h) s += f_.fine[static_cast<std::size_t>(cy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(cx)];
      }
      if (cell_weight_ > 0 || step_weight_ > 0)
        s *= std::exp(-(cell_weight_ * (x * x + y * y) + step_weight_ * a * a));
    } else {
      const std::vector<std::uint8_t>& g = f_.bounds[static_cast<std::size_t>(level - 1)];
      const int pad = (1 << level) - 1, wk = w + pad, hk = h + pad;
      std::uint32_t sum = 0;
      for (std::size_t i = 0; i < n_points_; ++i) {
        const int px = b[2 * i] + x + pad, py = b[2 * i + 1] + y + pad;
        if (px >= 0 && py >= 0 && px < wk && py < hk) sum += g[static_cast<std::size_t>(py) * static_cast<std::size_t>(wk) + static_cast<std::size_t>(px)];
      }
      s = sum / 255.0;
    }
    return {s * inv_n_, a, x, y, level};
  }

  static int correction(const Candidate& c) { return std::abs(c.angle) + std::abs(c.ix) + std::abs(c.iy); }

  // Whether every translation of the candidate's block lies within the excluded disc (the disc is
  // convex: its four corners do).
  bool inside_exclusion(const Candidate& c) const {
    const int span = (1 << c.level) - 1;
    for (int dx : {0, span})
      for (int dy : {0, span}) {
        const double ex = c.ix + dx - excluded_.ix, ey = c.iy + dy - excluded_.iy;
        if (ex * ex + ey * ey > exclusion2_) return false;
      }
    return true;
  }

  void descend(std::vector<Candidate>& cands) {
    std::sort(cands.begin(), cands.end(), [](const Candidate& p, const Candidate& q) { return p.score > q.score; });
    for (const Candidate& c : cands) {
      if (c.score < floor_ || c.score < best_.score) break;
      if (exclusion2_ > 0 && inside_exclusion(c)) continue;
      if (c.level == 0) {
        // Ties go to the smaller correction (nearer the guess).
        if (c.score > best_.score || correction(c) < correction(best_)) best_ = c;
        continue;
      }
      const int half = 1 << (c.level - 1);
      std::vector<Candidate> children;
      for (int dx : {0, half})
        for (int dy : {0, half})
          if (c.ix + dx <= n_l_ && c.iy + dy <= n_l_) children.push_back(scored(c.angle, c.ix + dx, c.iy + dy, c.level - 1));
      descend(children);
    }
  }

  const CorrelativeScanMatcher::Field& f_;
  std::size_t n_points_;
  int n_a_, n_l_ = 0;
  double inv_n_;
  double cell_weight_, step_weight_;
  std::vector<int> base_;
  Candidate best_;
  double floor_ = -1.0;
  Candidate excluded_;
  double exclusion2_ = 0.0;
};

}  // namespace

const ParamTable<CorrelativeMatcherConfig>& correlative_matcher_params() {
  static const ParamTable<CorrelativeMatcherConfig> table = [] {
    using C = CorrelativeMatcherConfig;
    ParamTable<C> t;
    t.real("resolution_m", &C::resolution_m, closed(0.005, 1.0), "m", "cell of the likelihood field, translation step");
    t.real("sigma_m", &C::sigma_m, closed(0.005, 1.0), "m", "spread of the likelihood around reference points");
    t.real("window_linear_m", &C::window_linear_m, closed(0.0, 10.0), "m", "search +- this in x and in y");
    t.real("window_angular_deg", &C::window_angular_rad, closed(0.0, 180.0), "deg", "search +- this in yaw", kPi / 180.0);
    t.real("min_score", &C::min_score, closed(0.0, 1.0), "", "least score (mean likelihood) to call a match converged");
    t.boolean("refine", &C::refine, "refine the best lattice pose by Gauss-Newton");
    t.real("prior_linear_weight", &C::prior_linear_weight, closed(0.0, 1e6), "1/m^2",
           "pull toward the guess: scores times exp(-w d^2), d the shift from the guess (0: none)");
    t.real("prior_angular_weight", &C::prior_angular_weight, closed(0.0, 1e6), "1/rad^2",
           "pull toward the guess's yaw: scores times exp(-w dyaw^2) (0: none)");
    return t;
  }();
  return table;
}

void CorrelativeMatcherConfig::validate() const {
  require(std::isfinite(resolution_m) && resolution_m >= 0.005 && resolution_m <= 1.0, "resolution_m", "must be in [0.005, 1] m");
  require(std::isfinite(sigma_m) && sigma_m >= 0.005 && sigma_m <= 1.0, "sigma_m", "must be in [0.005, 1] m");
  require(std::isfinite(window_linear_m) && window_linear_m >= 0 && window_linear_m <= 10, "window_linear_m", "must be in [0, 10] m");
  require(std::isfinite(window_angular_rad) && window_angular_rad >= 0 && window_angular_rad <= kPi, "window_angular_deg",
          "must be in [0, 180] deg");
  require(min_score >= 0 && min_score <= 1, "min_score", "must be in [0, 1]");
  require(std::isfinite(prior_linear_weight) && prior_linear_weight >= 0, "prior_linear_weight", "must be >= 0");
  require(std::isfinite(prior_angular_weight) && prior_angular_weight >= 0, "prior_angular_weight", "must be >= 0");
}

CorrelativeScanMatcher::CorrelativeScanMatcher(const CorrelativeMatcherConfig& config) : c_(config) { c_.validate(); }

double CorrelativeScanMatcher::Field::value(const Vec2& world) const {
  // Bicubic (Catmull-Rom) between cell centres, as Cartographer interpolates its grids: bilinear
  // interpolation peaks at cell centres, so a wall lying between two centres would leave the
  // refinement a flat top one cell wide (a bias of up to half a cell across the wall).
  const double gx = (world.x() - origin.x()) / resolution - 0.5, gy = (world.y() - origin.y()) / resolution - 0.5;
  if (!(gx > -2.0 && gy > -2.0 && gx < width + 1.0 && gy < height + 1.0)) return 0.0;
  const int x0 = static_cast<int>(std::floor(gx)), y0 = static_cast<int>(std::floor(gy));
  const double fx = gx - x0, fy = gy - y0;
  auto at = [&](int x, int y) -> double {
    return x >= 0 && y >= 0 && x < width && y < height ? fine[static_cast<std::size_t>(y * width + x)] : 0.0;
  };
  const auto weights = [](double t, double w[4]) {
    const double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2 * t2 - t);
    w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
  };
  double wx[4], wy[4];
  weights(fx, wx);
  weights(fy, wy);
  double v = 0.0;
  for (int j = 0; j < 4; ++j) {
    double row = 0.0;
    for (int i = 0; i < 4; ++i) row += wx[i] * at(x0 - 1 + i, y0 - 1 + j);
    v += wy[j] * row;
  }
  return v;
}

CorrelativeScanMatcher::Field CorrelativeScanMatcher::field_of_points(std::span<const Vec2> points, const Vec2& lo,
                                                                      const Vec2& hi, int depth) const {
  require(depth >= 0 && depth <= 10, "depth", "must be in [0, 10]");
  const double r = c_.resolution_m;
  const Vec2 origin(std::floor(lo.x() / r) * r, std::floor(lo.y() / r) * r);
  const double wx = std::ceil((hi.x() - origin.x()) / r) + 1, wy = std::ceil((hi.y() - origin.y()) / r) + 1;
  if (!(wx * wy <= static_cast<double>(kMaxCorrelativeFieldCells)))
    throw Error("the reference spans more than " + std::to_string(kMaxCorrelativeFieldCells) + " cells of the likelihood field", {}, 0,
                "resolution_m");
  const int w = static_cast<int>(wx), h = static_cast<int>(wy);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  // Per occupied cell the mean of its points (field coordinates).
  std::vector<Vec2> sum(mask.size(), Vec2::Zero());
  std::vector<std::uint32_t> count(mask.size(), 0);
  for (const Vec2& p : points) {
    const int x = static_cast<int>(std::floor((p.x() - origin.x()) / r)), y = static_cast<int>(std::floor((p.y() - origin.y()) / r));
    if (x < 0 || y < 0 || x >= w || y >= h) continue;
    const std::size_t i = static_cast<std::size_t>(y * w + x);
    mask[i] = 1;
    sum[i] += p - origin;
    ++count[i];
  }
  for (std::size_t i = 0; i < sum.size(); ++i)
    if (count[i]) sum[i] /= static_cast<double>(count[i]);
  return make_field(std::move(mask), w, h, r, origin, c_.sigma_m, depth, sum);
}

CorrelativeScanMatcher::Field CorrelativeScanMatcher::field_of_map(const OccupancyGrid& map, int depth) const {
  require(depth >= 0 && depth <= 10, "depth", "must be in [0, 10]");
  // The field on the map's own cells (its resolution replaces resolution_m).
  if (map.cell_count() > static_cast<std::size_t>(kMaxCorrelativeFieldCells))
    throw Error("the map's " + std::to_string(map.width()) + " x " + std::to_string(map.height()) + " cells are more than the " +
                    std::to_string(kMaxCorrelativeFieldCells) + " a likelihood field may have",
                {}, 0, "map");
  std::vector<std::uint8_t> mask(map.cell_count());
  const double occupied = OccupancyThresholds{}.occupied_percent;  // map_server's
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = map[i] >= occupied;
  return make_field(std::move(mask), map.width(), map.height(), map.resolution(), map.origin().translation(), c_.sigma_m, depth);
}

namespace {

// A prepared reference: the field and the matcher's configuration (a copy: the reference may
// outlive the matcher that prepared it).
class CorrelativeReference final : public ScanReference {
 public:
  CorrelativeReference(const CorrelativeScanMatcher& matcher, CorrelativeScanMatcher::Field field)
      : matcher_(matcher), field_(std::move(field)) {}
  ScanMatch match(std::span<const Vec2> scan, const Pose2& guess) const override { return matcher_.match_to_field(field_, scan, guess); }
  ScanMatch match(std::span<const Vec2> scan, const Pose2& guess, const MatchWindow& window) const override {
    return matcher_.match_to_field(field_, scan, guess, window);
  }
  std::size_t bytes() const override { return field_.bytes(); }

 private:
  CorrelativeScanMatcher matcher_;
  CorrelativeScanMatcher::Field field_;
};

}  // namespace

std::unique_ptr<ScanReference> CorrelativeScanMatcher::prepare(std::span<const Vec2> points, double search_margin_m,
                                                               int search_depth) const {
  if (points.empty()) throw Error("needs points in the reference", {}, 0, "reference");
  if (!(std::isfinite(search_margin_m) && search_margin_m >= 0)) throw Error("must be finite and >= 0", {}, 0, "search_margin_m");
  Vec2 lo = points.front(), hi = points.front();
  for (const Vec2& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec2 margin = Vec2::Constant(3 * c_.sigma_m + search_margin_m + c_.resolution_m);
  return std::make_unique<CorrelativeReference>(*this, field_of_points(points, lo - margin, hi + margin, search_depth));
}

void CorrelativeScanMatcher::check_search(const MatchWindow& window, double reach_m, double search_margin_m, int search_depth,
                                          const SearchNames& names) const {
  const double r = c_.resolution_m;
  const std::string resolution = names.matcher + "resolution_m " + format_number(r) + " m";
  const SearchSize z = search_size(r, reach_m, window.linear_m, window.angular_rad, search_depth);
  if (z.candidates() > static_cast<double>(kMaxCorrelativeSearchEntries)) {
    const std::string angular = names.angular.empty() ? std::string("the whole circle")
                                                      : names.angular + " " + format_number(rad_to_deg(window.angular_rad)) + " deg";
    throw Error(names.linear + " " + format_number(window.linear_m) + " m / " + resolution + " and " + angular + " (steps of " +
                    format_number(rad_to_deg(z.step_rad)) + " deg for points out to " + names.reach + " " + format_number(reach_m) +
                    " m) give a search of " + format_number(z.angles) + " angles x " + format_number(z.translations) + " x " +
                    format_number(z.translations) + " translations: " + format_number(z.candidates()) +
                    " candidates at the top of its depth-" + std::to_string(search_depth) + " branch and bound, more than " +
                    std::to_string(kMaxCorrelativeSearchEntries) + ": narrow the window or coarsen resolution_m",
                {}, 0, names.linear);
  }
  // One scan's points all round, widened as prepare() widens them.
  const double side = 2.0 * std::ceil((reach_m + search_margin_m + 3.0 * c_.sigma_m + r) / r) + 1.0;
  if (side * side > static_cast<double>(kMaxCorrelativeFieldCells))
    throw Error(names.reach + " " + format_number(reach_m) + " m / " + resolution + ": the likelihood field of one scan all round spans " +
                    format_number(side) + " x " + format_number(side) + " cells, more than the " +
                    std::to_string(kMaxCorrelativeFieldCells) + " a field may have: lower " + names.reach + " or coarsen resolution_m",
                {}, 0, names.reach);
}

MatchWindow CorrelativeScanMatcher::window() const {
  return {c_.window_linear_m, c_.window_angular_rad, c_.min_score, c_.prior_linear_weight, c_.prior_angular_weight};
}

ScanMatch CorrelativeScanMatcher::match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) {
  if (reference.empty() || scan.empty()) throw Error("needs points in the reference and in the scan", {}, 0, "scan");
  return prepare(reference, 0.0, 2)->match(scan, guess);
}

ScanMatch CorrelativeScanMatcher::match_to_map(const OccupancyGrid& map, std::span<const Vec2> scan, const Pose2& guess) {
  if (scan.empty()) throw Error("needs points in the scan", {}, 0, "scan");
  // Fields live in the grid's axes: poses go through the map origin's rotation.
  const Pose2 axes(0.0, 0.0, map.origin().yaw);
  const Field f = field_of_map(map);
  Pose2 g = axes.inverse().compose(guess);
  ScanMatch m = match_to_field(f, scan, g);
  m.transform = axes.compose(m.transform);
  return m;
}

ScanMatch CorrelativeScanMatcher::match_to_field(const Field& field, std::span<const Vec2> scan, const Pose2& guess) const {
  ScanMatch m = match_to_field(field, scan, guess,
                               MatchWindow{c_.window_linear_m, c_.window_angular_rad, 0.0, c_.prior_linear_weight, c_.prior_angular_weight});
  m.converged = m.score >= c_.min_score;
  return m;
}

std::size_t CorrelativeScanMatcher::Field::bytes() const {
  std::size_t n = fine.size() * sizeof(float);
  for (const auto& b : bounds) n += b.size();
  return n;
}

ScanMatch CorrelativeScanMatcher::match_to_field(const Field& field, std::span<const Vec2> scan, const Pose2& guess,
                                                 const MatchWindow& window) const {
  if (scan.empty()) throw Error("needs points in the scan", {}, 0, "scan");
  for (const Vec2& p : scan)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw Error("scan point not finite", {}, 0, "scan");
  if (!std::isfinite(guess.x) || !std::isfinite(guess.y) || !std::isfinite(guess.yaw)) throw Error("guess not finite", {}, 0, "guess");
  require(std::isfinite(window.linear_m) && window.linear_m >= 0 && window.linear_m <= 100, "window_linear_m", "must be in [0, 100] m");
  require(std::isfinite(window.angular_rad) && window.angular_rad >= 0 && window.angular_rad <= kPi, "window_angular_deg",
          "must be in [0, 180] deg");
  const double r = field.resolution;
  double d_max = r;
  for (const Vec2& p : scan) d_max = std::max(d_max, p.norm());
  // Olson's angular step: the farthest point moves at most one cell.
  const double step_a = angular_step(r, d_max);
  // The tables are sized before they are built (check_search judges the configured searches;
  // this holds any other scan or window).
  require(std::isfinite(window.rival_exclusion_m) && window.rival_exclusion_m >= 0 && window.rival_exclusion_m <= 100, "rival_exclusion_m",
          "must be in [0, 100] m");
  require(std::isfinite(window.rival_linear_m) && window.rival_linear_m >= 0 && window.rival_linear_m <= 100, "rival_linear_m",
          "must be in [0, 100] m");
  require(window.rival_min_share >= 0 && window.rival_min_share <= 1, "rival_min_share", "must be in [0, 1]");
  require(std::isfinite(window.rival_angular_rad) && window.rival_angular_rad >= 0 && window.rival_angular_rad <= kPi, "rival_angular_deg",
          "must be in [0, 180] deg");
  const double searched_m = window.rival_exclusion_m > 0 ? std::max(window.linear_m, window.rival_linear_m) : window.linear_m;
  const SearchSize z = search_size(r, d_max, searched_m, window.angular_rad, field.depth());
  if (z.candidates() > static_cast<double>(kMaxCorrelativeSearchEntries) ||
      z.angles * static_cast<double>(scan.size()) > static_cast<double>(kMaxCorrelativeSearchEntries))
    throw Error("window_linear_m " + format_number(window.linear_m) + " m / resolution_m " + format_number(r) + " m and " +
                    format_number(rad_to_deg(window.angular_rad)) + " deg for " + std::to_string(scan.size()) + " points out to " +
                    format_number(d_max) + " m: a search of " + format_number(z.angles) + " angles x " + format_number(z.translations) +
                    " x " + format_number(z.translations) + " translations takes more than " +
                    std::to_string(kMaxCorrelativeSearchEntries) + " entries of its tables",
                {}, 0, "window_linear_m");
  const int n_a = static_cast<int>(std::ceil(window.angular_rad / step_a));
  const int n_l = static_cast<int>(std::ceil(window.linear_m / r));
  const double inv_n = 1.0 / static_cast<double>(scan.size());
  BranchAndBound search(field, scan, guess, step_a, n_a, r * r * window.prior_linear_weight,
                        step_a * step_a * window.prior_angular_weight);
  const double floor = window.min_score > 0 ? window.min_score : -1.0;
  const Candidate best = search.run(floor, n_l);
  ScanMatch m;
  if (best.score < 0) {  // nothing reached min_score
    m.transform = guess;
    m.score = 0.0;
    return m;
  }
  if (window.rival_exclusion_m > 0 && best.score >= window.min_score && best.score > 0) {
    const int n_rival = static_cast<int>(std::ceil(window.rival_linear_m / r));
    const int a_rival = static_cast<int>(std::ceil(window.rival_angular_rad / step_a));
    const Candidate rival = search.run(std::max(floor, window.rival_min_share * best.score), n_rival, best, window.rival_exclusion_m / r,
                                       best.angle - a_rival, best.angle + a_rival);
    m.ambiguity = rival.score > 0 ? std::min(1.0, rival.score / best.score) : 0.0;
  }
  m.transform = Pose2(guess.x + best.ix * r, guess.y + best.iy * r, wrap_angle(guess.yaw + best.angle * step_a));
  m.score = best.score;
  if (c_.refine) {
    // Gauss-Newton on sum (1 - F(T p))^2 with the bicubic field; steps that do not lower the
    // cost are halved (at most 8 times).
    // The prior adds n w |T - guess|^2 (translation and yaw weights).
    const double n = static_cast<double>(scan.size());
    const double wl = n * window.prior_linear_weight, wa = n * window.prior_angular_weight;
    auto cost_of = [&](const Pose2& t) {
      double e = 0.0;
      for (const Vec2& p : scan) {
        const double f = field.value(t.transform(p));
        e += (1 - f) * (1 - f);
      }
      const double da = wrap_angle(t.yaw - guess.yaw);
      return e + wl * ((t.x - guess.x) * (t.x - guess.x) + (t.y - guess.y) * (t.y - guess.y)) + wa * da * da;
    };
    Pose2 t = m.transform;
    double e = cost_of(t);
    const double eps = 0.25 * r;
    for (int it = 0; it < 20; ++it) {
      ++m.iterations;
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      const double cs = std::cos(t.yaw), sn = std::sin(t.yaw);
      for (const Vec2& p : scan) {
        const Vec2 q = t.transform(p);
        const double f = field.value(q);
        const double fx = (field.value(q + Vec2(eps, 0)) - field.value(q - Vec2(eps, 0))) / (2 * eps);
        const double fy = (field.value(q + Vec2(0, eps)) - field.value(q - Vec2(0, eps))) / (2 * eps);
        // d q / d yaw = R'(yaw) p.
        const double dqx = -sn * p.x() - cs * p.y(), dqy = cs * p.x() - sn * p.y();
        const Eigen::Vector3d J(-fx, -fy, -(fx * dqx + fy * dqy));  // of the residual 1 - f
        H += J * J.transpose();
        g += J * (1 - f);
      }
      H += Eigen::Vector3d(wl, wl, wa).asDiagonal();
      g += Eigen::Vector3d(wl * (t.x - guess.x), wl * (t.y - guess.y), wa * wrap_angle(t.yaw - guess.yaw));
      if (H.determinant() < 1e-12) break;
      Eigen::Vector3d delta = -H.ldlt().solve(g);
      bool improved = false;
      for (int half = 0; half < 8 && !improved; ++half, delta *= 0.5) {
        const Pose2 cand(t.x + delta.x(), t.y + delta.y(), wrap_angle(t.yaw + delta.z()));
        const double ec = cost_of(cand);
        if (ec < e) t = cand, e = ec, improved = true;
      }
      if (!improved || delta.head<2>().norm() < 1e-4 * r) break;
      m.covariance = H.inverse() * (e / std::max<double>(1.0, static_cast<double>(scan.size()) - 3.0));
    }
    m.transform = t;
    double s = 0.0;
    for (const Vec2& p : scan) s += field.value(t.transform(p));
    m.score = s * inv_n;
  }
  double d2 = 0.0;
  std::size_t matched = 0;
  for (const Vec2& p : scan) {
    const double f = field.value(m.transform.transform(p));
    if (f > 1e-3) d2 += -2.0 * c_.sigma_m * c_.sigma_m * std::log(std::min(f, 1.0)), ++matched;
  }
  m.rms_m = matched ? std::sqrt(d2 / static_cast<double>(matched)) : 0.0;
  m.converged = m.score >= window.min_score;
  return m;
}

ScanMatcherDef correlative_scan_matcher() {
  ScanMatcherDef d;
  d.info.role = Role::ScanMatcher;
  d.info.name = "correlative";
  d.info.section = "correlative";
  d.info.summary = "Correlative scan matching (Olson 2009) with a branch-and-bound pruned window and Gauss-Newton refinement";
  d.info.params = correlative_matcher_params().specs();
  d.make = [](const ScanMatcherContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher> {
    return std::make_unique<CorrelativeScanMatcher>(configured(correlative_matcher_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
