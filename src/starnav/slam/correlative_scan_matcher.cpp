#include "starnav/slam/correlative_scan_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

namespace {

// The most cells a likelihood field may have (a reference spread over kilometres is refused).
constexpr std::int64_t kMaxFieldCells = std::int64_t{1} << 26;

// Sliding maximum over [x, x + 4) x [y, y + 4): an upper bound of the fine values a block of 4 x 4
// translations can reach from one base cell.
std::vector<float> block_max(const std::vector<float>& fine, int w, int h) {
  std::vector<float> rows(fine.size()), out(fine.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float m = 0.0f;
      for (int k = 0; k < 4 && x + k < w; ++k) m = std::max(m, fine[static_cast<std::size_t>(y * w + x + k)]);
      rows[static_cast<std::size_t>(y * w + x)] = m;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float m = 0.0f;
      for (int k = 0; k < 4 && y + k < h; ++k) m = std::max(m, rows[static_cast<std::size_t>((y + k) * w + x)]);
      out[static_cast<std::size_t>(y * w + x)] = m;
    }
  return out;
}

// `points` (field coordinates, metres from the origin; empty: the obstacle cells' centres) are
// where the reference really is: a cell's value is measured to the nearest obstacle cell's point,
// not to its centre, so the field carries no half-cell bias.
CorrelativeScanMatcher::Field make_field(std::vector<std::uint8_t> mask, int w, int h, double resolution, const Vec2& origin,
                                         double sigma, const std::vector<Vec2>& points = {}) {
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
  f.coarse = block_max(f.fine, w, h);
  return f;
}

struct Candidate {
  double score = -1.0;
  int angle = 0, ix = 0, iy = 0;
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
}

CorrelativeScanMatcher::CorrelativeScanMatcher(const CorrelativeMatcherConfig& config) : c_(config) { c_.validate(); }

double CorrelativeScanMatcher::Field::value(const Vec2& world) const {
  // Bilinear between cell centres.
  const double gx = (world.x() - origin.x()) / resolution - 0.5, gy = (world.y() - origin.y()) / resolution - 0.5;
  if (!(gx > -1.0 && gy > -1.0 && gx < width && gy < height)) return 0.0;
  const int x0 = static_cast<int>(std::floor(gx)), y0 = static_cast<int>(std::floor(gy));
  const double fx = gx - x0, fy = gy - y0;
  auto at = [&](int x, int y) -> double {
    return x >= 0 && y >= 0 && x < width && y < height ? fine[static_cast<std::size_t>(y * width + x)] : 0.0;
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

CorrelativeScanMatcher::Field CorrelativeScanMatcher::field_of_points(std::span<const Vec2> points, const Vec2& lo,
                                                                      const Vec2& hi) const {
  const double r = c_.resolution_m;
  const Vec2 origin(std::floor(lo.x() / r) * r, std::floor(lo.y() / r) * r);
  const double wx = std::ceil((hi.x() - origin.x()) / r) + 1, wy = std::ceil((hi.y() - origin.y()) / r) + 1;
  if (!(wx * wy <= static_cast<double>(kMaxFieldCells)))
    throw Error("the reference spans more than " + std::to_string(kMaxFieldCells) + " cells of the likelihood field", {}, 0,
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
  return make_field(std::move(mask), w, h, r, origin, c_.sigma_m, sum);
}

CorrelativeScanMatcher::Field CorrelativeScanMatcher::field_of_map(const OccupancyGrid& map) const {
  // The field on the map's own cells (its resolution replaces resolution_m).
  std::vector<std::uint8_t> mask(map.cell_count());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = map[i] >= 65;  // map_server's occupied threshold
  return make_field(std::move(mask), map.width(), map.height(), map.resolution(), map.origin().translation(), c_.sigma_m);
}

ScanMatch CorrelativeScanMatcher::match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) {
  if (reference.empty() || scan.empty()) throw Error("needs points in the reference and in the scan", {}, 0, "scan");
  Vec2 lo = reference.front(), hi = reference.front();
  for (const Vec2& p : reference) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec2 margin = Vec2::Constant(3 * c_.sigma_m + c_.resolution_m);
  return match_to_field(field_of_points(reference, lo - margin, hi + margin), scan, guess);
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
  for (const Vec2& p : scan)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw Error("scan point not finite", {}, 0, "scan");
  if (!std::isfinite(guess.x) || !std::isfinite(guess.y) || !std::isfinite(guess.yaw)) throw Error("guess not finite", {}, 0, "guess");
  const double r = field.resolution;
  double d_max = r;
  for (const Vec2& p : scan) d_max = std::max(d_max, p.norm());
  // Olson's angular step: the farthest point moves at most one cell.
  const double step_a = std::acos(std::max(-1.0, 1.0 - r * r / (2.0 * d_max * d_max)));
  const int n_a = static_cast<int>(std::ceil(c_.window_angular_rad / step_a));
  const int n_l = static_cast<int>(std::ceil(c_.window_linear_m / r));
  const double inv_n = 1.0 / static_cast<double>(scan.size());
  Candidate best;
  std::vector<int> base(scan.size() * 2);
  const int w = field.width, h = field.height;
  auto fine_at = [&](int x, int y) -> float {
    return x >= 0 && y >= 0 && x < w && y < h ? field.fine[static_cast<std::size_t>(y * w + x)] : 0.0f;
  };
  auto coarse_at = [&](int x, int y) -> float {
    // Blocks reaching in from outside the field: the nearest inside cell's bound covers them only
    // in part, so use the global bound 1 there.
    return x >= 0 && y >= 0 && x < w && y < h ? field.coarse[static_cast<std::size_t>(y * w + x)] : (x > -4 && y > -4 && x < w && y < h ? 1.0f : 0.0f);
  };
  for (int a = -n_a; a <= n_a; ++a) {
    const double yaw = guess.yaw + a * step_a;
    const double cs = std::cos(yaw), sn = std::sin(yaw);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const double x = guess.x + cs * scan[i].x() - sn * scan[i].y(), y = guess.y + sn * scan[i].x() + cs * scan[i].y();
      base[2 * i] = static_cast<int>(std::floor((x - field.origin.x()) / r));
      base[2 * i + 1] = static_cast<int>(std::floor((y - field.origin.y()) / r));
    }
    // Blocks of 4 x 4 translations, best bound first.
    std::vector<std::pair<float, std::pair<int, int>>> blocks;
    for (int bx = -n_l; bx <= n_l; bx += 4)
      for (int by = -n_l; by <= n_l; by += 4) {
        double bound = 0.0;
        for (std::size_t i = 0; i < scan.size(); ++i) bound += coarse_at(base[2 * i] + bx, base[2 * i + 1] + by);
        blocks.push_back({static_cast<float>(bound * inv_n), {bx, by}});
      }
    std::sort(blocks.begin(), blocks.end(), [](const auto& p, const auto& q) { return p.first > q.first; });
    for (const auto& [bound, xy] : blocks) {
      if (bound <= best.score) break;
      for (int ix = xy.first; ix < xy.first + 4 && ix <= n_l; ++ix)
        for (int iy = xy.second; iy < xy.second + 4 && iy <= n_l; ++iy) {
          double s = 0.0;
          for (std::size_t i = 0; i < scan.size(); ++i) s += fine_at(base[2 * i] + ix, base[2 * i + 1] + iy);
          s *= inv_n;
          // Ties go to the smaller correction (nearer the guess).
          const auto cost = [&](int aa, int x, int y) { return std::abs(aa) + std::abs(x) + std::abs(y); };
          if (s > best.score || (s == best.score && cost(a, ix, iy) < cost(best.angle, best.ix, best.iy))) best = {s, a, ix, iy};
        }
    }
  }
  ScanMatch m;
  m.transform = Pose2(guess.x + best.ix * r, guess.y + best.iy * r, wrap_angle(guess.yaw + best.angle * step_a));
  m.score = best.score;
  if (c_.refine) {
    // Gauss-Newton on sum (1 - F(T p))^2 with the bilinear field; steps that do not lower the
    // cost are halved (at most 8 times).
    auto cost_of = [&](const Pose2& t) {
      double e = 0.0;
      for (const Vec2& p : scan) {
        const double f = field.value(t.transform(p));
        e += (1 - f) * (1 - f);
      }
      return e;
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
    if (f > 1e-3) d2 += -2.0 * c_.sigma_m * c_.sigma_m * std::log(f), ++matched;
  }
  m.rms_m = matched ? std::sqrt(d2 / static_cast<double>(matched)) : 0.0;
  m.converged = m.score >= c_.min_score;
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
