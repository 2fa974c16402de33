// The scan proposal: which candidates it scores (every free block, every heading; a uniform
// subset above the limit), that its two-stage selection equals brute force when the first stage
// keeps everything, that the best candidate for a scan lies at the truth in a room where no pose
// looks like another, determinism, and the configuration's checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "estimate/amcl_test_support.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/scan_proposal.hpp"

namespace starnav {
namespace {

std::vector<std::int32_t> proposal_free_cells(const OccupancyGrid& grid) {
  std::vector<std::int32_t> cells;
  const OccupancyThresholds t;
  for (std::size_t i = 0; i < grid.cell_count(); ++i)
    if (t.classify(grid[i]) == CellState::Free) cells.push_back(static_cast<std::int32_t>(i));
  return cells;
}

const Pose2 kProposalMount(0.15, 0.02, 0.05);

TEST(ScanProposal, ScoresEveryFreeBlockAtEveryHeading) {
  const amcl_test::Room room = amcl_test::make_room();
  const std::vector<std::int32_t> free_cells = proposal_free_cells(room.grid);
  ScanProposalConfig c;
  c.spacing_m = 0.25;  // 5 x 5 cells
  c.yaw_step_rad = deg_to_rad(10.0);
  const ScanProposal proposal(room.grid.geometry(), free_cells, c);
  EXPECT_EQ(proposal.headings(), 36);
  // Brute force: the distinct 5 x 5 blocks that hold a free cell.
  std::set<std::pair<int, int>> blocks;
  for (const std::int32_t i : free_cells) {
    const Cell cell = room.grid.geometry().cell_of_index(static_cast<std::size_t>(i));
    blocks.insert({cell.x / 5, cell.y / 5});
  }
  ASSERT_EQ(proposal.blocks(), blocks.size());
  Rng rng(3);
  const std::vector<Pose2> all = proposal.candidates(rng, 100'000'000);
  ASSERT_EQ(all.size(), blocks.size() * 36);
  std::set<std::pair<int, int>> seen;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const Pose2& first = all[b * 36];
    const Vec2 g = room.grid.geometry().world_to_cell_continuous(first.translation());
    const int cx = static_cast<int>(std::floor(g.x())), cy = static_cast<int>(std::floor(g.y()));
    ASSERT_TRUE(room.grid.geometry().contains(cx, cy));
    EXPECT_EQ(OccupancyThresholds().classify(room.grid(cx, cy)), CellState::Free);
    seen.insert({cx / 5, cy / 5});
    for (int h = 0; h < 36; ++h) {
      const Pose2& p = all[b * 36 + static_cast<std::size_t>(h)];
      EXPECT_EQ(p.x, first.x);
      EXPECT_EQ(p.y, first.y);
      EXPECT_NEAR(angle_diff(p.yaw, first.yaw), wrap_angle(h * deg_to_rad(10.0)), 1e-9);
    }
  }
  EXPECT_EQ(seen, blocks);
}

TEST(ScanProposal, ScoresAUniformSubsetAboveTheLimit) {
  const amcl_test::Room room = amcl_test::make_room();
  ScanProposalConfig c;
  const ScanProposal proposal(room.grid.geometry(), proposal_free_cells(room.grid), c);
  const std::size_t h = static_cast<std::size_t>(proposal.headings());
  EXPECT_EQ(proposal.candidates_per_call(100 * h + 5), 100 * h);
  EXPECT_EQ(proposal.candidates_per_call(1), h);  // at least one block
  EXPECT_EQ(proposal.candidates_per_call(100'000'000), proposal.blocks() * h);
  // Every block is about equally likely to be in the subset: 400 draws of 100 blocks (the
  // default spacing is 5 cells), each block's count binomial(400, 100 / blocks).
  std::map<std::pair<int, int>, int> hits;
  Rng rng(5);
  for (int k = 0; k < 400; ++k) {
    const std::vector<Pose2> subset = proposal.candidates(rng, 100 * h);
    ASSERT_EQ(subset.size(), 100 * h);
    std::set<std::pair<int, int>> distinct;
    for (std::size_t b = 0; b < 100; ++b) {
      const Vec2 g = room.grid.geometry().world_to_cell_continuous(subset[b * h].translation());
      distinct.insert({static_cast<int>(std::floor(g.x())) / 5, static_cast<int>(std::floor(g.y())) / 5});
    }
    ASSERT_EQ(distinct.size(), 100u);  // no block twice
    for (const auto& key : distinct) ++hits[key];
  }
  const double p = 100.0 / static_cast<double>(proposal.blocks());
  const double mean = 400.0 * p, sd = std::sqrt(400.0 * p * (1.0 - p));
  int outside = 0;
  for (const auto& [key, n] : hits) outside += std::abs(n - mean) > 4.0 * sd;
  EXPECT_EQ(outside, 0);
  EXPECT_GT(hits.size(), 0.95 * static_cast<double>(proposal.blocks()));
}

// With the first stage keeping every candidate, the selection is the brute-force top of the
// same candidates scored with every beam.
TEST(ScanProposal, TwoStagesEqualBruteForceWhenTheFirstKeepsAll) {
  const amcl_test::Room room = amcl_test::make_room();
  LikelihoodFieldConfig fc;
  fc.range_max_m = 12.0;
  const LikelihoodField field(room.grid, {}, fc);
  Rng noise(9);
  const Pose2 truth(1.0, 0.2, 0.7);
  const PlanarScan scan = amcl_test::simulate_room_scan(room.boxes, truth.compose(kProposalMount), 180, 12.0, 0.01, noise);
  const std::vector<ModelBeam> beams = model_beams(scan, 60, scan.range_min_m, scan.range_max_m);
  ScanProposalConfig c;
  c.spacing_m = 0.5;
  c.yaw_step_rad = deg_to_rad(15.0);
  c.refine = 1'000'000;  // the first stage keeps everything
  const ScanProposal proposal(room.grid.geometry(), proposal_free_cells(room.grid), c);
  Rng a(21), b(21);
  const std::vector<ScoredPose> best = proposal.best(field, kProposalMount, beams, 50, 100'000'000, a);
  const std::vector<Pose2> all = proposal.candidates(b, 100'000'000);
  std::vector<double> scores;
  for (const Pose2& p : all) scores.push_back(field.weight(p, kProposalMount, beams));
  std::sort(scores.begin(), scores.end(), std::greater<>());
  ASSERT_EQ(best.size(), 50u);
  for (std::size_t k = 0; k < best.size(); ++k) {
    EXPECT_DOUBLE_EQ(best[k].score, scores[k]) << k;
    EXPECT_DOUBLE_EQ(best[k].score, field.weight(best[k].pose, kProposalMount, beams)) << k;
  }
}

// The lattice point nearest the truth (within half the spacing and half the heading step, and a
// little more) is among the ten best candidates for a scan. Not always the best: under Nav2's
// flat 1 + sum pz^3 a half-turned pose near the opposite corner of the room, which sees the same
// outer walls, can score higher (it does for the robot at (0.5, -1.2) facing the inner wall).
TEST(ScanProposal, BestCandidateLiesAtTheTruth) {
  const amcl_test::Room room = amcl_test::make_room();
  LikelihoodFieldConfig fc;
  fc.range_max_m = 12.0;
  const LikelihoodField field(room.grid, {}, fc);
  const ScanProposal proposal(room.grid.geometry(), proposal_free_cells(room.grid), ScanProposalConfig{});
  Rng noise(11), rng(12);
  for (const Pose2& truth : {Pose2(1.0, 0.2, 0.7), Pose2(4.8, 0.4, -2.0), Pose2(6.2, 3.2, 3.0), Pose2(0.5, -1.2, 1.4)}) {
    const PlanarScan scan =
        amcl_test::simulate_room_scan(room.boxes, truth.compose(kProposalMount), 180, 12.0, 0.01, noise);
    const std::vector<ModelBeam> beams = model_beams(scan, 60, scan.range_min_m, scan.range_max_m);
    const std::vector<ScoredPose> best = proposal.best(field, kProposalMount, beams, 10, 100'000'000, rng);
    ASSERT_FALSE(best.empty());
    const bool found = std::any_of(best.begin(), best.end(), [&](const ScoredPose& p) {
      return std::hypot(p.pose.x - truth.x, p.pose.y - truth.y) < 0.3 &&
             std::abs(angle_diff(p.pose.yaw, truth.yaw)) < deg_to_rad(5.0);
    });
    EXPECT_TRUE(found) << truth.x << "," << truth.y;
  }
}

TEST(ScanProposal, SameSeedSamePoses) {
  const amcl_test::Room room = amcl_test::make_room();
  LikelihoodFieldConfig fc;
  fc.range_max_m = 12.0;
  const LikelihoodField field(room.grid, {}, fc);
  const ScanProposal proposal(room.grid.geometry(), proposal_free_cells(room.grid), ScanProposalConfig{});
  Rng noise(2);
  const PlanarScan scan =
      amcl_test::simulate_room_scan(room.boxes, Pose2(3.0, 1.0, 0.3).compose(kProposalMount), 180, 12.0, 0.01, noise);
  const std::vector<ModelBeam> beams = model_beams(scan, 60, scan.range_min_m, scan.range_max_m);
  Rng a(4), b(4);
  const std::vector<ScoredPose> x = proposal.best(field, kProposalMount, beams, 200, 20'000, a);
  const std::vector<ScoredPose> y = proposal.best(field, kProposalMount, beams, 200, 20'000, b);
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_EQ(x[k].pose.x, y[k].pose.x);
    EXPECT_EQ(x[k].pose.yaw, y[k].pose.yaw);
    EXPECT_EQ(x[k].score, y[k].score);
  }
}

// A scan without a return says nothing: no candidates, and the generator is left as it was.
TEST(ScanProposal, NothingFromAScanWithoutAReturn) {
  const amcl_test::Room room = amcl_test::make_room();
  LikelihoodFieldConfig fc;
  fc.range_max_m = 12.0;
  const LikelihoodField field(room.grid, {}, fc);
  const ScanProposal proposal(room.grid.geometry(), proposal_free_cells(room.grid), ScanProposalConfig{});
  const std::vector<ModelBeam> none = {{12.0, 0.0}, {12.0, 1.0}, {12.0, 2.0}};
  Rng a(6), b(6);
  EXPECT_TRUE(proposal.best(field, kProposalMount, none, 100, 20'000, a).empty());
  EXPECT_EQ(a.next(), b.next());
}

TEST(ScanProposal, RejectsImpossibleConfigurations) {
  const amcl_test::Room room = amcl_test::make_room();
  const std::vector<std::int32_t> cells = proposal_free_cells(room.grid);
  const auto field_of = [&](const std::function<void(ScanProposalConfig&)>& change) {
    ScanProposalConfig c;
    change(c);
    try {
      ScanProposal p(room.grid.geometry(), cells, c);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.spacing_m = 0.0; }), "amcl.proposal_spacing_m");
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.spacing_m = std::nan(""); }), "amcl.proposal_spacing_m");
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.yaw_step_rad = 0.0; }), "amcl.proposal_yaw_step_deg");
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.coarse_beams = 0; }), "amcl.proposal_coarse_beams");
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.refine = 0; }), "amcl.proposal_refine");
  EXPECT_EQ(field_of([](ScanProposalConfig& c) { c.injection_pool = 0; }), "amcl.proposal_injection_pool");
  EXPECT_EQ(field_of([](ScanProposalConfig&) {}), "(accepted)");
  EXPECT_THROW(ScanProposal(room.grid.geometry(), std::vector<std::int32_t>{}, ScanProposalConfig{}), Error);
}

}  // namespace
}  // namespace starnav
