#pragma once
// Terrain analysis of an ElevationMap, computed once per map and cached, and recomputed for a
// rectangle of changed cells (docs/terrain.md has every definition):
//
//   per move (8 per cell)  height difference h = |z2 - z1| and slope a = atan(h / l), computed on
//                          the fly from the cached heights (a subtraction and an atan: cheaper to
//                          recompute than to load; the planners cache their move costs instead);
//   per cell               ruggedness S (3x3 height variance, the cells that exist at the border),
//                          gradient, surface normal and slope from a least-squares plane fit over
//                          the same 3x3 block;
//   masks                  Liu 2024 obstacles (thresholds h_y, a_y, S_y: the AOEA* obstacles),
//                          Li 2019 node criteria (height spread and neighbour mid-height
//                          difference), and both expanded by the robot radius with the exact
//                          Euclidean distance transform.
//
// Unobserved cells follow UnobservedPolicy. They have no height: they never enter another
// cell's ruggedness or plane fit, and their own ruggedness and gradient are 0.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/mask_inflation.hpp"
#include "starnav/terrain/liu_cost.hpp"

namespace starnav {

// What an unobserved cell is to the planners and masks.
enum class UnobservedPolicy : std::uint8_t {
  Blocked,      // impassable, and an obstacle in every mask (default: no guessing)
  FreeFlat,     // passable, flat: moves touching it have h = 0, a = 0; its S = 0 (optimistic)
  UnknownCost,  // passable at a fixed g (LiuCostParams::unobserved_g) for moves touching it
};
const char* unobserved_policy_name(UnobservedPolicy p);  // "blocked", "free_flat", "unknown_cost"
// Parses the names above; throws Error naming `field` otherwise.
UnobservedPolicy parse_unobserved_policy(const std::string& name, const std::string& field = "unobserved");

// Li et al. 2019 node traversability (docs/papers/li2019.md): k_step = max_step_m / cell size,
// k_slope = tan(max_slope_rad).
struct LiNodeParams {
  double max_step_m = 0.05;                 // largest obstacle the robot can climb
  double max_slope_rad = deg_to_rad(15.0);  // steepest slope the robot can climb
  void validate() const;                    // Error naming the field
};

struct TerrainAnalysisOptions {
  UnobservedPolicy unobserved = UnobservedPolicy::Blocked;
  LiuCostParams thresholds;   // h_y, a_y, s_y define the Liu obstacle mask (the rest is unused)
  LiNodeParams li;
  // Obstacle expansion radius (AOEA*, Li 2019 barrier distance): the circumscribed radius of
  // the default 0.6 m x 0.4 m footprint. 0 = no expansion.
  double robot_radius_m = 0.36;
  void validate() const;  // Error naming the field
};

// The 8 moves: E, N, W, S, NE, NW, SW, SE (x right, y up in grid cells).
inline constexpr int kMoveCount = 8;
inline constexpr int kMoveDx[kMoveCount] = {1, 0, -1, 0, 1, -1, -1, 1};
inline constexpr int kMoveDy[kMoveCount] = {0, 1, 0, -1, 1, 1, -1, -1};
inline constexpr bool move_is_diagonal(int k) { return k >= 4; }
// The two straight moves beside a diagonal move k (4..7): NE -> E, N; NW -> W, N; SW -> W, S;
// SE -> E, S.
inline constexpr int kDiagonalSideA[kMoveCount] = {-1, -1, -1, -1, 0, 2, 2, 0};
inline constexpr int kDiagonalSideB[kMoveCount] = {-1, -1, -1, -1, 1, 1, 3, 3};
// The move index of (dx, dy) in {-1, 0, 1}^2 \ {(0, 0)}, or -1.
int move_index(int dx, int dy);

// h and a of one move.
struct MoveTerrain {
  double h = 0.0;       // |z2 - z1|, metres (0 when an end is unobserved)
  double a = 0.0;       // atan(h / l), radians
  double length = 0.0;  // horizontal length l, metres
  bool known = false;   // both ends inside the map and observed
};

class TerrainAnalysis {
 public:
  TerrainAnalysis() = default;
  // Throws Error for bad options (naming the field).
  explicit TerrainAnalysis(const ElevationMap& map, const TerrainAnalysisOptions& options = {});

  void compute(const ElevationMap& map, const TerrainAnalysisOptions& options);
  // Recomputes everything that depends on the cells in `changed` (heights, min/max or observed
  // changed there). The map must have the geometry of the one analysed. The result equals a
  // full compute().
  void update(const ElevationMap& map, CellRect changed);

  const GridGeometry& geometry() const { return geometry_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }
  double resolution() const { return geometry_.resolution; }
  const TerrainAnalysisOptions& options() const { return options_; }
  std::size_t index(int x, int y) const { return geometry_.index(x, y); }
  bool contains(int x, int y) const { return geometry_.contains(x, y); }

  // Cached heights (0 where unobserved) and observed flags, row-major like the map.
  const std::vector<double>& heights() const { return z_; }
  const std::vector<std::uint8_t>& observed() const { return observed_; }
  double z(int x, int y) const { return z_[index(x, y)]; }
  bool observed(int x, int y) const { return observed_[index(x, y)] != 0; }

  // Horizontal length of move k in metres (resolution, or resolution * sqrt 2).
  double move_length(int k) const { return move_is_diagonal(k) ? diagonal_length_ : geometry_.resolution; }
  // h and a of move k out of (x, y). Requires (x, y) inside; a move leaving the map has
  // known = false and h = a = 0.
  MoveTerrain move(int x, int y, int k) const;

  // Ruggedness S (m^2) per cell.
  const std::vector<double>& ruggedness() const { return rugged_; }
  double ruggedness(int x, int y) const { return rugged_[index(x, y)]; }
  // dz/dx, dz/dy of the fitted plane in the grid frame (x along the grid's columns), metres per
  // metre.
  Vec2 gradient(int x, int y) const { return {grad_x_[index(x, y)], grad_y_[index(x, y)]}; }
  // Unit upward surface normal in the world frame (the grid's yaw applied).
  Vec3 normal(int x, int y) const;
  // Slope of the fitted plane: atan(|gradient|), radians.
  double cell_slope(int x, int y) const;

  // Masks, row-major, 1 = blocked / obstacle (docs/terrain.md):
  //  obstacle: observed with S >= s_y, or with a move to an observed 8-neighbour whose h >= h_y
  //            or a >= a_y; unobserved under UnobservedPolicy::Blocked.
  //  li_blocked: observed with max - min > max_step_m, or |mid - mid(m)| > tan(max_slope) * l
  //            for an observed 8-neighbour m; unobserved under UnobservedPolicy::Blocked.
  //  expanded_*: every cell whose centre lies within robot_radius_m of a masked cell's centre.
  const std::vector<std::uint8_t>& obstacle_mask() const { return obstacle_; }
  const std::vector<std::uint8_t>& li_blocked_mask() const { return li_blocked_; }
  const std::vector<std::uint8_t>& expanded_obstacle_mask() const { return expanded_obstacle_; }
  const std::vector<std::uint8_t>& expanded_li_blocked_mask() const { return expanded_li_; }

 private:
  void compute_cells(const ElevationMap& map, const CellRect& r);     // z, observed, mid, spread
  void compute_block_stats(const CellRect& r);                        // S and gradient
  void compute_masks(const CellRect& r);                              // obstacle, li_blocked
  void compute_expansion(const CellRect& affected);                   // expanded masks

  GridGeometry geometry_;
  TerrainAnalysisOptions options_;
  double diagonal_length_ = 0.0;
  std::vector<double> z_;
  std::vector<std::uint8_t> observed_;
  std::vector<double> mid_;     // (max + min) / 2
  std::vector<double> spread_;  // max - min
  std::vector<double> rugged_;
  std::vector<double> grad_x_;
  std::vector<double> grad_y_;
  std::vector<std::uint8_t> obstacle_;
  std::vector<std::uint8_t> li_blocked_;
  std::vector<std::uint8_t> expanded_obstacle_;
  std::vector<std::uint8_t> expanded_li_;
  IncrementalInflation inflation_;  // scratch of the windowed expansion update
};

// TerrainAnalysisOptions as declared parameters: unobserved, h_y, a_y, s_y (the Liu thresholds of
// the obstacle mask), max_step_m, max_slope_deg (Li 2019's node criteria), robot_radius_m.
const ParamTable<TerrainAnalysisOptions>& terrain_analysis_params();

// The Liu obstacle mask of `analysis` for other thresholds than its own (same definition).
std::vector<std::uint8_t> liu_obstacle_mask(const TerrainAnalysis& analysis, const LiuCostParams& thresholds);

// The 3x3 block statistics of one cell (exposed for tests and tools): mean and variance of the
// observed heights in the block (the cells that exist), and the least-squares plane gradient
// over them (minimum-norm solution when the points do not span a plane).
struct BlockStats {
  int count = 0;
  double mean = 0.0;
  double variance = 0.0;
  double grad_x = 0.0;  // per metre, grid frame
  double grad_y = 0.0;
};
BlockStats block_stats(const std::vector<double>& z, const std::vector<std::uint8_t>& observed, int width, int height,
                       double resolution, int x, int y);

}  // namespace starnav
