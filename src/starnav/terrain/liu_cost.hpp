#pragma once
// Liu et al. 2024 ground trafficability and ruggedness costs (docs/papers/liu2024.md,
// sections 1-3; docs/terrain.md).
//
// For a move from a parent cell to a child cell:
//   h = |z_child - z_parent|                  height difference (step), metres
//   a = atan(h / l)                           slope, l the horizontal move length, radians
//   S = 3x3 height variance at the child      ruggedness, m^2 (terrain_analysis.hpp)
//   f_s = tan(pi a / (2 a_y)),  f_e = tan(pi h / (2 h_y)),  f_r = tan(pi S / (2 S_y)),
//   each +infinity (impassable) when its value reaches the threshold;
//   g = w_s f_s + w_e f_e + w_r f_r;
//   move cost = w1 * g * scale + w2 * d, d the horizontal move length in metres and scale = 1
//   (the paper: g charged per move) or d / resolution (cost_per_metre);
//   G(child) = G(parent) + move cost.
// Heuristics: the paper's H = Euclidean distance to the goal (can overestimate: not admissible),
// and the admissible form H = w2 * Euclidean distance (consistent, so A* is optimal).
#include <cmath>
#include <limits>
#include <string>

namespace starnav {

struct LiuCostParams {
  // Thresholds (Table 1).
  double h_y = 0.05;  // height difference, m
  double a_y = 0.5;   // slope, rad
  double s_y = 0.02;  // ruggedness (3x3 height variance), m^2
  // Weights of g (sum 1) and of G.
  double w_s = 0.33;
  double w_e = 0.33;
  double w_r = 0.34;
  double w1 = 0.5;
  double w2 = 0.5;
  // Scale g by d / resolution (1 for straight moves, sqrt 2 for diagonals), so the cost of a
  // route does not depend on the grid resolution. Off: the paper's per-move g.
  bool cost_per_metre = false;
  // g of a move that touches an unobserved cell when unobserved cells have an "unknown cost"
  // (UnobservedPolicy::UnknownCost): 1 = the g of terrain at half of every threshold.
  double unobserved_g = 1.0;

  // Throws Error naming the field: thresholds finite and > 0, weights finite and >= 0,
  // w_s + w_e + w_r = 1 (within 1e-6), unobserved_g finite and >= 0.
  void validate() const;
};

inline constexpr double kImpassable = std::numeric_limits<double>::infinity();

// tan(pi v / (2 v_y)) for 0 <= v < v_y, +infinity from v_y on (v is a magnitude: negative
// values are taken by absolute value).
inline double liu_tan_cost(double v, double v_y) {
  v = std::abs(v);
  if (!(v < v_y)) return kImpassable;
  return std::tan(1.5707963267948966 * v / v_y);
}
inline double liu_f_slope(double a, const LiuCostParams& p) { return liu_tan_cost(a, p.a_y); }
inline double liu_f_step(double h, const LiuCostParams& p) { return liu_tan_cost(h, p.h_y); }
inline double liu_f_rugged(double s, const LiuCostParams& p) { return liu_tan_cost(s, p.s_y); }

// Whether a move with slope a and step h into a child of ruggedness s is passable (every value
// below its threshold).
inline bool liu_passable(double a, double h, double s, const LiuCostParams& p) {
  return std::abs(a) < p.a_y && std::abs(h) < p.h_y && std::abs(s) < p.s_y;
}

// g = w_s f_s + w_e f_e + w_r f_r; +infinity when any threshold is reached (even with a zero
// weight: passability does not depend on the weights).
double liu_g(double a, double h, double s, const LiuCostParams& p);

// The move cost from its three terms (f_s, f_e, f_r all finite): w1 * g * scale + w2 * d with
// g = w_s f_s + w_e f_e + w_r f_r. liu_move_cost is this; callers that cache the terms (the
// IA* move-cost table: f_s and f_e per neighbour pair, f_r per cell) get identical bits.
inline double liu_move_cost_from_terms(double f_s, double f_e, double f_r, double d, double resolution,
                                       const LiuCostParams& p) {
  const double g = p.w_s * f_s + p.w_e * f_e + p.w_r * f_r;
  const double scale = p.cost_per_metre ? d / resolution : 1.0;
  return p.w1 * g * scale + p.w2 * d;
}

// Slope of a move: atan(h / l).
inline double liu_slope(double h, double l) { return std::atan(std::abs(h) / l); }

// Cost of one move: w1 * g * (cost_per_metre ? d / resolution : 1) + w2 * d, +infinity when
// impassable. d: horizontal length of the move, metres.
double liu_move_cost(double a, double h, double s_child, double d, double resolution, const LiuCostParams& p);
// The same from the two heights and the move length (a = atan(|z2 - z1| / d)).
double liu_move_cost_from_heights(double z_parent, double z_child, double s_child, double d, double resolution,
                                  const LiuCostParams& p);

enum class LiuHeuristic {
  Paper,       // H = Euclidean distance to the goal (may overestimate: not admissible)
  Admissible,  // H = w2 * Euclidean distance (consistent: optimal costs)
};
const char* liu_heuristic_name(LiuHeuristic h);  // "paper", "admissible"
// Parses "paper" or "admissible"; throws Error naming `field` otherwise.
LiuHeuristic parse_liu_heuristic(const std::string& name, const std::string& field = "heuristic");

// H for a horizontal distance to the goal (metres).
inline double liu_heuristic(double distance_m, LiuHeuristic kind, const LiuCostParams& p) {
  return kind == LiuHeuristic::Paper ? distance_m : p.w2 * distance_m;
}

}  // namespace starnav
