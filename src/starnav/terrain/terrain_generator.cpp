#include "starnav/terrain/terrain_generator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

namespace {

// The half-width of the truncated Gaussian kernel along an axis of n cells: ceil(4 sigma),
// clipped to the field (weights beyond its far side never meet a cell, and a huge sigma (1e9)
// must not ask for a kernel of billions of weights).
int blur_radius(double sigma, int n) {
  return static_cast<int>(std::min(std::ceil(4.0 * sigma), static_cast<double>(std::max(n - 1, 0))));
}

// Truncated Gaussian blur (radius ceil(4 sigma)) along one axis of a row-major w x h field, the
// kernel renormalised where it is cut by the border. `sq` receives, per position along the
// axis, the sum of the squared normalised weights (the variance factor of blurred white noise).
void blur_axis(std::vector<double>& z, int w, int h, double sigma, bool along_x, std::vector<double>& sq) {
  const int n = along_x ? w : h;
  sq.assign(static_cast<std::size_t>(n), 1.0);
  if (!(sigma > 0.0)) return;
  const int radius = blur_radius(sigma, n);
  std::vector<double> kernel(static_cast<std::size_t>(2 * radius + 1));
  for (int i = -radius; i <= radius; ++i) kernel[static_cast<std::size_t>(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
  // Normalisation per output position.
  std::vector<double> norm(static_cast<std::size_t>(n));
  for (int p = 0; p < n; ++p) {
    double s = 0.0, s2 = 0.0;
    for (int q = std::max(0, p - radius); q <= std::min(n - 1, p + radius); ++q) {
      const double k = kernel[static_cast<std::size_t>(q - p + radius)];
      s += k;
      s2 += k * k;
    }
    norm[static_cast<std::size_t>(p)] = 1.0 / s;
    sq[static_cast<std::size_t>(p)] = s2 / (s * s);
  }
  const std::size_t W = static_cast<std::size_t>(w);
  if (along_x) {
    std::vector<double> row(W);
    for (int y = 0; y < h; ++y) {
      double* r = z.data() + static_cast<std::size_t>(y) * W;
      std::copy(r, r + W, row.begin());
      for (int p = 0; p < w; ++p) {
        double s = 0.0;
        for (int q = std::max(0, p - radius); q <= std::min(w - 1, p + radius); ++q)
          s += kernel[static_cast<std::size_t>(q - p + radius)] * row[static_cast<std::size_t>(q)];
        r[p] = s * norm[static_cast<std::size_t>(p)];
      }
    }
  } else {
    // Whole rows at a time, so memory is read contiguously.
    std::vector<double> out(z.size(), 0.0);
    for (int p = 0; p < h; ++p) {
      double* o = out.data() + static_cast<std::size_t>(p) * W;
      for (int q = std::max(0, p - radius); q <= std::min(h - 1, p + radius); ++q) {
        const double k = kernel[static_cast<std::size_t>(q - p + radius)] * norm[static_cast<std::size_t>(p)];
        const double* in = z.data() + static_cast<std::size_t>(q) * W;
        for (std::size_t x = 0; x < W; ++x) o[x] += k * in[x];
      }
    }
    z.swap(out);
  }
}

// Blurs white noise of unit variance per cell and rescales every cell to unit variance again
// (exactly in expectation: the factor is the kernel's own, border truncation included).
void blur_unit_noise(std::vector<double>& z, int w, int h, double sigma_cells) {
  std::vector<double> sqx, sqy;
  blur_axis(z, w, h, sigma_cells, true, sqx);
  blur_axis(z, w, h, sigma_cells, false, sqy);
  const std::size_t W = static_cast<std::size_t>(w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      z[static_cast<std::size_t>(y) * W + static_cast<std::size_t>(x)] /=
          std::sqrt(sqx[static_cast<std::size_t>(x)] * sqy[static_cast<std::size_t>(y)]);
}

ElevationMap map_from_heights(const GridGeometry& g, const std::vector<double>& z) {
  ElevationMap map(g);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) map.set_height(x, y, z[g.index(x, y)]);
  return map;
}

void validate_feature(const TerrainFeature& f) {
  if (!std::isfinite(f.centre.x()) || !std::isfinite(f.centre.y())) throw Error("must be finite", {}, 0, "centre");
  require_positive(f.radius_m, "radius_m");
  require_positive(f.depth_m, "depth_m");
}

constexpr int kBlockRows = 8;   // rows per block of the directional synthesis
constexpr int kBlockCols = 64;  // columns per block

// acc[r][j] += u_t,r * s_t[j] + v_t,r * c_t[j] for t = 0 .. T-1 in order. Cloned for AVX2 (no
// FMA): the same operations in the same order per cell as the baseline SSE2 code, so both give
// identical bits, twice as fast where AVX2 exists.
__attribute__((target_clones("avx2", "default"))) void accumulate_block(const double* sblock, const double* cblock,
                                                                         const double* coef, std::size_t T,
                                                                         double (*acc)[kBlockCols]) {
  for (std::size_t t = 0; t < T; ++t) {
    const double* __restrict s = sblock + t * kBlockCols;
    const double* __restrict c = cblock + t * kBlockCols;
    const double* p = coef + t * kBlockRows * 2;
    for (int r = 0; r < kBlockRows; ++r) {
      const double u = p[2 * r], v = p[2 * r + 1];
      double* __restrict a = acc[r];
      for (int j = 0; j < kBlockCols; ++j) a[j] += u * s[j] + v * c[j];
    }
  }
}

// Directional synthesis: q(x, y) = sum_t amp_t sin(kx_t x + ky_t y + theta_t) computed as
// sum_t (amp_t cos(ky_t y)) sin(kx_t x + theta_t) + (amp_t sin(ky_t y)) cos(kx_t x + theta_t):
// a matrix product of row tables (H x 2T) and column tables (2T x W), blocked so that a
// column block of the tables stays in cache while all rows use it. Every cell accumulates its
// terms in ascending t, so the result does not depend on the blocking.
void synthesize_directional(const std::vector<double>& amp, const std::vector<double>& kx, const std::vector<double>& ky,
                            const std::vector<double>& theta, int w, int h, double res, std::vector<double>& out) {
  constexpr int kRows = kBlockRows;
  constexpr int kCols = kBlockCols;
  const std::size_t T = amp.size();
  const int col_blocks = (w + kCols - 1) / kCols;
  const int row_blocks = (h + kRows - 1) / kRows;
  // Column tables per column block: [block][t][j] with j < kCols (zero padded).
  std::vector<double> sx(static_cast<std::size_t>(col_blocks) * T * kCols, 0.0);
  std::vector<double> cx(sx.size(), 0.0);
  for (int b = 0; b < col_blocks; ++b)
    for (std::size_t t = 0; t < T; ++t) {
      double* s = sx.data() + (static_cast<std::size_t>(b) * T + t) * kCols;
      double* c = cx.data() + (static_cast<std::size_t>(b) * T + t) * kCols;
      for (int j = 0; j < kCols; ++j) {
        const int x = b * kCols + j;
        if (x >= w) break;
        const double ph = kx[t] * ((x + 0.5) * res) + theta[t];
        s[j] = std::sin(ph);
        c[j] = std::cos(ph);
      }
    }
  // Row tables per row block: [block][t][r] pairs (amp cos(ky y), amp sin(ky y)).
  std::vector<double> uv(static_cast<std::size_t>(row_blocks) * T * kRows * 2, 0.0);
  for (int b = 0; b < row_blocks; ++b)
    for (std::size_t t = 0; t < T; ++t) {
      double* p = uv.data() + (static_cast<std::size_t>(b) * T + t) * kRows * 2;
      for (int r = 0; r < kRows; ++r) {
        const int y = b * kRows + r;
        if (y >= h) break;
        const double ph = ky[t] * ((y + 0.5) * res);
        p[2 * r] = amp[t] * std::cos(ph);
        p[2 * r + 1] = amp[t] * std::sin(ph);
      }
    }
  out.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0);
  alignas(64) double acc[kRows][kCols];
  for (int cb = 0; cb < col_blocks; ++cb) {
    const double* sblock = sx.data() + static_cast<std::size_t>(cb) * T * kCols;
    const double* cblock = cx.data() + static_cast<std::size_t>(cb) * T * kCols;
    for (int rb = 0; rb < row_blocks; ++rb) {
      for (auto& row : acc) std::fill(row, row + kCols, 0.0);
      accumulate_block(sblock, cblock, uv.data() + static_cast<std::size_t>(rb) * T * kRows * 2, T, acc);
      for (int r = 0; r < kRows; ++r) {
        const int y = rb * kRows + r;
        if (y >= h) break;
        const int x0 = cb * kCols;
        const int n = std::min(kCols, w - x0);
        std::copy(acc[r], acc[r] + n, out.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x0);
      }
    }
  }
}

}  // namespace

GridGeometry terrain_geometry(double width_m, double height_m, double resolution, const Pose2& origin) {
  if (!std::isfinite(resolution) || !(resolution > 0.0)) throw Error("must be a finite number > 0", {}, 0, "resolution");
  if (!std::isfinite(width_m) || !std::isfinite(height_m) || !(width_m > 0.0) || !(height_m > 0.0))
    throw Error("width and height must be finite numbers > 0", {}, 0, "size_m");
  const double wc = std::round(width_m / resolution), hc = std::round(height_m / resolution);
  if (wc < 1.0 || hc < 1.0) throw Error("the map must be at least one cell on each side", {}, 0, "size_m");
  if (wc * hc > 2147483647.0) throw Error("too many cells", {}, 0, "size_m");
  GridGeometry g;
  g.width = static_cast<int>(wc);
  g.height = static_cast<int>(hc);
  g.resolution = resolution;
  g.origin = origin;
  validate_geometry(g, "terrain");
  return g;
}

void add_terrain_feature(ElevationMap& map, const TerrainFeature& f) {
  validate_feature(f);
  const GridGeometry& g = map.geometry();
  const Vec2 c = g.world_to_grid(f.centre);  // grid frame, metres
  const double res = g.resolution;
  const int x0 = std::max(0, static_cast<int>(std::floor((c.x() - f.radius_m) / res)) - 1);
  const int x1 = std::min(g.width - 1, static_cast<int>(std::ceil((c.x() + f.radius_m) / res)) + 1);
  const int y0 = std::max(0, static_cast<int>(std::floor((c.y() - f.radius_m) / res)) - 1);
  const int y1 = std::min(g.height - 1, static_cast<int>(std::ceil((c.y() + f.radius_m) / res)) + 1);
  const double sign = f.kind == TerrainFeature::Kind::Pit ? -1.0 : 1.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      if (!map.observed_at(x, y)) continue;
      const double r = std::hypot((x + 0.5) * res - c.x(), (y + 0.5) * res - c.y());
      if (!(r < f.radius_m)) continue;
      const double dz = sign * f.depth_m * 0.5 * (1.0 + std::cos(kPi * r / f.radius_m));
      const double z = map.height_at(x, y) + dz;
      map.set_cell(x, y, z, std::min(z, map.min_height_at(x, y) + dz), std::max(z, map.max_height_at(x, y) + dz));
    }
}

// ---- hills -----------------------------------------------------------------------------------------

namespace {

// Elementary operations of blur_unit_noise on a w x h grid: a pass along each axis, each cell
// weighing the 2 radius + 1 taps of blur_axis's kernel.
double blur_operations(int w, int h, double sigma_cells) {
  if (!(sigma_cells > 0.0)) return 0.0;
  const double taps_x = 2.0 * blur_radius(sigma_cells, w) + 1.0;
  const double taps_y = 2.0 * blur_radius(sigma_cells, h) + 1.0;
  return static_cast<double>(w) * h * (taps_x + taps_y);
}

constexpr double kMaxHills = 1e7;  // the count is an int

// Refuses, before any work, a generation estimated above kMaxTerrainGenerationOperations.
void check_generation_work(double operations, const std::string& how, const char* field) {
  if (operations <= kMaxTerrainGenerationOperations) return;
  throw Error("the terrain would take about " + format_number(operations) + " operations (" + how + "), more than the " +
                  format_number(kMaxTerrainGenerationOperations) + " a generation may plan",
              {}, 0, field);
}

}  // namespace

void HillsOptions::validate() const {
  const GridGeometry g = terrain_geometry(width_m, height_m, resolution, origin);
  require_non_negative(amplitude, "amplitude");
  require_non_negative(hills_per_100m2, "hills_per_100m2");
  require_non_negative(hill_height_min_m, "hill_height_min_m");
  require_non_negative(hill_height_max_m, "hill_height_max_m");
  if (hill_height_max_m < hill_height_min_m) throw Error("must be >= hill_height_min_m", {}, 0, "hill_height_max_m");
  require_positive(hill_sigma_min_m, "hill_sigma_min_m");
  require_positive(hill_sigma_max_m, "hill_sigma_max_m");
  if (hill_sigma_max_m < hill_sigma_min_m) throw Error("must be >= hill_sigma_min_m", {}, 0, "hill_sigma_max_m");
  require_non_negative(roughness_m, "roughness_m");
  require_non_negative(roughness_correlation_m, "roughness_correlation_m");
  for (const auto& f : features) validate_feature(f);
  // Each hill touches the cells within 5 sigma; the roughness is one blur of the whole map.
  const double hills = std::max(1.0, std::round(hills_per_100m2 * g.width_m() * g.height_m() / 100.0));
  if (!(hills <= kMaxHills))
    throw Error("makes " + format_number(hills) + " hills on this map, more than " + format_number(kMaxHills), {}, 0,
                "hills_per_100m2");
  const double reach_cells = std::min(10.0 * hill_sigma_max_m / g.resolution + 1.0, static_cast<double>(std::max(g.width, g.height)));
  check_generation_work(hills * reach_cells * reach_cells, format_number(hills) + " hills of up to " +
                                                               format_number(std::round(reach_cells)) + " cells across",
                        "hills_per_100m2");
  if (roughness_m > 0.0)
    check_generation_work(blur_operations(g.width, g.height, roughness_correlation_m / g.resolution),
                          "the roughness blur over " + std::to_string(g.cell_count()) + " cells", "roughness_correlation_m");
}

ElevationMap generate_hills(const HillsOptions& o) {
  o.validate();
  const GridGeometry g = terrain_geometry(o.width_m, o.height_m, o.resolution, o.origin);
  const int w = g.width, h = g.height;
  const double res = g.resolution;
  const std::size_t W = static_cast<std::size_t>(w);
  std::vector<double> z(g.cell_count(), 0.0);
  const Rng root(o.seed);
  // Hills: centre (uniform over the map), height and sigma (uniform in their ranges), in that
  // order per hill, from one sub-stream; roughness from another.
  Rng hill_rng = root.fork(1);
  const double area = g.width_m() * g.height_m();
  const int count = std::max(1, static_cast<int>(std::lround(o.hills_per_100m2 * area / 100.0)));
  std::vector<double> ex, ey;
  for (int i = 0; i < count; ++i) {
    const double cx = hill_rng.uniform(0.0, g.width_m());
    const double cy = hill_rng.uniform(0.0, g.height_m());
    const double height = hill_rng.uniform(o.hill_height_min_m, o.hill_height_max_m);
    const double sigma = hill_rng.uniform(o.hill_sigma_min_m, o.hill_sigma_max_m);
    const double reach = 5.0 * sigma;  // exp(-12.5) ~ 4e-6 of the height beyond
    const int x0 = std::max(0, static_cast<int>(std::floor((cx - reach) / res)));
    const int x1 = std::min(w - 1, static_cast<int>(std::ceil((cx + reach) / res)));
    const int y0 = std::max(0, static_cast<int>(std::floor((cy - reach) / res)));
    const int y1 = std::min(h - 1, static_cast<int>(std::ceil((cy + reach) / res)));
    if (x1 < x0 || y1 < y0) continue;
    ex.resize(static_cast<std::size_t>(x1 - x0 + 1));
    ey.resize(static_cast<std::size_t>(y1 - y0 + 1));
    const double inv = 1.0 / (2.0 * sigma * sigma);
    for (int x = x0; x <= x1; ++x) {
      const double d = (x + 0.5) * res - cx;
      ex[static_cast<std::size_t>(x - x0)] = std::exp(-d * d * inv);
    }
    for (int y = y0; y <= y1; ++y) {
      const double d = (y + 0.5) * res - cy;
      ey[static_cast<std::size_t>(y - y0)] = height * std::exp(-d * d * inv);
    }
    for (int y = y0; y <= y1; ++y) {
      double* row = z.data() + static_cast<std::size_t>(y) * W;
      const double a = ey[static_cast<std::size_t>(y - y0)];
      for (int x = x0; x <= x1; ++x) row[x] += a * ex[static_cast<std::size_t>(x - x0)];
    }
  }
  if (o.roughness_m > 0.0) {
    Rng rough_rng = root.fork(2);
    std::vector<double> noise(z.size());
    for (double& v : noise) v = rough_rng.normal();
    blur_unit_noise(noise, w, h, o.roughness_correlation_m / res);
    for (std::size_t i = 0; i < z.size(); ++i) z[i] += o.roughness_m * noise[i];
  }
  for (double& v : z) v *= o.amplitude;
  ElevationMap map = map_from_heights(g, z);
  for (const auto& f : o.features) add_terrain_feature(map, f);
  return map;
}

// ---- road ------------------------------------------------------------------------------------------

const char* road_method_name(RoadMethod m) { return m == RoadMethod::Paper ? "paper" : "directional"; }

RoadMethod parse_road_method(const std::string& name, const std::string& field) {
  if (name == "directional") return RoadMethod::Directional;
  if (name == "paper") return RoadMethod::Paper;
  throw Error("unknown method '" + name + "' (directional, paper)", {}, 0, field);
}

double road_class_gd_n0(char road_class, const std::string& field) {
  const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(road_class)));
  if (c < 'A' || c > 'H') throw Error(std::string("unknown road class '") + road_class + "' (A..H)", {}, 0, field);
  // 16e-6 m^3 for A, times 4 per class.
  return 16e-6 * std::pow(4.0, c - 'A');
}

void RoadOptions::validate() const {
  const GridGeometry g = terrain_geometry(width_m, height_m, resolution, origin);
  if (gd_n0 == 0.0) road_class_gd_n0(road_class);
  else require_positive(gd_n0, "gd_n0");
  require_positive(n0, "n0");
  require_positive(n1, "n1");
  require_positive(n2, "n2");
  if (!(n2 > n1)) throw Error("must be greater than n1", {}, 0, "n2");
  require_positive(waviness, "waviness");
  if (intervals < 1 || intervals > kMaxRoadIntervals)
    throw Error("must be 1.." + std::to_string(kMaxRoadIntervals), {}, 0, "intervals");
  if (directions < 1 || directions > kMaxRoadDirections)
    throw Error("must be 1.." + std::to_string(kMaxRoadDirections), {}, 0, "directions");
  require_non_negative(blur_sigma_cells, "blur_sigma_cells");
  {
    // A blur wider than the map is its mean: a sigma beyond the larger side is a mistake.
    const int side = std::max(g.width, g.height);
    if (blur_sigma_cells > side)
      throw Error("must be at most the map's larger side, " + std::to_string(side) + " cells", {}, 0, "blur_sigma_cells");
    // Directional: a sine per cell, interval and direction; paper: a sine per cell and interval, then the blur.
    const double cells = static_cast<double>(g.cell_count());
    if (method == RoadMethod::Directional)
      check_generation_work(cells * intervals * directions,
                            std::to_string(g.cell_count()) + " cells x " + std::to_string(intervals) + " intervals x " +
                                std::to_string(directions) + " directions",
                            "directions");
    else
      check_generation_work(cells * intervals + blur_operations(g.width, g.height, blur_sigma_cells),
                            std::to_string(g.cell_count()) + " cells x " + std::to_string(intervals) + " intervals, and the blur",
                            "intervals");
  }
  for (const auto& f : features) validate_feature(f);
}

double RoadSpectrum::gd(double n) const { return gd_n0 * std::pow(n / n0, -waviness); }

RoadSpectrum road_spectrum(const RoadOptions& o, int width_cells, int height_cells) {
  RoadSpectrum sp;
  sp.gd_n0 = o.gd_n0 > 0.0 ? o.gd_n0 : road_class_gd_n0(o.road_class);
  sp.n0 = o.n0;
  sp.waviness = o.waviness;
  const double shorter = std::min(width_cells, height_cells) * o.resolution;
  sp.n_low = std::max(o.n1, 1.0 / shorter);
  sp.n_high = std::min(o.n2, 1.0 / (2.0 * o.resolution));
  if (!(sp.n_high > sp.n_low))
    throw Error("the band [" + format_number(o.n1) + ", " + format_number(o.n2) + "] 1/m clipped to the map (1/L = " +
                    format_number(1.0 / shorter) + ", 1/(2 res) = " + format_number(1.0 / (2.0 * o.resolution)) +
                    ") is empty: the map is too small or too coarse",
                {}, 0, "size_m");
  const int m = o.intervals;
  const double ratio = sp.n_high / sp.n_low;
  sp.centres.resize(static_cast<std::size_t>(m));
  sp.widths.resize(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    const double lo = i == 0 ? sp.n_low : sp.n_low * std::pow(ratio, static_cast<double>(i) / m);
    const double hi = i == m - 1 ? sp.n_high : sp.n_low * std::pow(ratio, static_cast<double>(i + 1) / m);
    sp.centres[static_cast<std::size_t>(i)] = 0.5 * (lo + hi);
    sp.widths[static_cast<std::size_t>(i)] = hi - lo;
    sp.sigma2 += sp.gd(sp.centres[static_cast<std::size_t>(i)]) * (hi - lo);
  }
  return sp;
}

RoadTerrain generate_road(const RoadOptions& o) {
  o.validate();
  const GridGeometry g = terrain_geometry(o.width_m, o.height_m, o.resolution, o.origin);
  RoadTerrain out{ElevationMap{}, road_spectrum(o, g.width, g.height)};
  const RoadSpectrum& sp = out.spectrum;
  const int w = g.width, h = g.height;
  const double res = g.resolution;
  const std::size_t m = sp.centres.size();
  Rng rng(o.seed);
  std::vector<double> z;
  if (o.method == RoadMethod::Directional) {
    // Terms t = i * K + k: interval i, direction psi_k = pi k / K; phases drawn in that order.
    const std::size_t K = static_cast<std::size_t>(o.directions);
    std::vector<double> amp(m * K), kx(m * K), ky(m * K), theta(m * K);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = 0; k < K; ++k) {
        const std::size_t t = i * K + k;
        const double psi = kPi * static_cast<double>(k) / static_cast<double>(K);
        const double n = sp.centres[i];
        amp[t] = std::sqrt(2.0 * sp.gd(n) * sp.widths[i] / static_cast<double>(K));
        kx[t] = 2.0 * kPi * n * std::cos(psi);
        ky[t] = 2.0 * kPi * n * std::sin(psi);
        theta[t] = 2.0 * kPi * rng.uniform();
      }
    synthesize_directional(amp, kx, ky, theta, w, h, res, z);
  } else {
    // The paper's recipe: q(x, y) = sum_i sqrt(2 Gd(n_i) dn_i) sin(2 pi n_i x + theta_i(x, y)),
    // a fresh phase per cell and interval (drawn row by row, cell by cell, interval by
    // interval), then a Gaussian blur, rescaled so every cell has variance sigma^2 again.
    std::vector<double> amp(m), k(m);
    for (std::size_t i = 0; i < m; ++i) {
      amp[i] = std::sqrt(2.0 * sp.gd(sp.centres[i]) * sp.widths[i]);
      k[i] = 2.0 * kPi * sp.centres[i];
    }
    z.assign(g.cell_count(), 0.0);
    const double inv_sigma = 1.0 / std::sqrt(sp.sigma2);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double xm = (x + 0.5) * res;
        double q = 0.0;
        for (std::size_t i = 0; i < m; ++i) q += amp[i] * std::sin(k[i] * xm + 2.0 * kPi * rng.uniform());
        z[g.index(x, y)] = q * inv_sigma;  // unit variance per cell
      }
    blur_unit_noise(z, w, h, o.blur_sigma_cells);
    const double sigma = std::sqrt(sp.sigma2);
    for (double& v : z) v *= sigma;
  }
  out.map = map_from_heights(g, z);
  for (const auto& f : o.features) add_terrain_feature(out.map, f);
  return out;
}

// ---- declared parameters ---------------------------------------------------------------------

namespace {

// The grid, the seed and the origin every generator takes.
template <class O>
void declare_terrain_grid(ParamTable<O>& t) {
  t.real("width_m", &O::width_m, positive(), "m", "size of the map along x");
  t.real("height_m", &O::height_m, positive(), "m", "size of the map along y");
  t.real("resolution", &O::resolution, positive(), "m", "metres per cell");
  t.integer("seed", &O::seed, non_negative(), "", "the seed of every random draw (same seed, same heights)");
  t.real("origin_x_m", [](O& o) -> double& { return o.origin.x; }, any_value(), "m", "world x of the map's lower-left corner");
  t.real("origin_y_m", [](O& o) -> double& { return o.origin.y; }, any_value(), "m", "world y of the map's lower-left corner");
  t.real("origin_yaw_deg", [](O& o) -> double& { return o.origin.yaw; }, any_value(), "deg", "the map's yaw about that corner",
         kPi / 180.0);
}

}  // namespace

const ParamTable<HillsOptions>& hills_params() {
  static const ParamTable<HillsOptions> table = [] {
    using O = HillsOptions;
    ParamTable<O> t;
    declare_terrain_grid(t);
    t.real("amplitude", &O::amplitude, non_negative(), "", "multiplies every height (hills and roughness)");
    t.real("hills_per_100m2", &O::hills_per_100m2, non_negative(), "", "hills per 100 m^2 (at least one hill)");
    t.real("hill_height_min_m", &O::hill_height_min_m, non_negative(), "m", "lowest hill");
    t.real("hill_height_max_m", &O::hill_height_max_m, non_negative(), "m", "highest hill");
    t.real("hill_sigma_min_m", &O::hill_sigma_min_m, positive(), "m", "narrowest hill's Gaussian sigma");
    t.real("hill_sigma_max_m", &O::hill_sigma_max_m, positive(), "m", "widest hill's Gaussian sigma");
    t.real("roughness_m", &O::roughness_m, non_negative(), "m", "standard deviation of the small-scale roughness");
    t.real("roughness_correlation_m", &O::roughness_correlation_m, non_negative(), "m",
           "Gaussian blur sigma of the roughness noise");
    return t;
  }();
  return table;
}

const ParamTable<RoadOptions>& road_params() {
  static const ParamTable<RoadOptions> table = [] {
    using O = RoadOptions;
    ParamTable<O> t;
    declare_terrain_grid(t);
    t.choice(
        "road_class", {"A", "B", "C", "D", "E", "F", "G", "H"}, [](O& o, const std::string& v) { o.road_class = v[0]; },
        [](const O& o) { return std::string(1, o.road_class); }, "road-roughness class (ISO 8608 / GB/T 7031)");
    t.real("gd_n0", &O::gd_n0, non_negative(), "m^3", "Gd(n0) of the PSD (0: the class's geometric mean)");
    t.choice(
        "method", {"directional", "paper"}, [](O& o, const std::string& v) { o.method = parse_road_method(v); },
        [](const O& o) { return std::string(road_method_name(o.method)); },
        "directional: plane waves in several directions; paper: per-cell random phase, blurred");
    t.real("n0", &O::n0, positive(), "1/m", "reference spatial frequency");
    t.real("n1", &O::n1, positive(), "1/m", "lower edge of the frequency band");
    t.real("n2", &O::n2, positive(), "1/m", "upper edge of the frequency band");
    t.real("waviness", &O::waviness, positive(), "", "the PSD's exponent W");
    t.integer("intervals", &O::intervals, closed(1, kMaxRoadIntervals), "", "log-spaced frequency intervals");
    t.integer("directions", &O::directions, closed(1, kMaxRoadDirections), "", "wave directions (directional)");
    t.real("blur_sigma_cells", &O::blur_sigma_cells, non_negative(), "cells", "Gaussian blur sigma (paper)");
    return t;
  }();
  return table;
}

}  // namespace starnav
