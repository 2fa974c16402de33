#include "starnav/sim/primitive_set.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace starnav {

namespace {

constexpr int kLeafSize = 2;

// Equal distances go to the lower (obstacle, part), so the answer does not depend on the order
// in which the hierarchy visits the primitives.
inline bool before(const PosedPrimitive& a, const PosedPrimitive& b) {
  return a.obstacle != b.obstacle ? a.obstacle < b.obstacle : a.part < b.part;
}

// Ray against a node's box (Williams et al.'s slab test: the near and far planes per axis are
// picked by the sign of the direction, so there is no swap): entry distance, or +inf when missed
// within [0, t_max]. A zero direction component uses a huge finite inverse of the right sign, so
// 0 * inf never produces NaN.
struct RayInv {
  double o[3];
  double inv[3];
  int near[3];  // 0: the lo plane is the near one (direction >= 0), 1: the hi plane
};

inline double box_entry(const double (&b)[2][3], const RayInv& r, double t_max) {
  double t0 = 0.0, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    const double tn = (b[r.near[a]][a] - r.o[a]) * r.inv[a];
    const double tf = (b[1 - r.near[a]][a] - r.o[a]) * r.inv[a];
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
  }
  return t0 <= t1 ? t0 : kInfinity;
}

}  // namespace

PrimitiveSet::PrimitiveSet(std::vector<PosedPrimitive> primitives) : prims_(std::move(primitives)) {
  if (prims_.empty()) return;
  nodes_.reserve(2 * prims_.size());
  nodes_.push_back({});
  build();
}

// Median split on the longest axis of the boxes' centres; node 0 is the root, children are
// allocated in pairs.
void PrimitiveSet::build() {
  struct Task {
    int node, begin, end;
  };
  std::vector<Task> stack{{0, 0, static_cast<int>(prims_.size())}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    Aabb box, centres;
    for (int i = task.begin; i < task.end; ++i) {
      box.extend(prims_[static_cast<std::size_t>(i)].box);
      centres.extend(prims_[static_cast<std::size_t>(i)].box.center());
    }
    Node& node = nodes_[static_cast<std::size_t>(task.node)];
    for (int a = 0; a < 3; ++a) {
      node.b[0][a] = box.lo[a];
      node.b[1][a] = box.hi[a];
    }
    const int n = task.end - task.begin;
    if (n <= kLeafSize) {
      node.first = task.begin;
      node.count = n;
      continue;
    }
    const Vec3 ext = centres.hi - centres.lo;
    int axis = 0;
    if (ext.y() > ext[axis]) axis = 1;
    if (ext.z() > ext[axis]) axis = 2;
    const int mid = task.begin + n / 2;
    std::nth_element(prims_.begin() + task.begin, prims_.begin() + mid, prims_.begin() + task.end,
                     [axis](const PosedPrimitive& a, const PosedPrimitive& b) {
                       return a.box.center()[axis] < b.box.center()[axis];
                     });
    const int left = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    Node& parent = nodes_[static_cast<std::size_t>(task.node)];  // push_back may have moved it
    parent.first = left;
    parent.count = 0;
    stack.push_back({left + 1, mid, task.end});
    stack.push_back({left, task.begin, mid});
  }
}

bool PrimitiveSet::cast(const Vec3& origin, const Vec3& dir, double max_range, double time, SetHit& hit) const {
  if (nodes_.empty()) return false;
  RayInv r;
  for (int a = 0; a < 3; ++a) {
    r.o[a] = origin[a];
    r.inv[a] = dir[a] != 0.0 ? 1.0 / dir[a] : std::copysign(1e300, dir[a]);
    r.near[a] = std::signbit(r.inv[a]) ? 1 : 0;
  }
  double best = max_range;
  bool found = false;
  PrimitiveHit ph;
  std::int32_t stack[64];
  int sp = 0;
  if (box_entry(nodes_[0].b, r, best) == kInfinity) return false;
  std::int32_t current = 0;
  for (;;) {
    const Node& node = nodes_[static_cast<std::size_t>(current)];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const PosedPrimitive& p = prims_[static_cast<std::size_t>(i)];
        if (!p.exists_at(time)) continue;
        if (intersect(p, origin, dir, best, ph) &&
            (!found || ph.distance < best ||
             (ph.distance == best && before(p, prims_[static_cast<std::size_t>(hit.index)])))) {
          best = ph.distance;
          found = true;
          hit.distance = ph.distance;
          hit.normal = ph.normal;
          hit.inside = ph.inside;
          hit.index = i;
        }
      }
    } else {
      const std::int32_t l = node.first, rr = node.first + 1;
      const double tl = box_entry(nodes_[static_cast<std::size_t>(l)].b, r, best);
      const double tr = box_entry(nodes_[static_cast<std::size_t>(rr)].b, r, best);
      if (tl != kInfinity && tr != kInfinity) {
        // Visit the nearer child first; the other waits on the stack.
        if (tl <= tr) {
          stack[sp++] = rr;
          current = l;
        } else {
          stack[sp++] = l;
          current = rr;
        }
        continue;
      }
      if (tl != kInfinity) {
        current = l;
        continue;
      }
      if (tr != kInfinity) {
        current = rr;
        continue;
      }
    }
    // Pop the next node that may still hold something nearer than the best hit.
    for (;;) {
      if (sp == 0) return found;
      current = stack[--sp];
      const Node& c = nodes_[static_cast<std::size_t>(current)];
      if (box_entry(c.b, r, best) != kInfinity) break;
    }
  }
}

bool PrimitiveSet::cast_brute_force(const Vec3& origin, const Vec3& dir, double max_range, double time,
                                    SetHit& hit) const {
  bool found = false;
  PrimitiveHit ph;
  for (std::size_t i = 0; i < prims_.size(); ++i) {
    if (!prims_[i].exists_at(time)) continue;
    if (intersect(prims_[i], origin, dir, max_range, ph) &&
        (!found || ph.distance < hit.distance ||
         (ph.distance == hit.distance && before(prims_[i], prims_[static_cast<std::size_t>(hit.index)])))) {
      found = true;
      hit.distance = ph.distance;
      hit.normal = ph.normal;
      hit.inside = ph.inside;
      hit.index = static_cast<int>(i);
    }
  }
  return found;
}

}  // namespace starnav
