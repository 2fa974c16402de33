#include "starnav/slam/scan_context.hpp"

#include <algorithm>
#include <cmath>

#include <nanoflann.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

ScanContext::ScanContext(std::span<const Vec2> points, int rings, int sectors, double max_range_m)
    : rings_(rings), sectors_(sectors), max_range_m_(max_range_m) {
  if (rings < 1 || sectors < 1 || !(max_range_m > 0) || !std::isfinite(max_range_m))
    throw Error("a scan context needs rings >= 1, sectors >= 1 and a range > 0");
  cells_.assign(static_cast<std::size_t>(rings) * static_cast<std::size_t>(sectors), 0);
  const double ring_m = max_range_m / rings;
  for (const Vec2& p : points) {
    const double r = p.norm();
    if (!(r > 0) || r > max_range_m) continue;
    const int ring = std::min(rings - 1, static_cast<int>(r / ring_m));
    cells_[static_cast<std::size_t>(ring * sectors + sector_of(std::atan2(p.y(), p.x())))] = 1;
  }
  ring_key_.assign(static_cast<std::size_t>(rings), 0.0);
  for (int ring = 0; ring < rings; ++ring) {
    int count = 0;
    for (int s = 0; s < sectors; ++s) count += occupied(ring, s);
    ring_key_[static_cast<std::size_t>(ring)] = static_cast<double>(count) / sectors;
  }
}

int ScanContext::sector_of(double bearing_rad) const {
  const double from_back = wrap_angle(bearing_rad) + kPi;  // (0, 2 pi]
  return std::clamp(static_cast<int>(from_back / (2 * kPi / sectors_)), 0, sectors_ - 1);
}

ScanContextMatch compare_scan_contexts(const ScanContext& query, const ScanContext& candidate) {
  if (query.rings() != candidate.rings() || query.sectors() != candidate.sectors() ||
      query.max_range_m() != candidate.max_range_m())
    throw Error("scan contexts of different shapes compared");
  const int rings = query.rings(), sectors = query.sectors();
  std::vector<int> count_q(static_cast<std::size_t>(sectors), 0), count_c(static_cast<std::size_t>(sectors), 0);
  for (int s = 0; s < sectors; ++s)
    for (int r = 0; r < rings; ++r) {
      count_q[static_cast<std::size_t>(s)] += query.occupied(r, s);
      count_c[static_cast<std::size_t>(s)] += candidate.occupied(r, s);
    }
  ScanContextMatch best;
  for (int shift = 0; shift < sectors; ++shift) {
    double similarity = 0.0;
    int compared = 0;
    for (int s = 0; s < sectors; ++s) {
      const int t = (s + shift) % sectors;
      const int nq = count_q[static_cast<std::size_t>(s)], nc = count_c[static_cast<std::size_t>(t)];
      if (nq == 0 && nc == 0) continue;
      ++compared;
      if (nq == 0 || nc == 0) continue;
      int common = 0;
      for (int r = 0; r < rings; ++r) common += query.occupied(r, s) && candidate.occupied(r, t);
      similarity += common / std::sqrt(static_cast<double>(nq) * nc);
    }
    const double distance = compared == 0 ? 1.0 : 1.0 - similarity / compared;
    if (distance < best.distance) best = {distance, shift, wrap_angle(shift * 2 * kPi / sectors)};
  }
  return best;
}

// Named (not anonymous): ScanContextIndex::Tree holds these.
namespace scan_context_detail {
struct RingKeys {
  const std::vector<ScanContext>* contexts = nullptr;
  std::size_t count = 0;
  std::size_t kdtree_get_point_count() const { return count; }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*contexts)[i].ring_key()[dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using RingKeyTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, RingKeys>, RingKeys, -1, std::uint32_t>;
}  // namespace scan_context_detail

struct ScanContextIndex::Tree {
  scan_context_detail::RingKeys keys;
  scan_context_detail::RingKeyTree tree;
  Tree(const std::vector<ScanContext>& contexts, int dims)
      : keys{&contexts, contexts.size()}, tree(dims, keys, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

ScanContextIndex::ScanContextIndex() = default;
ScanContextIndex::~ScanContextIndex() = default;
ScanContextIndex::ScanContextIndex(ScanContextIndex&&) noexcept = default;
ScanContextIndex& ScanContextIndex::operator=(ScanContextIndex&&) noexcept = default;

void ScanContextIndex::add(ScanContext context) {
  if (!contexts_.empty() && (context.rings() != contexts_.front().rings() || context.sectors() != contexts_.front().sectors() ||
                             context.max_range_m() != contexts_.front().max_range_m()))
    throw Error("a scan context of another shape added to an index");
  contexts_.push_back(std::move(context));
}

std::vector<std::size_t> ScanContextIndex::nearest(const ScanContext& query, std::size_t k) const {
  k = std::min(k, contexts_.size());
  if (k == 0) return {};
  if (query.rings() != contexts_.front().rings()) throw Error("a scan context of another shape looked up in an index");
  if (!tree_ || tree_size_ != contexts_.size()) {
    // The tree reads the contexts through a pointer: built again after additions (the vector
    // may have moved, and the new keys must be in it).
    tree_ = std::make_unique<Tree>(contexts_, query.rings());
    tree_size_ = contexts_.size();
  }
  std::vector<std::uint32_t> index(k);
  std::vector<double> dist(k);
  nanoflann::KNNResultSet<double, std::uint32_t> set(k);
  set.init(index.data(), dist.data());
  tree_->tree.findNeighbors(set, query.ring_key().data(), nanoflann::SearchParams());
  std::vector<std::pair<double, std::uint32_t>> found;
  for (std::size_t i = 0; i < set.size(); ++i) found.emplace_back(dist[i], index[i]);
  std::sort(found.begin(), found.end());
  std::vector<std::size_t> out;
  for (const auto& [d, i] : found) out.push_back(i);
  return out;
}

}  // namespace starnav
