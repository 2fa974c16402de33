#include "starnav/estimate/scan_proposal.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Best first; ties by a key drawn per candidate, so the selection does not depend on the sort
// and equal scores (open space where every beam lands beyond the field's reach) do not favour
// the blocks scored first.
bool scan_proposal_better(const ScoredPose& a, std::uint64_t ka, const ScoredPose& b, std::uint64_t kb) {
  return a.score != b.score ? a.score > b.score : ka < kb;
}

// A bijective 64-bit mix (the splitmix64 finaliser): distinct keys for distinct candidates.
std::uint64_t scan_proposal_key(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Keeps the `keep` best of `pool` (with their candidate numbers in `order`), in no order.
void scan_proposal_trim(std::vector<ScoredPose>& pool, std::vector<std::uint64_t>& order, std::size_t keep) {
  if (pool.size() <= keep) return;
  std::vector<std::size_t> idx(pool.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::nth_element(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(keep), idx.end(),
                   [&](std::size_t a, std::size_t b) { return scan_proposal_better(pool[a], order[a], pool[b], order[b]); });
  std::vector<ScoredPose> p(keep);
  std::vector<std::uint64_t> o(keep);
  for (std::size_t k = 0; k < keep; ++k) {
    p[k] = pool[idx[k]];
    o[k] = order[idx[k]];
  }
  pool.swap(p);
  order.swap(o);
}

}  // namespace

void ScanProposalConfig::validate() const {
  require(std::isfinite(spacing_m) && spacing_m > 0.0 && spacing_m <= 100.0, "amcl.proposal_spacing_m",
          "must be in (0, 100]");
  require(std::isfinite(yaw_step_rad) && yaw_step_rad >= deg_to_rad(0.1) && yaw_step_rad <= 2.0 * kPi,
          "amcl.proposal_yaw_step_deg", "must be in [0.1, 360]");
  require(coarse_beams >= 1, "amcl.proposal_coarse_beams", "must be >= 1");
  require(refine >= 1, "amcl.proposal_refine", "must be >= 1");
  require(max_candidates >= 1, "amcl.proposal_max_candidates", "must be >= 1");
  require(injection_candidates >= 1, "amcl.proposal_injection_candidates", "must be >= 1");
  require(injection_pool >= 1, "amcl.proposal_injection_pool", "must be >= 1");
  require(std::isfinite(injection_margin) && injection_margin >= 0.0, "amcl.proposal_injection_margin", "must be >= 0");
}

ScanProposal::ScanProposal(const GridGeometry& geometry, std::span<const std::int32_t> free_cells,
                           const ScanProposalConfig& config)
    : config_(config), geometry_(geometry) {
  config_.validate();
  require(!free_cells.empty(), "map", "has no free cell to draw poses from");
  headings_ = std::max(1, static_cast<int>(std::floor(2.0 * kPi / config_.yaw_step_rad + 1e-9)));
  // Block of a cell: its lower-left corner's block on a lattice of spacing_m (at least one cell).
  const double cells_per_block = std::max(1.0, config_.spacing_m / geometry_.resolution);
  const auto block_coord = [&](int c) { return static_cast<std::int64_t>(std::floor(c / cells_per_block)); };
  const std::int64_t blocks_x = block_coord(geometry_.width - 1) + 1;
  std::vector<std::pair<std::int64_t, std::int32_t>> keyed;
  keyed.reserve(free_cells.size());
  for (const std::int32_t i : free_cells) {
    const Cell c = geometry_.cell_of_index(static_cast<std::size_t>(i));
    keyed.emplace_back(block_coord(c.y) * blocks_x + block_coord(c.x), i);
  }
  std::sort(keyed.begin(), keyed.end());
  cells_.reserve(keyed.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) block_start_.push_back(cells_.size());
    cells_.push_back(keyed[k].second);
  }
  block_start_.push_back(cells_.size());
}

std::size_t ScanProposal::candidates_per_call(std::size_t limit) const {
  const std::size_t h = static_cast<std::size_t>(headings_);
  return std::clamp<std::size_t>(limit / h, 1, blocks()) * h;
}

void ScanProposal::for_each_chunk(Rng& rng, std::size_t limit, std::size_t chunk,
                                  const std::function<void(std::span<const Pose2>)>& fn) const {
  const std::size_t n_blocks = blocks();
  const std::size_t want_blocks = candidates_per_call(limit) / static_cast<std::size_t>(headings_);
  std::vector<Pose2> out;
  out.reserve(chunk + static_cast<std::size_t>(headings_));
  const double step = 2.0 * kPi / headings_;
  const auto emit = [&](std::size_t b) {
    const std::size_t first = block_start_[b], n = block_start_[b + 1] - first;
    const std::size_t pick = first + static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(n) - 1));
    const Cell c = geometry_.cell_of_index(static_cast<std::size_t>(cells_[pick]));
    const double gx = (c.x + rng.uniform()) * geometry_.resolution;
    const double gy = (c.y + rng.uniform()) * geometry_.resolution;
    const Vec2 w = geometry_.grid_to_world({gx, gy});
    const double offset = rng.uniform(-kPi, -kPi + step);
    for (int h = 0; h < headings_; ++h) out.emplace_back(w.x(), w.y(), wrap_angle(offset + h * step));
    if (out.size() >= chunk) {
      fn(out);
      out.clear();
    }
  };
  if (want_blocks >= n_blocks) {
    for (std::size_t b = 0; b < n_blocks; ++b) emit(b);
  } else {
    // A uniform subset of the blocks (selection sampling, Knuth's Algorithm S), in block order.
    std::size_t needed = want_blocks;
    for (std::size_t b = 0; b < n_blocks && needed > 0; ++b)
      if (rng.uniform() * static_cast<double>(n_blocks - b) < static_cast<double>(needed)) {
        emit(b);
        --needed;
      }
  }
  if (!out.empty()) fn(out);
}

std::vector<Pose2> ScanProposal::candidates(Rng& rng, std::size_t limit) const {
  std::vector<Pose2> all;
  for_each_chunk(rng, limit, 1 << 16, [&](std::span<const Pose2> c) { all.insert(all.end(), c.begin(), c.end()); });
  return all;
}

std::vector<ScoredPose> ScanProposal::best(const LikelihoodField& field, const Pose2& laser_in_base,
                                           std::span<const ModelBeam> beams, std::size_t count, std::size_t limit,
                                           Rng& rng) const {
  // The coarse beams: evenly spread over the returning ones (non-returns add nothing to the field).
  std::vector<ModelBeam> returning;
  for (const ModelBeam& b : beams)
    if (b.range_m < field.config().range_max_m) returning.push_back(b);
  if (count == 0 || returning.empty()) return {};
  std::vector<ModelBeam> coarse;
  const std::size_t nc = std::min(returning.size(), static_cast<std::size_t>(config_.coarse_beams));
  for (std::size_t k = 0; k < nc; ++k) coarse.push_back(returning[k * returning.size() / nc]);

  // Stage 1 chunk by chunk, so that every candidate's score is never held at once.
  const std::size_t keep1 = count * static_cast<std::size_t>(config_.refine);
  constexpr std::size_t kChunk = 1 << 16;
  std::vector<ScoredPose> pool;
  std::vector<std::uint64_t> order;
  std::vector<double> scores;
  std::uint64_t seen = rng.fork(0x5ca9).next();  // tie keys; the candidates draw from rng itself
  for_each_chunk(rng, limit, kChunk, [&](std::span<const Pose2> chunk) {
    scores.resize(chunk.size());
    field.weigh(chunk, laser_in_base, coarse, scores);
    for (std::size_t k = 0; k < chunk.size(); ++k) {
      pool.push_back({chunk[k], scores[k]});
      order.push_back(scan_proposal_key(seen + k));
    }
    seen += chunk.size();
    if (pool.size() >= 2 * keep1 + kChunk) scan_proposal_trim(pool, order, keep1);
  });
  scan_proposal_trim(pool, order, keep1);

  // Stage 2: the survivors with every beam.
  std::vector<Pose2> poses(pool.size());
  for (std::size_t k = 0; k < pool.size(); ++k) poses[k] = pool[k].pose;
  scores.resize(poses.size());
  field.weigh(poses, laser_in_base, beams, scores);
  for (std::size_t k = 0; k < pool.size(); ++k) pool[k].score = scores[k];
  scan_proposal_trim(pool, order, std::min(count, pool.size()));
  std::vector<std::size_t> idx(pool.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::sort(idx.begin(), idx.end(),
            [&](std::size_t a, std::size_t b) { return scan_proposal_better(pool[a], order[a], pool[b], order[b]); });
  std::vector<ScoredPose> out(idx.size());
  for (std::size_t k = 0; k < idx.size(); ++k) out[k] = pool[idx[k]];
  return out;
}

}  // namespace starnav
