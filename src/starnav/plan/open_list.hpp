#pragma once
// Open lists for best-first search.
//
// Shared building block (docs/benchmarks.md): `DaryHeap` is a d-ary min-heap that can track where each
// entry sits (for decrease-key / update / remove) or not (lazy deletion). The search core, D* Lite
// and the JPS planners may all use it; `DecreaseKeyOpenList` and `LazyOpenList` adapt it to a
// SearchMemory (search_memory.hpp). Both give the same expansion order, because the entry order
// is total (f, then larger g, then lower state id: conventions.md), so the minimum is unique.
//
// Measured on the MovingAI maps of docs/benchmarks.md (bench/bench_search_core.cpp): for A*, lazy deletion
// was 1.5-2x slower than decrease-key (more and staler entries); binary and 4-ary decrease-key were
// within about 5% of each other (4-ary 12% ahead on maze512-4-0); for Dijkstra all four were
// within 5%. The 4-ary decrease-key heap is the default (`DefaultOpenList`).
#include <cstdint>
#include <utility>
#include <vector>

#include "starnav/plan/search_memory.hpp"

namespace starnav {

// Orders A*-style entries: lower f first; on equal f the larger g (closer to the goal); then the
// lower state id, so every query is deterministic.
template <class Cost>
struct OpenEntry {
  Cost f;
  Cost g;
  std::uint32_t id;
};

template <class Cost>
struct OpenEntryBefore {
  bool operator()(const OpenEntry<Cost>& a, const OpenEntry<Cost>& b) const {
    if (a.f != b.f) return a.f < b.f;
    if (a.g != b.g) return a.g > b.g;
    return a.id < b.id;
  }
};

// A slot map that records nothing: the heap then supports push / pop only (lazy deletion).
struct NoSlotMap {
  static constexpr bool kTracks = false;
  void operator()(std::uint32_t /*id*/, std::uint32_t /*slot*/) const {}
};

// d-ary min-heap over `Entry` (which has a member `id`) ordered by `Before`. When SlotMap tracks
// positions it is told every entry's new position (slot_map(id, position)), which makes
// decrease(), update() and remove() possible. Storage grows on demand and is kept across clear(),
// so after warm-up no query allocates.
template <class Entry, class Before, unsigned Arity, class SlotMap = NoSlotMap>
class DaryHeap {
  static_assert(Arity >= 2);

 public:
  explicit DaryHeap(SlotMap slots = {}, Before before = {}) : slots_(slots), before_(before) {}
  void set_slot_map(SlotMap slots) { slots_ = slots; }

  void clear() { heap_.clear(); }
  void reserve(std::size_t n) { heap_.reserve(n); }
  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }
  std::size_t capacity() const { return heap_.capacity(); }
  const Entry& top() const { return heap_.front(); }
  const Entry& at(std::uint32_t position) const { return heap_[position]; }

  void push(const Entry& e) {
    heap_.push_back(e);
    sift_up(static_cast<std::uint32_t>(heap_.size() - 1), e);
  }

  // Removes and returns the first entry.
  Entry pop() {
    Entry first = heap_.front();
    Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0, last);
    return first;
  }

  // The entry at `position` gets a key that does not come later (decrease-key).
  void decrease(std::uint32_t position, const Entry& e) { sift_up(position, e); }

  // The entry at `position` gets any new key.
  void update(std::uint32_t position, const Entry& e) {
    if (position > 0 && before_(e, heap_[parent_of(position)])) sift_up(position, e);
    else sift_down(position, e);
  }

  // Removes the entry at `position`.
  void remove(std::uint32_t position) {
    Entry last = heap_.back();
    heap_.pop_back();
    if (position < heap_.size()) update(position, last);
  }

 private:
  static std::uint32_t parent_of(std::uint32_t i) { return (i - 1) / Arity; }

  void place(std::uint32_t i, const Entry& e) {
    heap_[i] = e;
    if constexpr (SlotMap::kTracks) slots_(e.id, i);
  }

  // Moves the hole at i up until e fits, then puts e there.
  void sift_up(std::uint32_t i, const Entry& e) {
    while (i > 0) {
      const std::uint32_t p = parent_of(i);
      if (!before_(e, heap_[p])) break;
      place(i, heap_[p]);
      i = p;
    }
    place(i, e);
  }

  // Moves the hole at i down until e fits, then puts e there.
  void sift_down(std::uint32_t i, const Entry& e) {
    const std::uint32_t n = static_cast<std::uint32_t>(heap_.size());
    for (;;) {
      const std::uint64_t first_child64 = static_cast<std::uint64_t>(i) * Arity + 1;
      if (first_child64 >= n) break;
      const std::uint32_t first_child = static_cast<std::uint32_t>(first_child64);
      std::uint32_t best = first_child;
      const std::uint32_t end = first_child + Arity < n ? first_child + Arity : n;
      for (std::uint32_t c = first_child + 1; c < end; ++c)
        if (before_(heap_[c], heap_[best])) best = c;
      if (!before_(heap_[best], e)) break;
      place(i, heap_[best]);
      i = best;
    }
    place(i, e);
  }

  std::vector<Entry> heap_;
  SlotMap slots_;
  Before before_;
};

// Writes heap positions into SearchMemory nodes.
template <class Cost>
struct NodeSlotMap {
  static constexpr bool kTracks = true;
  SearchMemory<Cost>* memory = nullptr;
  void operator()(std::uint32_t id, std::uint32_t slot) const { (*memory)[id].slot = slot; }
};

// Open list with decrease-key: each state is in the heap at most once.
template <class Cost, unsigned Arity = 4>
class DecreaseKeyOpenList {
 public:
  using Entry = OpenEntry<Cost>;
  static constexpr const char* kName = Arity == 2 ? "binary decrease-key" : "4-ary decrease-key";

  void bind(SearchMemory<Cost>& memory) {
    memory_ = &memory;
    heap_.set_slot_map(NodeSlotMap<Cost>{&memory});
  }
  void clear() { heap_.clear(); }
  bool empty() const { return heap_.empty(); }
  std::size_t capacity() const { return heap_.capacity(); }

  // `node` (of state e.id) has a new, better g: insert it or move it up.
  void push_or_decrease(SearchNode<Cost>& node, const Entry& e) {
    if (node.open()) heap_.decrease(node.slot, e);
    else heap_.push(e);
  }
  // Takes the best entry; false when the list is empty. The caller closes the node.
  bool pop_best(Entry& out) {
    if (heap_.empty()) return false;
    out = heap_.pop();
    return true;
  }

 private:
  SearchMemory<Cost>* memory_ = nullptr;
  DaryHeap<Entry, OpenEntryBefore<Cost>, Arity, NodeSlotMap<Cost>> heap_;
};

// Open list with lazy deletion: an improved state is pushed again and the outdated entries are
// skipped when they come out (closed already, or g no longer the node's g).
template <class Cost, unsigned Arity = 4>
class LazyOpenList {
 public:
  using Entry = OpenEntry<Cost>;
  static constexpr const char* kName = Arity == 2 ? "binary lazy" : "4-ary lazy";

  void bind(SearchMemory<Cost>& memory) { memory_ = &memory; }
  void clear() { heap_.clear(); }
  bool empty() const { return heap_.empty(); }
  std::size_t capacity() const { return heap_.capacity(); }

  void push_or_decrease(SearchNode<Cost>& node, const Entry& e) {
    node.slot = 0;  // "open" (any value below kClosed)
    heap_.push(e);
  }
  bool pop_best(Entry& out) {
    while (!heap_.empty()) {
      out = heap_.pop();
      const SearchNode<Cost>& n = (*memory_)[out.id];
      if (!n.closed() && n.g == out.g) return true;
    }
    return false;
  }

 private:
  SearchMemory<Cost>* memory_ = nullptr;
  DaryHeap<Entry, OpenEntryBefore<Cost>, Arity> heap_;
};

template <class Cost>
using DefaultOpenList = DecreaseKeyOpenList<Cost, 4>;

}  // namespace starnav
