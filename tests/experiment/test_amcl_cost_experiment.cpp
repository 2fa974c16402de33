// starnav bench amcl-cost's runner on a tiny grid of pairs: one row per pair in order, timings
// that order as min <= median <= max, the beams Nav2's subsampling uses, the derived rate, the
// pictures, and the checks of its flags.
#include <gtest/gtest.h>

#include <filesystem>

#include "starnav/core/error.hpp"
#include "starnav/experiment/amcl_cost_experiment.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(AmclCost, OneRowPerPairWithOrderedTimings) {
  AmclCostConfig c;
  c.map_file = test::scenario_path("maps/indoor_rooms.yaml");
  c.particles = {100, 300};
  c.beams = {10, 30};
  c.updates = 2;
  c.repeats = 3;
  const AmclCostResult r = run_amcl_cost(c);
  ASSERT_EQ(r.rows.size(), 4u);
  EXPECT_EQ(r.map_name, "indoor_rooms");
  EXPECT_NEAR(r.map_width_m, 24.0, 1e-9);
  // Nav2's subsampling of the 360-beam scan: step (360 - 1) / (b - 1) = 39 and 12, every step-th
  // beam from the first: 10 and 30 beams.
  const int expected_beams[2] = {10, 30};
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const AmclCostRow& row = r.rows[k];
    EXPECT_EQ(row.particles, c.particles[k / 2]);
    EXPECT_EQ(row.beams, expected_beams[k % 2]);
    EXPECT_GT(row.min_ms, 0.0);
    EXPECT_LE(row.min_ms, row.median_ms);
    EXPECT_LE(row.median_ms, row.max_ms);
    EXPECT_NEAR(row.ns_per_particle_beam, row.median_ms * 1e6 / (row.particles * row.beams), 1e-9);
  }
  EXPECT_NE(amcl_cost_markdown(r).find("| 300 | " + std::to_string(expected_beams[1]) + " | "), std::string::npos);
  EXPECT_EQ(amcl_cost_csv(r).find("particles,beams,median_ms"), 0u);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "starnav_test_amcl_cost";
  std::filesystem::create_directories(dir);
  write_amcl_cost_pictures(r, dir.string());
  EXPECT_TRUE(std::filesystem::exists(dir / "cost_vs_particles.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "cost_vs_beams.svg"));
  std::filesystem::remove_all(dir);
}

TEST(AmclCost, RefusesImpossibleFlags) {
  const auto flag_of = [](AmclCostConfig c) {
    try {
      c.validate();
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  AmclCostConfig c;
  EXPECT_EQ(flag_of(c), "(accepted)");
  AmclCostConfig p = c;
  p.particles = {0};
  EXPECT_EQ(flag_of(p), "--particles");
  p.particles = {};
  EXPECT_EQ(flag_of(p), "--particles");
  AmclCostConfig b = c;
  b.beams = {1};
  EXPECT_EQ(flag_of(b), "--beams");
  b.beams = {361};
  EXPECT_EQ(flag_of(b), "--beams");
  AmclCostConfig u = c;
  u.updates = 0;
  EXPECT_EQ(flag_of(u), "--updates");
  AmclCostConfig n = c;
  n.repeats = 0;
  EXPECT_EQ(flag_of(n), "--repeats");
  c.map_file = "/nonexistent/map.yaml";
  EXPECT_THROW(run_amcl_cost(c), Error);
}

}  // namespace
}  // namespace starnav
