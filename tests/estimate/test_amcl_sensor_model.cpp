// AMCL's laser models against independent truths: the likelihood field's distances against brute
// force over every occupied cell (to centres and to squares, clamped, off the map, with a rotated
// map origin), one particle's weight computed by hand, the beam model's expected range against
// brute-force ray sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "estimate/amcl_test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl_sensor_model.hpp"

namespace starnav {
namespace {

using amcl_test::brute_obstacle_distance;

// A random map with every kind of cell: free, occupied, unknown, in between (occupied by the
// default thresholds) and low values (free); a rotated, shifted origin.
OccupancyGrid amcl_sensor_test_grid(int w, int h, double res, double occupied_share, std::uint64_t seed) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = Pose2(1.5, -2.0, 0.4);
  OccupancyGrid grid(g, kFreeOccupancy);
  Rng rng(seed);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      const double u = rng.uniform();
      std::int8_t v = kFreeOccupancy;
      if (u < occupied_share) v = kOccupiedOccupancy;
      else if (u < occupied_share * 1.3) v = 40;   // between the thresholds: occupied
      else if (u < occupied_share * 1.6) v = kUnknownOccupancy;
      else if (u < occupied_share * 2.0) v = 10;   // free
      grid(ix, iy) = v;
    }
  return grid;
}

void amcl_expect_field_matches_brute_force(const OccupancyGrid& grid, FieldReference reference, double max_dist) {
  const OccupancyThresholds t;
  LikelihoodFieldConfig c;
  c.max_dist_m = max_dist;
  c.range_max_m = 12.0;
  c.reference = reference;
  const LikelihoodField field(grid, t, c);
  const GridGeometry& g = grid.geometry();
  const bool surface = reference == FieldReference::Surface;
  int clamped = 0, exact_zero = 0;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Vec2 centre = g.cell_center(ix, iy);
      const double truth = std::min(brute_obstacle_distance(grid, t, centre, surface), max_dist);
      clamped += truth == max_dist;
      exact_zero += truth == 0.0;
      ASSERT_NEAR(field.distance_m(centre), truth, 2e-6) << ix << "," << iy;
      const double pz = c.z_hit * std::exp(-truth * truth / (2 * c.sigma_hit_m * c.sigma_hit_m)) + c.z_rand / c.range_max_m;
      ASSERT_NEAR(field.term(centre), pz * pz * pz, 1e-6 * pz * pz * pz + 1e-7);
      // Anywhere inside the cell the cell's value (nearest-cell lookup).
      const Vec2 inside = g.grid_to_world({(ix + 0.9) * g.resolution, (iy + 0.1) * g.resolution});
      ASSERT_EQ(field.distance_m(inside), field.distance_m(centre));
    }
  EXPECT_GT(clamped, 0);
  EXPECT_GT(exact_zero, 0);
  // Off the map: max_dist.
  for (const Vec2& off : {g.grid_to_world({-0.01, 0.5}), g.grid_to_world({g.width_m() + 0.01, 0.5}),
                         g.grid_to_world({0.5, -1.0}), g.grid_to_world({0.5, g.height_m() + 3.0})}) {
    EXPECT_EQ(field.distance_m(off), max_dist);
    EXPECT_NEAR(field.term(off), field.term_at_distance(max_dist), 1e-7);
  }
}

TEST(LikelihoodField, CentreDistancesMatchBruteForce) {
  amcl_expect_field_matches_brute_force(amcl_sensor_test_grid(37, 23, 0.1, 0.03, 1), FieldReference::Centre, 0.7);
}

TEST(LikelihoodField, SurfaceDistancesMatchBruteForce) {
  amcl_expect_field_matches_brute_force(amcl_sensor_test_grid(37, 23, 0.1, 0.03, 1), FieldReference::Surface, 0.7);
}

// Sparse obstacles and a long clamp: the nearest square is often not the nearest centre's square.
TEST(LikelihoodField, SurfaceDistancesMatchBruteForceFarFromSparseObstacles) {
  amcl_expect_field_matches_brute_force(amcl_sensor_test_grid(61, 47, 0.05, 0.004, 7), FieldReference::Surface, 0.6);
  amcl_expect_field_matches_brute_force(amcl_sensor_test_grid(61, 47, 0.05, 0.004, 7), FieldReference::Centre, 0.6);
}

// Occupied cells 7 columns right of a cell and 5 right, 5 up: the centre at (7, 0) is nearer
// (7 < 7.07 cells), but the square at (5, 5) is (4.5^2 + 4.5^2)^(1/2) = 6.36 < 6.5 cells away.
TEST(LikelihoodField, SurfaceIsNotTheNearestCentresSquare) {
  GridGeometry g;
  g.width = 20;
  g.height = 12;
  g.resolution = 0.1;
  OccupancyGrid grid(g, kFreeOccupancy);
  grid(9, 2) = kOccupiedOccupancy;
  grid(7, 7) = kOccupiedOccupancy;
  LikelihoodFieldConfig c;
  c.reference = FieldReference::Surface;
  const LikelihoodField field(grid, {}, c);
  EXPECT_NEAR(field.distance_m(g.cell_center(2, 2)), std::hypot(4.5, 4.5) * 0.1, 1e-6);
  c.reference = FieldReference::Centre;
  EXPECT_NEAR(LikelihoodField(grid, {}, c).distance_m(g.cell_center(2, 2)), 0.7, 1e-6);
}

TEST(LikelihoodField, NoObstacleIsMaxDistanceEverywhere) {
  GridGeometry g;
  g.width = 9;
  g.height = 5;
  g.resolution = 0.2;
  OccupancyGrid grid(g, kFreeOccupancy);
  grid(3, 2) = kUnknownOccupancy;  // unknown is not an obstacle (Nav2 counts occupied cells only)
  for (const FieldReference ref : {FieldReference::Centre, FieldReference::Surface}) {
    LikelihoodFieldConfig c;
    c.reference = ref;
    const LikelihoodField field(grid, {}, c);
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix) EXPECT_EQ(field.distance_m(g.cell_center(ix, iy)), c.max_dist_m);
  }
}

TEST(LikelihoodField, RejectsImpossibleParameters) {
  const OccupancyGrid grid = amcl_sensor_test_grid(5, 5, 0.1, 0.1, 2);
  LikelihoodFieldConfig c;
  c.sigma_hit_m = 0.0;
  try {
    LikelihoodField f(grid, {}, c);
    FAIL() << "sigma 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "amcl.sigma_hit_m");
  }
  c = {};
  c.z_rand = -0.1;
  EXPECT_THROW(LikelihoodField(grid, {}, c), Error);
}

TEST(LikelihoodField, ModelBeamsSubsampleAsNav2) {
  PlanarScan s;
  s.range_min_m = 0.1;
  s.range_max_m = 10.0;
  for (int i = 0; i < 10; ++i) {
    s.ranges.push_back(1.0 + i);
    s.angles_rad.push_back(-0.1 * i);
  }
  s.ranges[3] = std::numeric_limits<double>::quiet_NaN();
  s.ranges[6] = 0.05;  // <= range_min
  // step = (10 - 1) / (4 - 1) = 3: beams 0, 3, 6, 9.
  const std::vector<ModelBeam> b = model_beams(s, 4, s.range_min_m, s.range_max_m);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[0].range_m, 1.0);
  EXPECT_EQ(b[1].range_m, 10.0);  // NaN: a non-return
  EXPECT_EQ(b[2].range_m, 10.0);  // short: a non-return (Nav2)
  EXPECT_EQ(b[3].range_m, 10.0);  // 10 >= range_max
  EXPECT_DOUBLE_EQ(b[3].bearing_rad, -0.9);
  // More beams asked than there are: every beam; step 9 / 59 = 0 becomes 1.
  EXPECT_EQ(model_beams(s, 60, s.range_min_m, s.range_max_m).size(), 10u);
  // n = 7, max_beams 3: step 3, beams 0 and 3 and 6.
  s.ranges.resize(7);
  s.angles_rad.resize(7);
  EXPECT_EQ(model_beams(s, 3, s.range_min_m, s.range_max_m).size(), 3u);
  EXPECT_THROW(model_beams(s, 1, 0.1, 10.0), Error);
}

// One particle weighed by hand: a robot pose, a laser mount and beams (two reach range_max: 4.0
// and 5.0 are non-returns), the field's settings, and per returning beam its pz from the brute-
// force distance of the end point's cell.
struct HandWeighing {
  OccupancyGrid grid = amcl_sensor_test_grid(37, 23, 0.1, 0.03, 3);
  OccupancyThresholds thresholds;
  LikelihoodFieldConfig config;
  Pose2 pose{2.3, -0.4, 2.1};
  Pose2 mount{0.12, -0.03, 0.3};
  std::vector<ModelBeam> beams = {{0.8, 0.0}, {1.7, 1.2}, {4.0, 0.5}, {2.9, -2.5}, {0.3, 3.0}, {5.0, -1.0}};

  HandWeighing() {
    config.max_dist_m = 0.6;
    config.sigma_hit_m = 0.15;
    config.z_hit = 0.7;
    config.z_rand = 0.3;
    config.range_max_m = 4.0;
    config.reference = FieldReference::Surface;
  }
  double pz_of(double d) const {
    return config.z_hit * std::exp(-d * d / (2 * config.sigma_hit_m * config.sigma_hit_m)) +
           config.z_rand / config.range_max_m;
  }
  std::vector<double> returning_pz() const {
    std::vector<double> pz;
    const Pose2 laser = pose.compose(mount);
    for (const ModelBeam& b : beams) {
      if (b.range_m >= config.range_max_m) continue;
      const Vec2 hit(laser.x + b.range_m * std::cos(laser.yaw + b.bearing_rad),
                     laser.y + b.range_m * std::sin(laser.yaw + b.bearing_rad));
      const auto cell = grid.geometry().world_to_cell(hit);
      const double d =
          cell ? std::min(brute_obstacle_distance(grid, thresholds, grid.geometry().cell_center(*cell), true), config.max_dist_m)
               : config.max_dist_m;
      pz.push_back(pz_of(d));
    }
    return pz;
  }
};

TEST(LikelihoodField, WeightOfOneParticleByHand) {
  const HandWeighing h;
  const LikelihoodField field(h.grid, h.thresholds, h.config);
  double expected = 1.0;
  for (const double pz : h.returning_pz()) expected += pz * pz * pz;
  EXPECT_NEAR(field.weight(h.pose, h.mount, h.beams), expected, 1e-6);
  // The batch form gives the same numbers.
  std::vector<Pose2> poses = {h.pose, Pose2(1.0, 1.0, -0.5), h.pose};
  std::vector<double> out(3);
  field.weigh(poses, h.mount, h.beams, out);
  EXPECT_EQ(out[0], field.weight(h.pose, h.mount, h.beams));
  EXPECT_EQ(out[2], out[0]);
  EXPECT_EQ(out[1], field.weight(poses[1], h.mount, h.beams));
  // No usable beam: p = 1.
  EXPECT_EQ(field.weight(h.pose, h.mount, std::vector<ModelBeam>{{4.0, 0.0}}), 1.0);
}

TEST(LikelihoodField, TemperedProductOfOneParticleByHand) {
  HandWeighing h;
  h.config.independent_beams = 3.0;
  const LikelihoodField field(h.grid, h.thresholds, h.config);
  // (prod pz / pz(0))^(k / n) over the n returning beams, multiplied out.
  const std::vector<double> pz = h.returning_pz();
  ASSERT_EQ(pz.size(), 4u);
  double product = 1.0;
  for (const double p : pz) product *= p / h.pz_of(0.0);
  const double expected = std::pow(product, h.config.independent_beams / static_cast<double>(pz.size()));
  EXPECT_NEAR(field.weight(h.pose, h.mount, h.beams), expected, 1e-5 * expected);
  EXPECT_LE(field.weight(h.pose, h.mount, h.beams), 1.0);  // a perfect fit weighs 1
  // Counting every beam twice is the same scan: the weight depends on k, not on the beam count.
  std::vector<ModelBeam> doubled = h.beams;
  doubled.insert(doubled.end(), h.beams.begin(), h.beams.end());
  EXPECT_NEAR(field.weight(h.pose, h.mount, doubled), expected, 1e-5 * expected);
  // No usable beam: p = 1.
  EXPECT_EQ(field.weight(h.pose, h.mount, std::vector<ModelBeam>{{4.0, 0.0}}), 1.0);
  // k is the exponent: twice k squares the weight.
  LikelihoodFieldConfig twice = h.config;
  twice.independent_beams = 6.0;
  const LikelihoodField field6(h.grid, h.thresholds, twice);
  EXPECT_NEAR(field6.weight(h.pose, h.mount, h.beams), expected * expected, 1e-5 * expected * expected);
}

TEST(LikelihoodField, TemperedProductRejectsImpossibleParameters) {
  const OccupancyGrid grid = amcl_sensor_test_grid(5, 5, 0.1, 0.1, 2);
  for (const double k : {-1.0, kMaxIndependentBeams + 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    LikelihoodFieldConfig c;
    c.independent_beams = k;
    try {
      LikelihoodField f(grid, {}, c);
      FAIL() << "independent_beams " << k << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "amcl.search_independent_beams");
    }
  }
  LikelihoodFieldConfig c;
  c.independent_beams = 3.0;
  c.z_hit = 0.0;
  c.z_rand = 0.0;
  EXPECT_THROW(LikelihoodField(grid, {}, c), Error);
}

TEST(LikelihoodField, RangeMaxChangesOnlyTheRandomTerm) {
  const OccupancyGrid grid = amcl_sensor_test_grid(20, 20, 0.1, 0.05, 4);
  LikelihoodFieldConfig c;
  c.range_max_m = 5.0;
  LikelihoodField field(grid, {}, c);
  const Vec2 p = grid.geometry().cell_center(7, 9);
  const double d = field.distance_m(p);
  field.set_range_max(20.0);
  EXPECT_EQ(field.distance_m(p), d);
  const double pz = c.z_hit * std::exp(-d * d / (2 * c.sigma_hit_m * c.sigma_hit_m)) + c.z_rand / 20.0;
  EXPECT_NEAR(field.term(p), pz * pz * pz, 1e-6 * pz * pz * pz);
}

// -------------------------------------------------------------------------------------------
// Beam model

// Marches along the ray in steps of `step` m until a cell that is not free or the map's edge.
double amcl_brute_expected_range(const OccupancyGrid& grid, const OccupancyThresholds& t, const Pose2& laser,
                            double range_max, double step) {
  const GridGeometry& g = grid.geometry();
  for (double s = 0.0; s < range_max; s += step) {
    const auto cell = g.world_to_cell({laser.x + s * std::cos(laser.yaw), laser.y + s * std::sin(laser.yaw)});
    if (!cell || t.classify(grid(cell->x, cell->y)) != CellState::Free) return s;
  }
  return range_max;
}

TEST(AmclBeamModel, ExpectedRangeMatchesBruteForceSampling) {
  const OccupancyGrid grid = amcl_sensor_test_grid(37, 23, 0.1, 0.03, 5);
  const OccupancyThresholds t;
  const BeamModel model(grid, t, {});
  const GridGeometry& g = grid.geometry();
  Rng rng(11);
  int hits = 0, maxed = 0, tested = 0;
  while (tested < 200) {
    const Vec2 p = g.grid_to_world({rng.uniform(0.0, g.width_m()), rng.uniform(0.0, g.height_m())});
    const Pose2 laser(p.x(), p.y(), rng.uniform(-kPi, kPi));
    const double range_max = rng.uniform(0.2, 3.0);
    const double step = 1e-4;
    const double truth = amcl_brute_expected_range(grid, t, laser, range_max, step);
    const double r = model.expected_range(laser, range_max);
    ASSERT_NEAR(r, truth, step + 1e-9) << tested;
    hits += truth < range_max;
    maxed += truth == range_max;
    ++tested;
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(maxed, 10);
  // Axis-aligned rays along the grid (exactly through corners and along lines).
  const Pose2 along_row = Pose2(g.grid_to_world({0.05, 0.05}).x(), g.grid_to_world({0.05, 0.05}).y(), g.origin.yaw);
  EXPECT_NEAR(model.expected_range(along_row, 5.0), amcl_brute_expected_range(grid, t, along_row, 5.0, 1e-5), 2e-5);
}

TEST(AmclBeamModel, WeightByHand) {
  const OccupancyGrid grid = amcl_sensor_test_grid(37, 23, 0.1, 0.03, 6);
  const OccupancyThresholds t;
  BeamModelConfig c;
  c.z_hit = 0.6;
  c.z_short = 0.1;
  c.z_max = 0.08;
  c.z_rand = 0.22;
  c.sigma_hit_m = 0.1;
  c.lambda_short = 0.5;
  const BeamModel model(grid, t, c);
  const double range_max = 3.0;
  // A free cell for the laser.
  Pose2 pose;
  for (int i = 0; i < grid.width() * grid.height(); ++i) {
    const Cell cell = grid.geometry().cell_of_index(static_cast<std::size_t>(i));
    if (cell.x > 5 && cell.y > 5 && t.classify(grid(cell.x, cell.y)) == CellState::Free) {
      const Vec2 w = grid.geometry().cell_center(cell);
      pose = Pose2(w.x(), w.y(), 0.7);
      break;
    }
  }
  const Pose2 mount(0.0, 0.0, -0.2);
  const std::vector<ModelBeam> beams = {{0.5, 0.0}, {2.0, 1.0}, {3.0, -1.5} /* non-return */, {0.05, 2.0}};
  double expected = 1.0;
  const Pose2 laser = pose.compose(mount);
  for (const ModelBeam& b : beams) {
    const Pose2 ray(laser.x, laser.y, laser.yaw + b.bearing_rad);
    const double zs = amcl_brute_expected_range(grid, t, ray, range_max, 1e-5);
    const double z = b.range_m;
    double pz = c.z_hit * std::exp(-(z - zs) * (z - zs) / (2 * c.sigma_hit_m * c.sigma_hit_m));
    if (z < zs) pz += c.z_short * c.lambda_short * std::exp(-c.lambda_short * z);
    pz += z >= range_max ? c.z_max : c.z_rand / range_max;
    expected += pz * pz * pz;
  }
  EXPECT_NEAR(model.weight(pose, mount, beams, range_max), expected, 1e-3);
}

}  // namespace
}  // namespace starnav
