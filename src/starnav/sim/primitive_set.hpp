#pragma once
// A set of posed primitives with a bounding-volume hierarchy over their boxes (the broad phase):
// a ray visits only the nodes whose boxes it crosses, nearest first, and stops descending once
// a node lies beyond the nearest hit found so far, so its cost grows with the objects near the
// ray rather than with all objects.
#include <cstdint>
#include <vector>

#include "starnav/sim/primitives.hpp"

namespace starnav {

struct SetHit {
  double distance = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();
  bool inside = false;
  int index = -1;  // index into primitives()
};

class PrimitiveSet {
 public:
  PrimitiveSet() = default;
  explicit PrimitiveSet(std::vector<PosedPrimitive> primitives);

  const std::vector<PosedPrimitive>& primitives() const { return prims_; }
  bool empty() const { return prims_.empty(); }
  std::size_t node_count() const { return nodes_.size(); }

  // Nearest hit at s in [0, max_range] among the primitives that exist at `time`.
  bool cast(const Vec3& origin, const Vec3& dir, double max_range, double time, SetHit& hit) const;
  // The same by testing every primitive (reference for tests).
  bool cast_brute_force(const Vec3& origin, const Vec3& dir, double max_range, double time, SetHit& hit) const;

 private:
  struct Node {
    double b[2][3];      // lo, hi corners
    std::int32_t first;  // leaf: first primitive; inner: index of the left child (right = left + 1)
    std::int32_t count;  // leaf: number of primitives (> 0); inner: 0
  };
  void build();

  std::vector<PosedPrimitive> prims_;  // reordered so every leaf holds a contiguous run
  std::vector<Node> nodes_;
};

}  // namespace starnav
