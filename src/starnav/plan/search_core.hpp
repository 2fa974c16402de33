#pragma once
// The one best-first search engine of starnav (docs/benchmarks.md). Every grid planner is this loop with a
// different graph, cost, heuristic and open list, all template policies (no virtual call per
// node):
//
//   Graph      for_each_successor(u, visit): calls visit(v, edge_cost) for each move out of u.
//              States are integer ids (< 2^32 - 2); cost_type is the cost's type. Any-angle graphs
//              may instead call visit.via(v, p, cost_from_p) to offer v a path through an
//              earlier state p (Theta*), and read visit.parent_of(u), visit.g_of(u) and
//              visit.closed(v).
//   Heuristic  set_goal(goal) then h(id): estimate of the cost to the goal. Consistent
//              heuristics give optimal costs; weighted ones (WeightedHeuristic) give <= w * optimal.
//   GoalTest   bool(id): whether a state is a goal (SingleGoal for one state).
//   OpenList   DecreaseKeyOpenList (default) or LazyOpenList (open_list.hpp).
//   Listener   on_expand(id) / on_generate(id): statistics, traces; NullListener costs nothing.
//   Reopen     NeverReopen (default) or ReopenClosed: whether a closed state reached again with a
//              lower g goes back on the open list (a compile-time choice: the default loop has
//              no extra test).
//
// Order of expansion: lower f = g + h first, then larger g, then lower state id (conventions.md),
// so a query is deterministic and independent of the open-list variant. By default closed states
// are never reopened (with a consistent heuristic they cannot improve; weighted A* keeps its w
// bound without reopening). ReopenClosed is A* for heuristics that are admissible but not
// consistent, or not admissible at all (Liu 2024's IA* with its H = distance, its Algorithm 1):
// a closed state reached with a lower g is reopened, which keeps A*'s optimality for admissible
// heuristics at the price of re-expansions (counted in `expanded`, and in `reopened`). Memory
// (search_memory.hpp) is sized once per graph and reused with generation stamps; the open list
// keeps its storage, so queries do not allocate after warm-up.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "starnav/plan/open_list.hpp"
#include "starnav/plan/plan_result.hpp"
#include "starnav/plan/search_memory.hpp"

namespace starnav {

enum class SearchOutcome : std::uint8_t { Found, Exhausted, ExpansionLimit, TimeLimit, Cancelled };

struct SearchStats {
  std::uint64_t expanded = 0;   // popped from the open list and closed (re-expansions included)
  std::uint64_t generated = 0;  // pushed onto the open list, counting each improvement of g
  std::uint64_t reopened = 0;   // closed states put back on the open list (ReopenClosed only)
};

// Reopening policies of BestFirstSearch.
struct NeverReopen {
  static constexpr bool kReopens = false;
};
struct ReopenClosed {
  static constexpr bool kReopens = true;
};

struct NullListener {
  void on_expand(std::uint32_t) {}
  void on_generate(std::uint32_t) {}
};

// Keeps the expanded states in order (for pictures).
struct TraceListener {
  std::vector<std::uint32_t>* expanded = nullptr;
  void on_expand(std::uint32_t id) { expanded->push_back(id); }
  void on_generate(std::uint32_t) {}
};

struct SingleGoal {
  std::uint32_t id;
  bool operator()(std::uint32_t s) const { return s == id; }
};

// Limits are checked every kLimitCheckInterval expansions (clock and cancel flag) and at every
// expansion (count).
inline constexpr std::uint64_t kLimitCheckInterval = 1024;

template <class Cost, class OpenList = DefaultOpenList<Cost>, class Reopen = NeverReopen>
class BestFirstSearch {
 public:
  using cost_type = Cost;
  using Node = SearchNode<Cost>;
  using Entry = OpenEntry<Cost>;

  BestFirstSearch() { open_.bind(memory_); }
  explicit BestFirstSearch(std::size_t states) : memory_(states) { open_.bind(memory_); }
  BestFirstSearch(const BestFirstSearch&) = delete;
  BestFirstSearch& operator=(const BestFirstSearch&) = delete;

  void resize(std::size_t states) { memory_.resize(states); }

  // Runs one query from `start` until a goal state is expanded (Found), the open list runs dry
  // (Exhausted) or a limit stops it. `heuristic.set_goal` is the caller's business.
  template <class Graph, class Heuristic, class GoalTest, class Listener = NullListener>
  SearchOutcome run(const Graph& graph, const Heuristic& heuristic, std::uint32_t start, GoalTest is_goal,
                    const SearchLimits& limits = {}, Listener&& listener = {}) {
    memory_.begin_query();
    open_.clear();
    stats_ = {};
    goal_reached_ = kNoState;
    const auto started = std::chrono::steady_clock::now();

    Node& s = memory_.touch(start);
    s.g = Cost{};
    s.parent = kNoState;
    open_.push_or_decrease(s, Entry{heuristic(start), Cost{}, start});
    ++stats_.generated;
    listener.on_generate(start);

    Relaxer<Heuristic, std::remove_reference_t<Listener>> relax{this, &heuristic, &listener, 0, Cost{}};
    Entry top;
    while (open_.pop_best(top)) {
      if ((stats_.expanded % kLimitCheckInterval) == 0) {
        if (limits.cancel && limits.cancel->load(std::memory_order_relaxed)) return SearchOutcome::Cancelled;
        if (limits.time_budget_s > 0.0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() > limits.time_budget_s)
          return SearchOutcome::TimeLimit;
      }
      if (limits.max_expansions != 0 && stats_.expanded >= limits.max_expansions) return SearchOutcome::ExpansionLimit;
      Node& n = memory_[top.id];
      n.slot = Node::kClosed;
      ++stats_.expanded;
      listener.on_expand(top.id);
      if (is_goal(top.id)) {
        goal_reached_ = top.id;
        return SearchOutcome::Found;
      }
      relax.u = top.id;
      relax.gu = n.g;
      graph.for_each_successor(top.id, relax);
    }
    return SearchOutcome::Exhausted;
  }

  const SearchStats& stats() const { return stats_; }
  std::uint32_t goal_reached() const { return goal_reached_; }
  Cost g(std::uint32_t id) const { return memory_.g(id); }
  SearchMemory<Cost>& memory() { return memory_; }
  const SearchMemory<Cost>& memory() const { return memory_; }
  std::size_t open_capacity() const { return open_.capacity(); }

  // States from the start to `last` (inclusive) along parents; `out` is overwritten.
  void path_to(std::uint32_t last, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t s = last; s != kNoState; s = memory_[s].parent) out.push_back(s);
    std::reverse(out.begin(), out.end());
  }

 private:
  // The visitor handed to the graph: relaxes the edges out of the state being expanded.
  template <class Heuristic, class Listener>
  struct Relaxer {
    BestFirstSearch* self;
    const Heuristic* heuristic;
    Listener* listener;
    std::uint32_t u;
    Cost gu;

    // Edge u -> v of cost c.
    void operator()(std::uint32_t v, Cost c) const { self->relax(v, u, gu + c, *heuristic, *listener); }
    // Any-angle: v reached straight from the earlier state p at cost c.
    void via(std::uint32_t v, std::uint32_t p, Cost c) const {
      self->relax(v, p, self->memory_[p].g + c, *heuristic, *listener);
    }
    std::uint32_t parent_of(std::uint32_t id) const { return self->memory_[id].parent; }
    bool closed(std::uint32_t id) const { return self->memory_.seen(id) && self->memory_[id].closed(); }
    Cost g_of(std::uint32_t id) const { return self->memory_[id].g; }
  };

  template <class Heuristic, class Listener>
  void relax(std::uint32_t v, std::uint32_t parent, Cost g, const Heuristic& heuristic, Listener& listener) {
    Node& n = memory_.touch(v);
    if constexpr (Reopen::kReopens) {
      if (!(g < n.g)) return;
      // Both open lists push a closed node afresh (its slot is not a heap position).
      if (n.closed()) ++stats_.reopened;
    } else {
      if (!(g < n.g) || n.closed()) return;
    }
    n.g = g;
    n.parent = parent;
    open_.push_or_decrease(n, Entry{g + heuristic(v), g, v});
    ++stats_.generated;
    listener.on_generate(v);
  }

  SearchMemory<Cost> memory_;
  OpenList open_;
  SearchStats stats_;
  std::uint32_t goal_reached_ = kNoState;
};

}  // namespace starnav
