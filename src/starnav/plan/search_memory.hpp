#pragma once
// Per-state search memory, allocated once per map and reused by every query.
//
// Shared building block (docs/benchmarks.md): the search core (search_core.hpp), Theta*, and anyone else who
// needs per-state g / parent / open-list bookkeeping may use it (the JPS planners are welcome to).
//
// Each state holds its cost-so-far g, its parent, its slot in the open list (or a closed / not-open
// mark) and the generation of the query that last touched it. A query starts by bumping the
// generation, so a state whose stamp differs is "unseen" without clearing anything: no O(states)
// work per query and no allocation once the memory is sized (warm-up).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace starnav {

// "Infinite" cost for a cost type: +inf for floating point, a large value that can still be
// added to a few path costs without overflow for integers.
template <class Cost>
constexpr Cost infinite_cost() {
  if constexpr (std::is_floating_point_v<Cost>) return std::numeric_limits<Cost>::infinity();
  else return std::numeric_limits<Cost>::max() / 4;
}

inline constexpr std::uint32_t kNoState = 0xFFFFFFFFu;

template <class Cost>
struct SearchNode {
  Cost g;                  // cost from the start (valid when generation is current)
  std::uint32_t parent;    // predecessor on the best known path (kNoState for the start)
  std::uint32_t slot;      // open-list position, or kNotOpen / kClosed
  std::uint32_t generation;

  static constexpr std::uint32_t kNotOpen = 0xFFFFFFFFu;
  static constexpr std::uint32_t kClosed = 0xFFFFFFFEu;
  bool closed() const { return slot == kClosed; }
  bool open() const { return slot < kClosed; }
};
// Budget (docs/benchmarks.md): search state <= 32 bytes per state (24 with 64-bit costs, 20 -> 24 padded otherwise).
static_assert(sizeof(SearchNode<std::int64_t>) <= 32 && sizeof(SearchNode<double>) <= 32);

template <class Cost>
class SearchMemory {
 public:
  using Node = SearchNode<Cost>;

  SearchMemory() = default;
  explicit SearchMemory(std::size_t states) { resize(states); }

  // Sizes the memory for `states` states (allocates only when it grows).
  void resize(std::size_t states) {
    if (states > nodes_.size()) nodes_.resize(states, Node{infinite_cost<Cost>(), kNoState, Node::kNotOpen, 0});
    state_count_ = states;
  }
  std::size_t size() const { return state_count_; }
  std::size_t bytes_per_state() const { return sizeof(Node); }

  // Starts a query: every state becomes unseen. O(1) except once every 2^32 queries.
  void begin_query() {
    if (++generation_ == 0) {
      for (Node& n : nodes_) n.generation = 0;
      generation_ = 1;
    }
  }
  std::uint32_t generation() const { return generation_; }

  // The node of a state, reset to "unseen" (g = inf, not open) if this query has not touched it.
  Node& touch(std::uint32_t id) {
    Node& n = nodes_[id];
    if (n.generation != generation_) {
      n.g = infinite_cost<Cost>();
      n.parent = kNoState;
      n.slot = Node::kNotOpen;
      n.generation = generation_;
    }
    return n;
  }
  // True when the current query has touched the state.
  bool seen(std::uint32_t id) const { return nodes_[id].generation == generation_; }
  // Raw access: only meaningful when seen(id).
  Node& operator[](std::uint32_t id) { return nodes_[id]; }
  const Node& operator[](std::uint32_t id) const { return nodes_[id]; }
  // g of a state, infinite when unseen in this query.
  Cost g(std::uint32_t id) const { return seen(id) ? nodes_[id].g : infinite_cost<Cost>(); }
  std::uint32_t parent(std::uint32_t id) const { return seen(id) ? nodes_[id].parent : kNoState; }

 private:
  std::vector<Node> nodes_;
  std::size_t state_count_ = 0;
  std::uint32_t generation_ = 0;
};

}  // namespace starnav
