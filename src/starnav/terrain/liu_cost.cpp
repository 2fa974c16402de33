#include "starnav/terrain/liu_cost.hpp"

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

void LiuCostParams::validate() const {
  require_positive(h_y, "h_y");
  require_positive(a_y, "a_y");
  if (a_y >= 1.5707963267948966) throw Error("must be below pi/2", {}, 0, "a_y");
  require_positive(s_y, "s_y");
  require_non_negative(w_s, "w_s");
  require_non_negative(w_e, "w_e");
  require_non_negative(w_r, "w_r");
  require_non_negative(w1, "w1");
  require_non_negative(w2, "w2");
  require_non_negative(unobserved_g, "unobserved_g");
  if (std::abs(w_s + w_e + w_r - 1.0) > 1e-6)
    throw Error("w_s + w_e + w_r must be 1, got " + format_number(w_s + w_e + w_r), {}, 0, "weights");
}

double liu_g(double a, double h, double s, const LiuCostParams& p) {
  if (!liu_passable(a, h, s, p)) return kImpassable;
  return p.w_s * liu_f_slope(a, p) + p.w_e * liu_f_step(h, p) + p.w_r * liu_f_rugged(s, p);
}

double liu_move_cost(double a, double h, double s_child, double d, double resolution, const LiuCostParams& p) {
  if (!liu_passable(a, h, s_child, p)) return kImpassable;
  return liu_move_cost_from_terms(liu_f_slope(a, p), liu_f_step(h, p), liu_f_rugged(s_child, p), d, resolution, p);
}

double liu_move_cost_from_heights(double z_parent, double z_child, double s_child, double d, double resolution,
                                  const LiuCostParams& p) {
  const double h = std::abs(z_child - z_parent);
  return liu_move_cost(liu_slope(h, d), h, s_child, d, resolution, p);
}

const char* liu_heuristic_name(LiuHeuristic h) { return h == LiuHeuristic::Paper ? "paper" : "admissible"; }

LiuHeuristic parse_liu_heuristic(const std::string& name, const std::string& field) {
  if (name == "paper") return LiuHeuristic::Paper;
  if (name == "admissible") return LiuHeuristic::Admissible;
  throw Error("unknown heuristic '" + name + "' (paper, admissible)", {}, 0, field);
}

}  // namespace starnav
