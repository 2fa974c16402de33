#pragma once
// Jump Point Search (Harabor & Grastien 2011) for 8-connected grids without corner cutting, with
// the pruning rules of "Improving Jump Point Search" (2014) and block-based scanning of 64 cells
// per machine word (bit_grid.hpp), and JPS+ (per-map jump tables, jps_tables.hpp).
//
// Same moves, costs and answers as A* with the octile heuristic (conventions.md): the returned
// path is the full cell path from start to goal (jump points are expanded into every cell in
// between, diagonal steps first), its cost is exact (counts of straight and diagonal moves are
// kept as integers), ties on f go to larger g and then to the lower cell index. `expanded` and
// `generated` count jump points (popped and closed / pushed), not cells.
//
// Memory per map: the bit grid (1 bit per cell; online JPS adds its transpose), the search
// memory (16 bytes per cell, generation-stamped, so a query never clears it) and, for JPS+, the
// jump table (8 bytes per cell). It is allocated with the planner and reused by every query: a
// query allocates nothing except the vectors of the returned PlanResult (and the open list's
// growth on the first large queries). `time_ms` covers the search and the reconstruction of
// the cell path, not the copy into the result.
//
// The open list is this file's own: a binary heap of 128-bit integer keys (f, g and cell index
// packed so one integer comparison orders them) with lazy deletion. On the MovingAI maps it was
// faster than a 4-ary heap and than plan/open_list.hpp's DaryHeap with the same keys; the
// shared SearchMemory holds one floating-point g, whereas JPS keeps integer move counts and the
// direction of arrival, so JPS has its own per-cell state too.
//
// Diagonal jumps generate the straight jump points they find directly as successors of the
// node being expanded (the intermediate diagonal cell is not pushed), as warthog's jps2 does.
#include <memory>

#include "starnav/plan/grid_planner.hpp"

namespace starnav {

// jump_tables = false: online JPS; true: JPS+ (tables built here; preprocess_ms() reports the
// time of everything built here). Options: connectivity must be 8 (Error otherwise), weight 1,
// heuristic "" or "octile"; unknown_is_free, thresholds and record_trace are honoured.
std::unique_ptr<GridPlanner> make_jps_planner(const OccupancyGrid& grid, const GridPlannerOptions& options,
                                              bool jump_tables);

}  // namespace starnav
