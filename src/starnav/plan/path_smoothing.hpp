#pragma once
// Removal of redundant path nodes by line of sight (Ou et al. 2022, Fig. 5; docs/papers/ou2022.md).
//
// From the anchor P0, keep the farthest later vertex Pj whose straight segment from the anchor
// touches no blocked cell, make it the anchor, repeat until the last vertex. The line test is
// line_of_sight (line_of_sight.hpp): a supercover test of every cell the segment touches,
// including the four cells around a grid corner it passes exactly through, so a segment can
// neither cross a blocked cell nor slip between two diagonally touching ones.
//
// Guarantees, for an input whose consecutive vertices are in line of sight (every grid path of
// A* / JPS / Dijkstra / Theta* on the same map): every output segment is in line of sight on
// `map` (collision-free on the inflated map when `map` is the inflated map), the output is a
// subsequence of the input with the same first and last vertex, and it is never longer (triangle
// inequality). The same pass removes the collinear redundant jump points of JPS paths (Fig. 14).
//
// Cost: O(k * n * L) for k kept vertices, n input vertices and segment lengths L (the search for
// the farthest visible vertex scans backwards from the end), negligible against the search on
// the paths the benchmarks see.
#include <span>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/plan/grid_graph.hpp"

namespace starnav {

// Cells must lie on the map. Consecutive input vertices are trusted to be in line of sight.
std::vector<Cell> remove_redundant_nodes(const GridSearchMap& map, std::span<const Cell> path);

}  // namespace starnav
