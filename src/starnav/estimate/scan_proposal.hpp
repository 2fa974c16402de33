#pragma once
// Poses drawn from the scan instead of from the prior: the candidate poses over a map's free
// space that best explain one scan under a likelihood field. AMCL starts a global localization
// from them and draws its recovery poses from them (sensor resetting, Lenser & Veloso 2000; the
// dual proposal of Mixture MCL, Thrun, Fox, Burgard & Dellaert 2001): a pose drawn uniformly
// over a 1,500 m^2 map lands within 0.25 m and 5 degrees of the robot with a chance of about
// 3e-6, so uniform draws rarely find it; scoring a lattice of every position and heading does.
//
// Candidates: the free cells grouped into square blocks of `spacing_m`; per block one random free
// cell and a uniform point in it, with every heading on a `yaw_step_rad` ring from a random
// offset. Scoring in two stages: every candidate with `coarse_beams` of the scan's returning
// beams, then the best `refine` times the requested count with all of them.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl_sensor_model.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

struct ScanProposalConfig {
  double spacing_m = 0.25;
  double yaw_step_rad = deg_to_rad(5.0);
  int coarse_beams = 12;
  int refine = 20;
  // At most this many candidates for a global start: above it a random subset of the blocks is
  // scored (memory and time stay bounded on large maps).
  int max_candidates = 4'000'000;
  // An injection (with `recovery`) scores a random subset of at most this many (it recurs at
  // every update while the filter is lost, each time another subset) and draws from the best
  // `injection_pool` of them.
  // The recovery draws from the scan too (off by default: Nav2 draws uniformly). Ungated, in
  // rows of look-alike shelves a spurious injection while tracking (the likelihood dips now and
  // then) filled the set with the few look-alikes that fit that scan best, and the filter jumped
  // to one of them (4-4.3 m RMSE after convergence in nav2_warehouse); injection_margin gates it.
  bool recovery = false;
  int injection_candidates = 250'000;
  int injection_pool = 50;
  // The recovery draws from the scan only when its best candidate explains the scan at least
  // this many times better than the set's best particle (both under the likelihood
  // injection_gate names); otherwise uniform free poses. After a kidnap no particle fits and the candidates
  // do; while tracking, a dip leaves the true particles about as good as any look-alike, so a
  // dip no longer fills the set with look-alikes (0.9 m jumps in nav2_warehouse without it).
  double injection_margin = 2.0;
  // The likelihood that margin is measured in. Search (the default): the search phase's, the
  // tempered product when search_independent_beams > 0. Tracking: the tracking field (Nav2's
  // 1 + sum pz^3), which compares the share of beams that fit: a look-alike that fits 80 % of
  // them scores 0.8 of the true place, never half as well, so a filter that had settled on one
  // after a kidnap was never offered the true place (nav2_depot: 4 of 20 kidnaps back only at
  // the next corner, 120-150 updates later; 0 of 20 with the search likelihood).
  enum class Gate : std::uint8_t { Search, Tracking };
  Gate injection_gate = Gate::Search;
  // Throws Error naming the field ("amcl.proposal_spacing_m", ...).
  void validate() const;
};

struct ScoredPose {
  Pose2 pose;
  double score = 0.0;
};

class ScanProposal {
 public:
  // `free_cells`: indices into the grid of `geometry` (AMCL's free cells). Throws Error (field
  // "map") when there is none.
  ScanProposal(const GridGeometry& geometry, std::span<const std::int32_t> free_cells, const ScanProposalConfig& config);

  const ScanProposalConfig& config() const { return config_; }
  std::size_t blocks() const { return block_start_.size() - 1; }
  int headings() const { return headings_; }
  // Candidates one call with at most `limit` scores: every block (or a random subset of them
  // when there are more than limit / headings) times the headings; at least one block.
  std::size_t candidates_per_call(std::size_t limit) const;

  // The candidates of one call, in the order scored (the draws of `rng` decide them).
  std::vector<Pose2> candidates(Rng& rng, std::size_t limit) const;
  // The same candidates handed to `fn` in chunks of about `chunk` (whole blocks).
  void for_each_chunk(Rng& rng, std::size_t limit, std::size_t chunk,
                      const std::function<void(std::span<const Pose2>)>& fn) const;

  // The `count` best candidates of one call (at most `limit` candidates) for the scan's `beams` (AMCL's model beams), best
  // first (ties in a random order), scored by `field` weight() (Nav2's sum or the tempered product,
  // as the field is configured) with the laser at `laser_in_base`. Fewer when there are fewer candidates; none (and no draw of
  // `rng`) when no beam returns: such a scan says nothing about where the robot is.
  std::vector<ScoredPose> best(const LikelihoodField& field, const Pose2& laser_in_base,
                               std::span<const ModelBeam> beams, std::size_t count, std::size_t limit, Rng& rng) const;

 private:
  ScanProposalConfig config_;
  GridGeometry geometry_;
  int headings_ = 1;
  std::vector<std::int32_t> cells_;        // the free cells, grouped by block
  std::vector<std::size_t> block_start_;   // block b holds cells_[block_start_[b] .. block_start_[b + 1])
};

}  // namespace starnav
