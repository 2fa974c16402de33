// Terrain generators: road spectrum (band, sigma^2), variance over seeds, periodogram slope,
// determinism; hills; pits and mounds.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdlib>
#include <numbers>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "support/test_support.hpp"

namespace {

using namespace starnav;

using starnav::test::long_tests;

double mean_square(const ElevationMap& m) {
  long double s = 0;
  for (const double z : m.heights()) s += static_cast<long double>(z) * z;
  return static_cast<double>(s / static_cast<long double>(m.cell_count()));
}

// In-place radix-2 FFT (n a power of two).
void fft(std::vector<std::complex<double>>& a) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = -2 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1);
      for (std::size_t j = 0; j < len / 2; ++j) {
        const auto u = a[i + j], v = a[i + j + len / 2] * w;
        a[i + j] = u + v;
        a[i + j + len / 2] = u - v;
        w *= wl;
      }
    }
  }
}

TEST(RoadSpectrum, ClassValuesAndBand) {
  EXPECT_DOUBLE_EQ(road_class_gd_n0('A'), 16e-6);
  EXPECT_DOUBLE_EQ(road_class_gd_n0('C'), 256e-6);
  EXPECT_DOUBLE_EQ(road_class_gd_n0('h'), 262144e-6);
  EXPECT_THROW(road_class_gd_n0('I'), Error);
  RoadOptions o;
  o.resolution = 0.1;
  // 1000 x 1000 cells of 0.1 m: 1/L = 0.01 < n1, 1/(2 res) = 5 > n2: the band is kept.
  RoadSpectrum s = road_spectrum(o, 1000, 1000);
  EXPECT_EQ(s.n_low, 0.011);
  EXPECT_EQ(s.n_high, 2.83);
  // 100 x 50 cells: L = 5 m clips n1 to 0.2; at 0.25 m cells n2 is clipped to 2.
  s = road_spectrum(o, 100, 50);
  EXPECT_DOUBLE_EQ(s.n_low, 0.2);
  o.resolution = 0.25;
  s = road_spectrum(o, 100, 50);
  EXPECT_DOUBLE_EQ(s.n_low, 1.0 / 12.5);
  EXPECT_DOUBLE_EQ(s.n_high, 2.0);
  ASSERT_EQ(s.centres.size(), 64u);
  // Log-spaced edges, midpoints, sigma^2 = sum Gd dn: recomputed here, and close to the integral
  // Gd(n0) n0^2 (1/n_low - 1/n_high) for W = 2.
  double total = 0, lo = s.n_low;
  for (int i = 0; i < 64; ++i) {
    const double hi = s.n_low * std::pow(s.n_high / s.n_low, (i + 1) / 64.0);
    EXPECT_NEAR(s.widths[i], hi - lo, 1e-15);
    EXPECT_NEAR(s.centres[i], 0.5 * (lo + hi), 1e-15);
    total += 256e-6 * std::pow(s.centres[i] / 0.1, -2.0) * (hi - lo);
    lo = hi;
  }
  EXPECT_NEAR(s.sigma2, total, 1e-15);
  const double integral = 256e-6 * 0.01 * (1 / s.n_low - 1 / s.n_high);
  EXPECT_NEAR(s.sigma2 / integral, 1.0, 0.01);
  // A map too small for the band.
  o.resolution = 0.1;
  try {
    road_spectrum(o, 3, 3);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "size_m");
  }
}

// The mean square of the heights (the process has mean 0), averaged over seeds, against sigma^2.
// One realisation scatters around sigma^2 (most of the variance sits in the longest waves): on
// these maps the per-seed standard deviation is about 21 % for `directional` and 10 % for
// `paper`, so 160 and 48 seeds put 5 % at about three standard deviations of the average.
void check_variance_over_seeds(RoadMethod method, int seeds) {
  RoadOptions o;
  o.width_m = 6.4;
  o.height_m = 6.4;
  o.resolution = 0.1;
  o.road_class = 'D';
  o.method = method;
  double sum = 0, sigma2 = 0;
  for (int s = 0; s < seeds; ++s) {
    o.seed = static_cast<std::uint64_t>(1000 + s);
    const RoadTerrain t = generate_road(o);
    sigma2 = t.spectrum.sigma2;
    sum += mean_square(t.map);
  }
  const double mean = sum / seeds;
  EXPECT_NEAR(mean / sigma2, 1.0, 0.05) << road_method_name(method) << ": mean " << mean << " sigma2 " << sigma2;
}

TEST(RoadGenerator, DirectionalVarianceOverSeedsIsSigma2) {
  check_variance_over_seeds(RoadMethod::Directional, long_tests() ? 1000 : 160);
}

TEST(RoadGenerator, PaperVarianceOverSeedsIsSigma2) {
  check_variance_over_seeds(RoadMethod::Paper, long_tests() ? 400 : 48);
}

TEST(RoadGenerator, DirectionalPeriodogramFallsOffAsNToTheMinusTwo) {
  // Profiles along x (512 cells of 0.1 m, Hann window), averaged over rows and seeds; the
  // log-log slope over the middle decade of the clipped band must be -W = -2 within 0.3.
  RoadOptions o;
  o.width_m = 51.2;
  o.height_m = 12.8;
  o.resolution = 0.1;
  o.road_class = 'C';
  const int n = 512;
  std::vector<double> power(n / 2 + 1, 0.0), window(n);
  for (int i = 0; i < n; ++i) window[i] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * i / n);
  RoadSpectrum spectrum;
  const int seeds = long_tests() ? 60 : 12;
  for (int s = 0; s < seeds; ++s) {
    o.seed = static_cast<std::uint64_t>(s);
    const RoadTerrain t = generate_road(o);
    spectrum = t.spectrum;
    ASSERT_EQ(t.map.width(), n);
    for (int y = 0; y < t.map.height(); ++y) {
      std::vector<std::complex<double>> row(n);
      for (int x = 0; x < n; ++x) row[x] = t.map.height_at(x, y) * window[x];
      fft(row);
      for (int k = 0; k <= n / 2; ++k) power[k] += std::norm(row[k]);
    }
  }
  const double centre = std::sqrt(spectrum.n_low * spectrum.n_high);
  const double f_lo = centre / std::sqrt(10.0), f_hi = centre * std::sqrt(10.0);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (int k = 1; k <= n / 2; ++k) {
    const double f = k / o.width_m;
    if (f < f_lo || f > f_hi) continue;
    const double lx = std::log10(f), ly = std::log10(power[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    ++count;
  }
  ASSERT_GT(count, 20);
  const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
  EXPECT_NEAR(slope, -2.0, 0.3) << "band [" << spectrum.n_low << ", " << spectrum.n_high << "]";
}

TEST(RoadGenerator, SameSeedSameHeightsDifferentSeedsDiffer) {
  for (const auto method : {RoadMethod::Directional, RoadMethod::Paper}) {
    RoadOptions o;
    o.width_m = 6.4;
    o.height_m = 3.2;
    o.resolution = 0.1;
    o.method = method;
    o.seed = 42;
    const RoadTerrain a = generate_road(o), b = generate_road(o);
    EXPECT_EQ(a.map, b.map);
    o.seed = 43;
    const RoadTerrain c = generate_road(o);
    EXPECT_NE(a.map.heights(), c.map.heights());
    int differ = 0;
    for (std::size_t i = 0; i < a.map.cell_count(); ++i) differ += a.map.heights()[i] != c.map.heights()[i];
    EXPECT_GT(differ, static_cast<int>(a.map.cell_count() * 9 / 10));
  }
}

TEST(RoadGenerator, DirectionalEqualsTheDirectSum) {
  // The blocked product form must equal the plain double sum over terms, with phases drawn in
  // the documented order (interval-major, then direction).
  RoadOptions o;
  o.width_m = 7.3;  // not a multiple of the block sizes
  o.height_m = 2.1;
  o.resolution = 0.1;
  o.intervals = 5;
  o.directions = 3;
  o.seed = 9;
  const RoadTerrain t = generate_road(o);
  const RoadSpectrum& s = t.spectrum;
  Rng rng(9);
  std::vector<double> theta;
  for (int i = 0; i < 5 * 3; ++i) theta.push_back(2 * std::numbers::pi * rng.uniform());
  for (int y = 0; y < t.map.height(); ++y)
    for (int x = 0; x < t.map.width(); ++x) {
      const double xm = (x + 0.5) * 0.1, ym = (y + 0.5) * 0.1;
      double q = 0;
      for (int i = 0; i < 5; ++i)
        for (int k = 0; k < 3; ++k) {
          const double psi = std::numbers::pi * k / 3.0;
          const double n = s.centres[i];
          q += std::sqrt(2 * s.gd(n) * s.widths[i] / 3.0) *
               std::sin(2 * std::numbers::pi * n * (xm * std::cos(psi) + ym * std::sin(psi)) + theta[i * 3 + k]);
        }
      EXPECT_NEAR(t.map.height_at(x, y), q, 1e-12);
    }
}

TEST(TerrainFeatures, PitAndMound) {
  RoadOptions o;
  o.width_m = 10;
  o.height_m = 10;
  o.resolution = 0.1;
  o.seed = 3;
  const RoadTerrain plain = generate_road(o);
  o.features.push_back({TerrainFeature::Kind::Pit, Vec2(3.05, 3.05), 1.0, 0.4});
  o.features.push_back({TerrainFeature::Kind::Mound, Vec2(7.05, 7.05), 0.8, 0.3});
  const RoadTerrain with = generate_road(o);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const Vec2 c((x + 0.5) * 0.1, (y + 0.5) * 0.1);
      const double rp = (c - Vec2(3.05, 3.05)).norm(), rm = (c - Vec2(7.05, 7.05)).norm();
      double dz = 0;
      if (rp < 1.0) dz -= 0.4 * 0.5 * (1 + std::cos(std::numbers::pi * rp / 1.0));
      if (rm < 0.8) dz += 0.3 * 0.5 * (1 + std::cos(std::numbers::pi * rm / 0.8));
      EXPECT_NEAR(with.map.height_at(x, y) - plain.map.height_at(x, y), dz, 1e-12);
    }
  EXPECT_NEAR(with.map.height_at(30, 30) - plain.map.height_at(30, 30), -0.4, 1e-12);
  TerrainFeature bad;
  bad.radius_m = 0;
  ElevationMap m = plain.map;
  try {
    add_terrain_feature(m, bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "radius_m");
  }
}

TEST(HillsGenerator, DeterministicScaledAndHilly) {
  HillsOptions o;
  o.seed = 5;
  const ElevationMap a = generate_hills(o), b = generate_hills(o);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.width(), 100);
  EXPECT_EQ(a.height(), 100);
  o.amplitude = 2.0;
  const ElevationMap c = generate_hills(o);
  for (std::size_t i = 0; i < a.cell_count(); ++i) ASSERT_EQ(c.heights()[i], 2.0 * a.heights()[i]);
  o.amplitude = 1.0;
  o.seed = 6;
  const ElevationMap d = generate_hills(o);
  EXPECT_NE(a.heights(), d.heights());
  // Hills of 0.5-1.0 m: the relief is of that order (overlaps can add up).
  const auto range = a.height_range();
  ASSERT_TRUE(range);
  EXPECT_GT(range->max - range->min, 0.4);
  EXPECT_LT(range->max - range->min, 4.0);
  // Without roughness and with one hill of known height and width: a Gaussian.
  HillsOptions one;
  one.hills_per_100m2 = 0.0;  // max(1, 0) = one hill
  one.roughness_m = 0.0;
  one.hill_height_min_m = one.hill_height_max_m = 0.8;
  one.hill_sigma_min_m = one.hill_sigma_max_m = 1.0;
  const ElevationMap g = generate_hills(one);
  const auto r1 = g.height_range();
  EXPECT_LE(r1->max, 0.8 + 1e-12);
  EXPECT_GT(r1->max, 0.8 * std::exp(-0.5 * 0.0707 * 0.0707 * 2));  // a centre within half a cell diagonal
  EXPECT_GE(r1->min, 0.0);
}

TEST(HillsGenerator, BadOptionsNameTheField) {
  auto field_of = [](const HillsOptions& o) -> std::string {
    try {
      generate_hills(o);
    } catch (const Error& e) {
      return e.field();
    }
    return "";
  };
  HillsOptions o;
  o.resolution = 0;
  EXPECT_EQ(field_of(o), "resolution");
  o = {};
  o.width_m = -1;
  EXPECT_EQ(field_of(o), "size_m");
  o = {};
  o.width_m = 0.01;  // rounds to 0 cells
  EXPECT_EQ(field_of(o), "size_m");
  o = {};
  o.hill_sigma_max_m = 0.1;
  EXPECT_EQ(field_of(o), "hill_sigma_max_m");
  o = {};
  o.amplitude = -1;
  EXPECT_EQ(field_of(o), "amplitude");
}

}  // namespace
