#pragma once
// D* Lite (Koenig & Likhachev 2002, the optimised version with the key modifier km) on 4- or
// 8-connected occupancy grids without corner cutting, for repeated planning while cells change
// and the robot moves. It searches backwards from the goal, so after cells change or the start
// moves only the affected part of the search is repaired; the returned cost is the same as an A*
// search from scratch on the current map.
//
// Typical use:
//   DStarLite d(grid);
//   PlanResult r = d.plan(start, goal);       // first search
//   d.move_start(next_cell);                  // the robot moved
//   d.update_cells({{cell, 100}});            // a cell turned out occupied
//   r = d.replan();                           // repaired search
//
// Costs are fixed point (as UniformGridCost) so the local-consistency tests g == rhs are exact.
// Queue order: key (k1, k2) lexicographically (k2 smaller first, as in the paper), then lower
// cell index.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/open_list.hpp"
#include "starnav/plan/search_core.hpp"

namespace starnav {


class DStarLite final : public GridPlanner {
 public:
  explicit DStarLite(const OccupancyGrid& grid, const GridPlannerOptions& options = {});

  std::string_view name() const override { return "dstar_lite"; }
  bool incremental() const override { return true; }
  PlanResult replan(Cell start, std::span<const CellChange> changed) override {
    update_cells(changed);
    move_start(start);
    return replan();
  }
  bool admissible() const override { return true; }

  // Starts over: a fresh search from start to goal (GridPlanner interface).
  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) override;
  // Changes cells; returns how many became passable or blocked. Throws Error (field "cell") for a
  // cell outside the map or an occupancy outside -1..100. The search is repaired by replan().
  std::size_t update_cells(std::span<const CellChange> changes);
  // The robot is now at `start` (may be anywhere; replan() reports start_outside_map or
  // start_blocked when it cannot plan from there).
  void move_start(Cell start);
  // Repairs the search after update_cells / move_start and returns the path from the current
  // start. Throws Error when plan() was never called.
  PlanResult replan(const SearchLimits& limits = {});

  const std::vector<Cell>& trace() const override { return trace_; }
  const GridSearchMap& search_map() const { return map_; }
  Cell start() const { return start_; }
  Cell goal() const { return goal_; }

 private:
  using Cost = std::int64_t;
  struct Node {
    Cost g;
    Cost rhs;
    std::uint32_t slot;  // position in the queue, or kNotQueued
    std::uint32_t generation;
  };
  static constexpr std::uint32_t kNotQueued = 0xFFFFFFFFu;
  struct Key {
    Cost k1, k2;
  };
  struct Entry {
    Cost k1, k2;
    std::uint32_t id;
  };
  struct EntryBefore {
    bool operator()(const Entry& a, const Entry& b) const {
      if (a.k1 != b.k1) return a.k1 < b.k1;
      if (a.k2 != b.k2) return a.k2 < b.k2;
      return a.id < b.id;
    }
  };
  struct SlotMap {
    static constexpr bool kTracks = true;
    std::vector<Node>* nodes = nullptr;
    void operator()(std::uint32_t id, std::uint32_t slot) const { (*nodes)[id].slot = slot; }
  };

  Node& node(std::uint32_t id);
  Key key(std::uint32_t id);
  static bool key_less(const Key& a, const Key& b) { return a.k1 < b.k1 || (a.k1 == b.k1 && a.k2 < b.k2); }
  Cost heuristic_from_start(std::uint32_t id) const;
  Cost edge_cost(std::uint32_t from, std::uint32_t to) const;  // infinite when blocked
  template <class Visit>
  void for_each_neighbour(std::uint32_t u, Visit&& visit) const;  // passable edges only
  Cost best_rhs(std::uint32_t u);
  void update_vertex(std::uint32_t u);
  SearchOutcome compute_shortest_path(const SearchLimits& limits, std::uint64_t& expanded, std::uint64_t& generated);
  PlanResult make_result();

  int connectivity_;
  OccupancyThresholds thresholds_;
  bool unknown_is_free_;
  bool record_trace_;
  GridGeometry geometry_;
  GridSearchMap map_;
  std::vector<Node> nodes_;
  std::uint32_t generation_ = 0;
  DaryHeap<Entry, EntryBefore, 4, SlotMap> queue_;
  OctileHeuristic<Cost> octile_;
  ManhattanHeuristic<Cost> manhattan_;
  Cost km_ = 0;
  Cell start_{}, goal_{};
  std::uint32_t start_state_ = 0, goal_state_ = 0;
  std::uint32_t heuristic_origin_ = kNoState;  // the start the keys' heuristic measures from
  bool initialised_ = false;
  std::uint64_t generated_ = 0;  // queue insertions of the current compute_shortest_path
  std::vector<Cell> trace_;
};

}  // namespace starnav
