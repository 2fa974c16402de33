#pragma once
// Gradient smoothing of a planned path beyond Ou et al. 2022 ("a further smoothing
// beyond the paper ... that keeps a minimum clearance"). The paper's line-of-sight pruning gives a
// taut polyline whose corners touch the inflated obstacles; a robot following it has to turn on
// the spot there. This smoother spreads those turns over the free space around them.
//
// Method. The path is resampled every `spacing` along its arc (its vertices kept), giving input
// samples o_0 .. o_n; the samples p_i then minimise
//     E = w_data * sum_i |p_i - o_i|^2 + w_smooth * sum_i |p_{i-1} - 2 p_i + p_{i+1}|^2
// (closeness to the input plus discrete curvature), endpoints fixed, by Gauss-Seidel sweeps: each
// interior sample moves to the exact minimiser of E over its own position with the others held.
// A move is taken only when (1) both segments to its neighbours touch no blocked cell (a
// supercover test of the continuous segment, so a segment passing exactly through a grid corner
// counts all four cells around it) and (2) the sample's clearance stays at least
// min(min_clearance_m, the clearance of its input sample), a point's clearance being the least
// over the cells whose closed square holds it (its cell; both cells on an edge). A refused move is retried at half,
// quarter and eighth length, then skipped for this sweep. Sweeps stop when no sample moved more
// than `tolerance` or after `max_iterations`.
//
// Guarantees: the first and last points are the input's; every output segment touches no blocked
// cell when every input segment touches none (a line-of-sight-pruned path on the same map); every
// sample keeps clearance >= min(min_clearance_m, its input sample's); E never increases (every
// taken move lowers a convex quadratic along one coordinate), so E(output) <= E(resampled input).
// The output is not shorter than a taut input in general: rounding a corner that hugs an obstacle
// moves it away from the obstacle.
#include <cstddef>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/path_metrics.hpp"

namespace starnav {

struct GradientSmoothingOptions {
  double weight_data = 0.2;      // w_data > 0: pull towards the input samples
  double weight_smooth = 0.3;    // w_smooth >= 0: penalty on the discrete curvature
  double spacing_m = 0.0;        // resampling step along the path; 0 = the map's resolution
  double min_clearance_m = 0.0;  // a sample may not end nearer an obstacle than this (or its input)
  int max_iterations = 500;      // Gauss-Seidel sweeps
  double tolerance_m = 1e-6;     // stop when no sample moved more than this in a sweep
};

// Throws Error naming the field (smooth_weight_data, smooth_weight_smooth, smooth_spacing,
// smooth_clearance, smooth_iterations, smooth_tolerance) for a value out of range.
void validate_gradient_smoothing(const GradientSmoothingOptions& options);

struct GradientSmoothingResult {
  std::vector<Vec2> points;     // world points, first and last equal to the input's
  int iterations = 0;           // sweeps run
  double energy_input = 0.0;    // E of the resampled input (in cells^2, so maps compare)
  double energy_output = 0.0;   // E of the output
};

// The points of `path` resampled every `spacing` (same units) along each segment; every input
// vertex is kept, and consecutive duplicates are dropped. spacing must be > 0.
std::vector<Vec2> resample_polyline(std::span<const Vec2> path, double spacing);

// Whether the segment between two world points touches only passable cells of `map` (whose
// geometry is `geometry`): every cell the segment enters, with both side cells where it passes
// within 1e-9 cells of a grid corner. False when any part lies off the map.
bool segment_clear(const GridSearchMap& map, const GridGeometry& geometry, const Vec2& a, const Vec2& b);

// Smooths `path` (world points, e.g. the centres of a line-of-sight-pruned grid path) on `map`.
// `clearance` (may be null) gives each cell's distance to the nearest obstacle, in metres; without
// it min_clearance_m must be 0. Paths of fewer than three samples come back resampled, unchanged.
// Throws Error for invalid options (validate_gradient_smoothing) or a clearance field whose
// geometry differs from `geometry`.
GradientSmoothingResult smooth_path_gradient(std::span<const Vec2> path, const GridSearchMap& map,
                                             const GridGeometry& geometry, const ClearanceField* clearance,
                                             const GradientSmoothingOptions& options = {});

}  // namespace starnav
