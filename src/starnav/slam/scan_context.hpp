#pragma once
// Scan Context (Kim and Kim, IROS 2018) for planar points: a place described by which cells of a
// polar grid around the sensor hold points (rings of equal width out to a range, sectors of equal
// angle), compared with the sensor's heading unknown by shifting one description's sectors
// against the other's. The ring key (the share of occupied sectors per ring) does not change when
// the sensor turns, so places are looked up by it in a k-d tree before the full comparison. It
// proposes where a scan may have been seen before when the pose estimate has drifted too far to
// say: what it proposes is verified by the scan matcher.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"

namespace starnav {

class ScanContext {
 public:
  // Points in the sensor frame; those beyond `max_range_m` (and at the sensor) are left out.
  ScanContext(std::span<const Vec2> points, int rings, int sectors, double max_range_m);
  int rings() const { return rings_; }
  int sectors() const { return sectors_; }
  double max_range_m() const { return max_range_m_; }
  bool occupied(int ring, int sector) const { return cells_[static_cast<std::size_t>(ring * sectors_ + sector)] != 0; }
  // Per ring, the share of its sectors that hold points.
  const std::vector<double>& ring_key() const { return ring_key_; }
  // The sector holding bearing `bearing_rad` (in (-pi, pi], 0 ahead, counter-clockwise).
  int sector_of(double bearing_rad) const;

 private:
  int rings_, sectors_;
  double max_range_m_;
  std::vector<std::uint8_t> cells_;  // ring-major
  std::vector<double> ring_key_;
};

// How two descriptions compare with the sensor's heading unknown. `distance` in [0, 1]: one minus
// the mean cosine similarity of their sectors (the occupied cells of each as a vector) under the
// best shift, averaged over the sectors occupied in either (a sector empty in one of them counts
// as no likeness, so two places seen from half their sides do not match on the half they share
// by chance); 1 when neither holds a point. `yaw_rad`: how far the query's sensor is turned from
// the candidate's (counter-clockwise) under that shift, a multiple of the sector angle.
struct ScanContextMatch {
  double distance = 1.0;
  int shift = 0;
  double yaw_rad = 0.0;
};
// Both descriptions must have the same rings, sectors and range.
ScanContextMatch compare_scan_contexts(const ScanContext& query, const ScanContext& candidate);

// Descriptions looked up by ring key: the k-d tree is built again on the first lookup after
// descriptions were added.
class ScanContextIndex {
 public:
  ScanContextIndex();
  ~ScanContextIndex();
  ScanContextIndex(ScanContextIndex&&) noexcept;
  ScanContextIndex& operator=(ScanContextIndex&&) noexcept;
  void add(ScanContext context);
  std::size_t size() const { return contexts_.size(); }
  const ScanContext& at(std::size_t i) const { return contexts_[i]; }
  // The `k` descriptions whose ring keys are nearest the query's (Euclidean), nearest first, ties
  // by the order they were added.
  std::vector<std::size_t> nearest(const ScanContext& query, std::size_t k) const;

 private:
  struct Tree;
  std::vector<ScanContext> contexts_;
  mutable std::unique_ptr<Tree> tree_;
  mutable std::size_t tree_size_ = 0;  // descriptions the tree holds
};

}  // namespace starnav
