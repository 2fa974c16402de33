#include "starnav/plan/hybrid_astar.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/car_curves.hpp"

namespace starnav {

namespace {

constexpr double kHybridInf = std::numeric_limits<double>::infinity();
// The largest ratio of the octile distance to the Euclidean one (at 22.5 degrees): an 8-connected
// path on grid corners is at most this much longer than the shortest path among the cells
// (Nash and Koenig 2013, "Any-angle path planning"), so dividing by it keeps the bound below.
const double kHybridOctileRatio = std::sqrt(4.0 - 2.0 * std::sqrt(2.0));
constexpr std::uint8_t kHybridNoMotion = 255;

// The motions the search may take, by index: 0..2 forward straight/left/right, 3..5 reverse,
// 6..7 turn on the spot left/right, 8..9 sideways left/right.
int hybrid_primitive_count(HybridMotionModel m) {
  switch (m) {
    case HybridMotionModel::Dubins: return 3;
    case HybridMotionModel::ReedsShepp: return 6;
    case HybridMotionModel::Diff: return 8;
    case HybridMotionModel::Omni: return 10;
  }
  return 3;
}

bool hybrid_turns_on_the_spot(HybridMotionModel m) { return m == HybridMotionModel::Diff || m == HybridMotionModel::Omni; }

struct HybridCostModel {
  const HybridAStarOptions* options;
  // A motion's cost given the motion before it (nullptr: the first) and its mean costmap
  // multiplier (1 + cost_penalty * normalised cost over its samples).
  double operator()(const HybridMotion& m, const HybridMotion* before, double multiplier) const {
    const HybridAStarOptions& o = *options;
    double c = (m.kind == HybridMotion::Kind::Rotate ? o.rotation_penalty_m_per_rad : 1.0) * std::abs(m.length) * multiplier;
    if (m.kind == HybridMotion::Kind::Arc && m.curvature != 0.0) {
      const bool changed = before && !(before->kind == m.kind && before->curvature == m.curvature &&
                                       (before->length < 0.0) == (m.length < 0.0));
      c *= o.non_straight_penalty + (changed ? o.change_penalty : 0.0);
    }
    if (m.reverse()) c *= o.reverse_penalty;
    if (before && before->kind == HybridMotion::Kind::Arc && m.kind == HybridMotion::Kind::Arc &&
        before->reverse() != m.reverse())
      c += o.cusp_penalty_m;
    return c;
  }
};

double hybrid_path_length(const std::vector<HybridMotion>& motions) {
  double l = 0.0;
  for (const HybridMotion& m : motions)
    if (m.kind != HybridMotion::Kind::Rotate) l += std::abs(m.length);
  return l;
}

// The motions of an obstacle-free curve.
void append_hybrid_curve(const CarPath& path, std::vector<HybridMotion>& out) {
  double s = 0.0;
  for (std::size_t i = 0; i < path.segment_count; ++i) {
    const CurveSegment& seg = path.segments[i];
    HybridMotion m;
    m.kind = HybridMotion::Kind::Arc;
    m.start = i == 0 ? path.start : path.pose_at(s);
    m.curvature = path.curvature(seg);
    m.length = seg.length;
    out.push_back(m);
    s += std::abs(seg.length);
  }
}

}  // namespace

const char* hybrid_motion_model_name(HybridMotionModel m) {
  switch (m) {
    case HybridMotionModel::Dubins: return "dubins";
    case HybridMotionModel::ReedsShepp: return "reeds_shepp";
    case HybridMotionModel::Diff: return "diff";
    case HybridMotionModel::Omni: return "omni";
  }
  return "unknown";
}

Pose2 HybridMotion::pose_at(double t) const {
  t = std::clamp(t, 0.0, std::abs(length));
  switch (kind) {
    case Kind::Rotate: return {start.x, start.y, start.yaw + (length < 0.0 ? -t : t)};
    case Kind::Sideways: {
      const double d = length < 0.0 ? -t : t;
      return {start.x - std::sin(start.yaw) * d, start.y + std::cos(start.yaw) * d, start.yaw};
    }
    case Kind::Arc: break;
  }
  const double s = length < 0.0 ? -t : t;
  if (curvature == 0.0) return {start.x + std::cos(start.yaw) * s, start.y + std::sin(start.yaw) * s, start.yaw};
  const double yaw = start.yaw + curvature * s;
  return {start.x + (std::sin(yaw) - std::sin(start.yaw)) / curvature,
          start.y - (std::cos(yaw) - std::cos(start.yaw)) / curvature, yaw};
}

void HybridAStarOptions::validate() const {
  const auto check = [](bool ok, const char* key, const char* what) {
    if (!ok) throw Error(what, {}, 0, key);
  };
  const auto finite = [](double v) { return std::isfinite(v); };
  check(minimum_turning_radius_m > 0.0 && finite(minimum_turning_radius_m), "minimum_turning_radius_m", "must be > 0");
  check(angle_bins >= 4 && angle_bins <= 4096, "angle_bins", "must be in [4, 4096]");
  check(non_straight_penalty >= 1.0 && finite(non_straight_penalty), "non_straight_penalty", "must be >= 1");
  check(change_penalty >= 0.0 && finite(change_penalty), "change_penalty", "must be >= 0");
  check(reverse_penalty >= 1.0 && finite(reverse_penalty), "reverse_penalty", "must be >= 1");
  check(cusp_penalty_m >= 0.0 && finite(cusp_penalty_m), "cusp_penalty_m", "must be >= 0");
  check(rotation_penalty_m_per_rad >= 0.0 && finite(rotation_penalty_m_per_rad), "rotation_penalty_m_per_rad",
        "must be >= 0");
  check(cost_penalty >= 0.0 && finite(cost_penalty), "cost_penalty", "must be >= 0");
  check(inflation_radius_m >= 0.0 && finite(inflation_radius_m), "inflation_radius_m", "must be >= 0");
  check(cost_scaling_factor >= 0.0 && finite(cost_scaling_factor), "cost_scaling_factor", "must be >= 0");
  check(robot_radius_m >= 0.0 && finite(robot_radius_m), "robot_radius_m", "must be >= 0");
  check(footprint_length_m >= 0.0 && finite(footprint_length_m), "footprint_length_m", "must be >= 0");
  check(footprint_width_m >= 0.0 && finite(footprint_width_m), "footprint_width_m", "must be >= 0");
  check((footprint_length_m > 0.0) == (footprint_width_m > 0.0), footprint_length_m > 0.0 ? "footprint_width_m" : "footprint_length_m",
        "give both footprint_length_m and footprint_width_m (a rectangle), or neither (the circle of robot_radius_m)");
  check(finite(footprint_center_x_m), "footprint_center_x_m", "must be a finite number");
  check(collision_step_m >= 0.0 && finite(collision_step_m), "collision_step_m", "must be >= 0");
  check(path_step_m >= 0.0 && finite(path_step_m), "path_step_m", "must be >= 0");
  check(heuristic_weight >= 1.0 && finite(heuristic_weight), "heuristic_weight", "must be >= 1");
  check(analytic_expansion_ratio > 0.0 && finite(analytic_expansion_ratio), "analytic_expansion_ratio", "must be > 0");
  check(analytic_expansion_max_length_m >= 0.0 && finite(analytic_expansion_max_length_m),
        "analytic_expansion_max_length_m", "must be >= 0");
  check(max_planning_time_s >= 0.0 && finite(max_planning_time_s), "max_planning_time_s", "must be >= 0");
}

FootprintModel HybridAStarOptions::footprint() const {
  FootprintModel m;
  if (footprint_length_m > 0.0) {
    m.circle = false;
    m.half_length_m = 0.5 * footprint_length_m;
    m.half_width_m = 0.5 * footprint_width_m;
  } else {
    m.circle = true;
    m.radius_m = robot_radius_m;
  }
  m.center_x_m = footprint_center_x_m;
  return m;
}

const ParamTable<HybridAStarOptions>& hybrid_astar_params() {
  static const ParamTable<HybridAStarOptions> table = [] {
    using C = HybridAStarOptions;
    ParamTable<C> t;
    t.choice(
        "motion_model", {"dubins", "reeds_shepp", "diff", "omni"},
        [](C& c, const std::string& v) {
          c.motion_model = v == "dubins"        ? HybridMotionModel::Dubins
                           : v == "reeds_shepp" ? HybridMotionModel::ReedsShepp
                           : v == "diff"        ? HybridMotionModel::Diff
                                                : HybridMotionModel::Omni;
        },
        [](const C& c) { return std::string(hybrid_motion_model_name(c.motion_model)); },
        "dubins: forward only; reeds_shepp: forward and reverse; diff: also turns on the spot; omni: also steps sideways");
    t.real("minimum_turning_radius_m", &C::minimum_turning_radius_m, positive(), "m", "the arcs' radius R (Nav2 default 0.4)");
    t.integer("angle_bins", &C::angle_bins, closed(4, 4096), "", "heading bins of the search (Nav2: angle_quantization_bins)");
    t.real("non_straight_penalty", &C::non_straight_penalty, ParamRange{1.0, kInfinity, false, false}, "",
           "multiplies the cost of an arc");
    t.real("change_penalty", &C::change_penalty, non_negative(), "",
           "added to the arc multiplier when the motion before was a different one (Nav2's)");
    t.real("reverse_penalty", &C::reverse_penalty, ParamRange{1.0, kInfinity, false, false}, "",
           "multiplies the cost of a reverse motion");
    t.real("cusp_penalty_m", &C::cusp_penalty_m, non_negative(), "m", "added at each change between forward and reverse");
    t.real("rotation_penalty_m_per_rad", &C::rotation_penalty_m_per_rad, non_negative(), "m/rad",
           "diff, omni: the cost of turning on the spot per radian");
    t.real("cost_penalty", &C::cost_penalty, non_negative(), "",
           "a motion costs its length times 1 + cost_penalty * the normalised inflation cost");
    t.real("inflation_radius_m", &C::inflation_radius_m, non_negative(), "m",
           "the inflation cost reaches this far from an obstacle (costmap inflation_radius)");
    t.real("cost_scaling_factor", &C::cost_scaling_factor, non_negative(), "1/m", "decay of the inflation cost");
    t.real("robot_radius_m", &C::robot_radius_m, non_negative(), "m", "the footprint's circle when no rectangle is given");
    t.real("footprint_length_m", &C::footprint_length_m, non_negative(), "m",
           "the footprint's rectangle along x (0: the circle)");
    t.real("footprint_width_m", &C::footprint_width_m, non_negative(), "m", "the footprint's rectangle along y");
    t.real("footprint_center_x_m", &C::footprint_center_x_m, ParamRange{-kInfinity, kInfinity, false, false}, "m",
           "the footprint's centre ahead of base_link (a car's base_link is its rear axle)");
    for (const char* key : {"robot_radius_m", "footprint_length_m", "footprint_width_m", "footprint_center_x_m"})
      t.default_rule(key, "in navigation: the robot's body box unless any footprint key is set");
    t.default_rule("minimum_turning_radius_m", "in navigation: an Ackermann robot's own (wheelbase / tan(max steer)); else 0.4 (Nav2)");
    t.real("collision_step_m", &C::collision_step_m, non_negative(), "m",
           "footprint checks along every motion at most this far apart (0: half a cell)");
    t.real("path_step_m", &C::path_step_m, non_negative(), "m", "the returned poses at most this far apart (0: one cell)");
    t.real("heuristic_weight", &C::heuristic_weight, ParamRange{1.0, kInfinity, false, false}, "",
           "f = g + weight * h (1: the heuristic stays admissible; above 1: weighted A*, faster, costlier paths)");
    t.real("analytic_expansion_ratio", &C::analytic_expansion_ratio, positive(), "",
           "try the curve to the goal every max(1, h / (ratio * cell)) expansions");
    t.real("analytic_expansion_max_length_m", &C::analytic_expansion_max_length_m, non_negative(), "m",
           "longest curve to the goal tried (0: no limit)");
    t.integer("max_iterations", &C::max_iterations, positive(), "", "expansions before giving up");
    t.real("max_planning_time_s", &C::max_planning_time_s, non_negative(), "s", "search time before giving up (0: no limit)");
    t.boolean("smooth", &C::smooth, "shorten the path with free curves of radius >= R between its poses");
    return t;
  }();
  return table;
}

void sample_hybrid_motions(const std::vector<HybridMotion>& motions, double step, std::vector<Pose2>& poses,
                           std::vector<std::uint8_t>& reversing) {
  if (!(step > 0.0)) throw Error("must be > 0", {}, 0, "path_step_m");
  poses.clear();
  reversing.clear();
  for (std::size_t k = 0; k < motions.size(); ++k) {
    const HybridMotion& m = motions[k];
    const std::uint8_t rev = m.reverse() ? 1 : 0;
    if (k == 0) {
      poses.push_back(m.start);
      reversing.push_back(rev);
    } else {
      reversing.back() = rev;  // the end of the motion before starts this one
    }
    const double total = std::abs(m.length);
    if (m.kind != HybridMotion::Kind::Rotate) {
      const int n = static_cast<int>(std::ceil(total / step - 1e-9));
      for (int i = 1; i < n; ++i) {
        poses.push_back(m.pose_at(i * step));
        reversing.push_back(rev);
      }
    }
    poses.push_back(m.end());
    reversing.push_back(rev);
  }
  for (Pose2& p : poses) p.yaw = wrap_angle(p.yaw);
}

// ---- the planner ---------------------------------------------------------------------------------

struct HybridAStar::Impl {
  GridGeometry geometry;  // the map's
  ClearanceWindow window;
  FootprintChecker checker;
  double inscribed_m = 0.0;
  double collision_step = 0.0;
  std::vector<float> multiplier;       // per window cell: 1 + cost_penalty * normalised cost
  std::vector<std::uint8_t> passable;  // per window cell: the robot's centre may be in it
  // The obstacle distance from the goal per window corner (width + 1 by height + 1), found lazily:
  // an A* from the goal's corner toward the start's (a reverse resumable A*, Silver 2005), resumed
  // whenever a corner not yet settled is asked for. Its heuristic (the octile distance to the
  // start's corner) is consistent, so every settled corner has its exact distance; a query plans
  // only as much of the map as its search touches. Stamps mark the corners of this query.
  struct CornerEntry {
    double f;
    std::uint32_t corner;
    bool operator>(const CornerEntry& o) const { return f > o.f || (f == o.f && corner > o.corner); }
  };
  std::vector<double> corner_g;
  std::vector<std::uint32_t> corner_seen, corner_settled;  // == corner_stamp: this query's
  std::uint32_t corner_stamp = 0;
  std::vector<CornerEntry> corner_open;  // a binary heap (std::push_heap with std::greater)
  int corner_target_i = 0, corner_target_j = 0;
  double goal_corner_offset = 0.0;
  Pose2 goal;
  bool has_goal = false;
  HybridMotionModel model = HybridMotionModel::ReedsShepp;
  double radius = 1.0;

  std::size_t cell_index(const Pose2& p, bool& inside) const {
    const Cell c = window.cell_of({p.x, p.y});
    inside = window.contains(c.x, c.y);
    return inside ? window.index(c.x, c.y) : 0;
  }

  double cell_multiplier(const Pose2& p) const {
    bool inside = false;
    const std::size_t i = cell_index(p, inside);
    return inside ? multiplier[i] : 1.0;
  }

  bool collides(const Pose2& p) const { return checker.collides(window, p); }

  // The checker's growth below its rule down to the footprint itself (the rule grows it by half a
  // cell's diagonal): a start whose footprint holds an obstacle cell centre is blocked.
  double footprint_extra_m = 0.0;

  // Whether motion `m` keeps the footprint clear at every collision step after its start (its
  // start is known clear); `mean_multiplier` gets the mean costmap multiplier over those samples.
  // With a finite `escape_extra` (the path is still leaving its start, which may lie nearer an
  // obstacle than the rule allows, or so near that the growth for the motion between the samples
  // blocks every first step), the samples need only be clear at that growth (the start's own:
  // no nearer than the start), until the first that clears the rule, which ends the escape
  // (`escape_extra` becomes infinite: a path never re-enters the band once out of it).
  bool motion_clear(const HybridMotion& m, double& mean_multiplier, double* escape_extra = nullptr) const {
    const double total = std::abs(m.length);
    // The farthest point of the footprint moves farther than base_link: bounding radius * angle
    // turning on the spot, (1 + |curvature| * bounding radius) * length on an arc.
    const double b = std::max(checker.model().bounding_radius_m(), 1e-3);
    const double span = m.kind == HybridMotion::Kind::Rotate ? total * b
                        : m.kind == HybridMotion::Kind::Arc  ? total * (1.0 + std::abs(m.curvature) * b)
                                                             : total;
    const int n = std::max(1, static_cast<int>(std::ceil(span / collision_step - 1e-9)));
    // Between two checks no point of the body moves more than span / n: every pose in between
    // lies within half that of a checked one, so checking the body grown by it misses nothing.
    const double between = 0.5 * span / n;
    double sum = 0.0;
    for (int i = 1; i <= n; ++i) {
      const Pose2 p = m.pose_at(total * i / n);
      if (escape_extra && *escape_extra < kHybridInf) {
        if (!checker.collides(window, p, between)) *escape_extra = kHybridInf;
        else if (checker.collides(window, p, *escape_extra)) return false;
      } else if (checker.collides(window, p, between)) {
        return false;
      }
      sum += cell_multiplier(p);
    }
    mean_multiplier = sum / n;
    return true;
  }

  // The obstacle distance bound at `p` (+inf where the centre cannot go).
  double obstacle_bound(const Pose2& p) {
    bool inside = false;
    cell_index(p, inside);
    if (!inside) return kHybridInf;
    const Cell c = window.cell_of({p.x, p.y});
    const int w1 = window.width() + 1;
    double best = -kHybridInf;
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const double d = corner_distance(static_cast<std::size_t>(c.y + dy) * static_cast<std::size_t>(w1) +
                                         static_cast<std::size_t>(c.x + dx));
        if (d == kHybridInf) continue;  // another corner may still reach
        const Vec2 cw = corner_world(c.x + dx, c.y + dy);
        const double e = std::hypot(cw.x() - p.x, cw.y() - p.y);
        best = std::max(best, d / kHybridOctileRatio - e);
      }
    if (best == -kHybridInf) return kHybridInf;
    return std::max(0.0, best - goal_corner_offset);
  }

  // World position of window corner (i, j): the lower-left corner of cell (i, j).
  Vec2 corner_world(int i, int j) const {
    const Vec2 a = window.cell_center(i, j);
    const Vec2 ex = window.cell_center(i + 1, j) - a, ey = window.cell_center(i, j + 1) - a;
    return a - 0.5 * ex - 0.5 * ey;
  }

  double curve_bound(const Pose2& p) const {
    if (hybrid_turns_on_the_spot(model)) return std::hypot(goal.x - p.x, goal.y - p.y);
    const CarPath c = model == HybridMotionModel::Dubins ? shortest_dubins_path(p, goal, radius)
                                                         : shortest_reeds_shepp_path(p, goal, radius);
    return c.length;
  }

  // The corner graph: a horizontal or vertical step along a cell edge needs one of the two cells
  // beside it passable, a diagonal step across a cell needs that cell passable.
  bool pass(int x, int y) const {
    return x >= 0 && y >= 0 && x < window.width() && y < window.height() && passable[window.index(x, y)] != 0;
  }

  // Octile distance (m) from corner (i, j) to the start's corner: consistent for the corner graph.
  double corner_h(int i, int j) const {
    const double dx = std::abs(i - corner_target_i), dy = std::abs(j - corner_target_j);
    const double res = window.resolution();
    return res * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  }

  // Starts the distances from the goal's nearest corner toward the start's; nothing is expanded.
  void reset_corner_field(const Pose2& g, const Pose2& s) {
    const int w1 = window.width() + 1, h1 = window.height() + 1;
    const std::size_t corners = static_cast<std::size_t>(w1) * static_cast<std::size_t>(h1);
    if (corner_g.size() != corners || corner_stamp == std::numeric_limits<std::uint32_t>::max()) {
      corner_g.assign(corners, kHybridInf);
      corner_seen.assign(corners, 0);
      corner_settled.assign(corners, 0);
      corner_stamp = 0;
    }
    ++corner_stamp;
    corner_open.clear();
    const Cell gc = window.cell_of({g.x, g.y});
    int bi = gc.x, bj = gc.y;
    double be = kHybridInf;
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const Vec2 cw = corner_world(gc.x + dx, gc.y + dy);
        const double e = std::hypot(cw.x() - g.x, cw.y() - g.y);
        if (e < be) be = e, bi = gc.x + dx, bj = gc.y + dy;
      }
    goal_corner_offset = be;
    const Cell sc = window.cell_of({s.x, s.y});
    corner_target_i = std::clamp(sc.x, 0, w1 - 1);
    corner_target_j = std::clamp(sc.y, 0, h1 - 1);
    const auto k = static_cast<std::uint32_t>(static_cast<std::size_t>(bj) * static_cast<std::size_t>(w1) + static_cast<std::size_t>(bi));
    corner_g[k] = 0.0;
    corner_seen[k] = corner_stamp;
    corner_open.push_back({corner_h(bi, bj), k});
  }

  // The exact obstacle distance of corner k from the goal's corner (+inf: unreachable), expanding
  // the A* until k is settled or nothing is left.
  double corner_distance(std::size_t k) {
    const int w1 = window.width() + 1, h1 = window.height() + 1;
    const double res = window.resolution(), diag = res * std::sqrt(2.0);
    while (corner_settled[k] != corner_stamp) {
      if (corner_open.empty()) return kHybridInf;
      std::pop_heap(corner_open.begin(), corner_open.end(), std::greater<>());
      const std::uint32_t u = corner_open.back().corner;
      corner_open.pop_back();
      if (corner_settled[u] == corner_stamp) continue;  // a stale entry
      corner_settled[u] = corner_stamp;
      const double d = corner_g[u];
      const int i = static_cast<int>(u % static_cast<std::uint32_t>(w1)), j = static_cast<int>(u / static_cast<std::uint32_t>(w1));
      const auto relax = [&](int ni, int nj, double step) {
        if (ni < 0 || nj < 0 || ni >= w1 || nj >= h1) return;
        const auto v = static_cast<std::uint32_t>(static_cast<std::size_t>(nj) * static_cast<std::size_t>(w1) + static_cast<std::size_t>(ni));
        if (corner_settled[v] == corner_stamp) return;
        if (corner_seen[v] != corner_stamp) {
          corner_seen[v] = corner_stamp;
          corner_g[v] = kHybridInf;
        }
        const double nd = d + step;
        if (nd < corner_g[v]) {
          corner_g[v] = nd;
          corner_open.push_back({nd + corner_h(ni, nj), v});
          std::push_heap(corner_open.begin(), corner_open.end(), std::greater<>());
        }
      };
      if (pass(i, j - 1) || pass(i, j)) relax(i + 1, j, res);
      if (pass(i - 1, j - 1) || pass(i - 1, j)) relax(i - 1, j, res);
      if (pass(i - 1, j) || pass(i, j)) relax(i, j + 1, res);
      if (pass(i - 1, j - 1) || pass(i, j - 1)) relax(i, j - 1, res);
      if (pass(i, j)) relax(i + 1, j + 1, diag);
      if (pass(i - 1, j)) relax(i - 1, j + 1, diag);
      if (pass(i, j - 1)) relax(i + 1, j - 1, diag);
      if (pass(i - 1, j - 1)) relax(i - 1, j - 1, diag);
    }
    return corner_g[k];
  }
};

HybridAStar::HybridAStar(const OccupancyGrid& grid, const HybridAStarOptions& options)
    : impl_(std::make_unique<Impl>()), options_(options) {
  options_.validate();
  Impl& m = *impl_;
  m.geometry = grid.geometry();
  if (m.geometry.y_down) throw Error("Hybrid-A* plans on metric maps (rows bottom-up)", {}, 0, "map");
  const double res = m.geometry.resolution;
  const FootprintModel model = options_.footprint();
  m.checker = FootprintChecker(model, 0.0);
  m.footprint_extra_m = -0.5 * std::sqrt(2.0) * res;
  m.inscribed_m = model.inscribed_radius_m();
  m.collision_step = options_.collision_step_m > 0.0 ? std::min(options_.collision_step_m, 0.5 * res) : 0.5 * res;
  m.model = options_.motion_model;
  m.radius = options_.minimum_turning_radius_m;
  // One window over the whole map; unknown cells are obstacles unless the grid options free them.
  OccupancyGrid obstacles = grid;
  if (!options_.unknown_is_free)
    for (std::int8_t& v : obstacles.data())
      if (options_.thresholds.classify(v) == CellState::Unknown) v = kOccupiedOccupancy;
  const Vec2 centre = m.geometry.grid_to_world({0.5 * m.geometry.width * res, 0.5 * m.geometry.height * res});
  const double half = 0.5 * std::max(m.geometry.width, m.geometry.height) * res + res;
  m.window.build(obstacles, centre, half, model.bounding_radius_m() + 2.0 * res, options_.thresholds);
  const std::size_t cells = static_cast<std::size_t>(m.window.width()) * static_cast<std::size_t>(m.window.height());
  m.multiplier.resize(cells);
  m.passable.resize(cells);
  for (std::size_t i = 0; i < cells; ++i) {
    const double d = m.window.clearance_m(i);
    // Nav2's normalised cost: 1 up to the inscribed radius, exp(-k (d - r_in)) out to the
    // inflation radius, 0 beyond.
    const double c = d <= m.inscribed_m ? 1.0
                     : d <= options_.inflation_radius_m ? std::exp(-options_.cost_scaling_factor * (d - m.inscribed_m))
                                                        : 0.0;
    m.multiplier[i] = static_cast<float>(1.0 + options_.cost_penalty * c);
    // A centre in a cell whose centre lies within r_in of an obstacle cell's centre always
    // collides under the checker's rule (footprint grown by half a cell's diagonal).
    m.passable[i] = d > m.inscribed_m ? 1 : 0;
  }
  const double bin = 2.0 * kPi / options_.angle_bins;
  const double r = options_.minimum_turning_radius_m;
  // Nav2's primitive: the smallest arc whose chord spans a cell diagonal, rounded up to whole bins.
  const double angle = 2.0 * std::asin(std::min(1.0, std::sqrt(2.0) * res / (2.0 * r)));
  turn_bins_ = std::max(1, static_cast<int>(std::ceil(angle / bin - 1e-9)));
  step_ = r * turn_bins_ * bin;
}

HybridAStar::~HybridAStar() = default;

bool HybridAStar::collides(const Pose2& pose) const { return impl_->collides(pose); }

double HybridAStar::curve_heuristic(const Pose2& pose) const {
  if (!impl_->has_goal) throw Error("no goal yet: plan first", {}, 0, "goal");
  return impl_->curve_bound(pose);
}
double HybridAStar::obstacle_heuristic(const Pose2& pose) const {
  if (!impl_->has_goal) throw Error("no goal yet: plan first", {}, 0, "goal");
  return impl_->obstacle_bound(pose);
}
double HybridAStar::heuristic(const Pose2& pose) const { return std::max(curve_heuristic(pose), obstacle_heuristic(pose)); }

namespace {

struct HybridSearchNode {
  Pose2 pose;
  double g = 0.0;
  std::int32_t parent = -1;
  std::uint8_t motion = kHybridNoMotion;
  bool closed = false;
  double escape_extra = kHybridInf;  // still leaving the start's band (motion_clear)
};

struct HybridOpenEntry {
  double f;
  double g;
  std::uint64_t seq;
  std::int32_t node;
  bool operator>(const HybridOpenEntry& o) const {
    if (f != o.f) return f > o.f;
    if (g != o.g) return g < o.g;  // ties: the deeper state first
    return seq > o.seq;
  }
};

}  // namespace

PlanResult HybridAStar::plan(const Pose2& start, const Pose2& goal, const SearchLimits& limits) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Impl& m = *impl_;
  PlanResult r;
  motions_.clear();
  const auto finish = [&](PlanStatus s) {
    r.status = s;
    r.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return r;
  };
  const auto finite_pose = [](const Pose2& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw); };
  if (!finite_pose(start)) throw Error("the start pose is not finite", {}, 0, "start");
  if (!finite_pose(goal)) throw Error("the goal pose is not finite", {}, 0, "goal");
  m.has_goal = false;
  if (!m.geometry.world_to_cell({start.x, start.y})) return finish(PlanStatus::StartOutsideMap);
  if (!m.geometry.world_to_cell({goal.x, goal.y})) return finish(PlanStatus::GoalOutsideMap);
  // A start the rule calls blocked but whose footprint itself holds no obstacle cell centre (a
  // robot beside a sensed wall, nearer than the rule's half cell) is not: the path may leave it
  // by poses no nearer than it (motion_clear). Its margin: the largest growth it is clear at,
  // to 1/64 of the rule's.
  if (m.checker.collides(m.window, start, m.footprint_extra_m)) return finish(PlanStatus::StartBlocked);
  double start_escape = m.footprint_extra_m;
  if (!m.collides(start)) {
    start_escape = 0.0;
  } else {
    double hi = 0.0;  // collides at hi, clear at start_escape
    for (int k = 0; k < 6; ++k) {
      const double mid = 0.5 * (start_escape + hi);
      (m.checker.collides(m.window, start, mid) ? hi : start_escape) = mid;
    }
  }
  if (m.collides(goal)) return finish(PlanStatus::GoalBlocked);
  m.goal = goal;
  m.has_goal = true;
  m.reset_corner_field(goal, start);

  const HybridAStarOptions& o = options_;
  const HybridCostModel cost{&options_};
  const double res = m.geometry.resolution;
  const double bin = 2.0 * kPi / o.angle_bins;
  const int bins = o.angle_bins;
  const double r_turn = o.minimum_turning_radius_m;
  const int prims = hybrid_primitive_count(o.motion_model);
  std::uint64_t max_expansions = o.max_iterations;
  if (limits.max_expansions > 0) max_expansions = std::min(max_expansions, limits.max_expansions);
  double budget = o.max_planning_time_s;
  if (limits.time_budget_s > 0.0) budget = budget > 0.0 ? std::min(budget, limits.time_budget_s) : limits.time_budget_s;

  const auto make_motion = [&](const Pose2& from, int k) {
    HybridMotion mo;
    mo.start = from;
    if (k < 6) {
      mo.kind = HybridMotion::Kind::Arc;
      const int turn = k % 3;  // 0 straight, 1 left, 2 right
      mo.curvature = turn == 0 ? 0.0 : (turn == 1 ? 1.0 / r_turn : -1.0 / r_turn);
      mo.length = k < 3 ? step_ : -step_;
    } else if (k < 8) {
      mo.kind = HybridMotion::Kind::Rotate;
      mo.length = k == 6 ? bin : -bin;
    } else {
      mo.kind = HybridMotion::Kind::Sideways;
      mo.length = k == 8 ? step_ : -step_;
    }
    return mo;
  };
  const auto key_of = [&](const Pose2& p, bool& inside) -> std::uint64_t {
    const std::size_t c = m.cell_index(p, inside);
    const double a = std::floor(wrap_angle(p.yaw) / bin + 0.5);
    int b = static_cast<int>(a) % bins;
    if (b < 0) b += bins;
    return static_cast<std::uint64_t>(c) * static_cast<std::uint64_t>(bins) + static_cast<std::uint64_t>(b);
  };
  // The curve from `from` to the goal when it is free (and no longer than allowed): its motions
  // and cost after motion `before`.
  // The cost of `ms` after motion `before` when every motion is free (else infinity).
  const auto free_cost = [&](const std::vector<HybridMotion>& ms, const HybridMotion* before, double escape_extra) {
    double c = 0.0;
    const HybridMotion* prev = before;
    for (const HybridMotion& mo : ms) {
      double mult = 1.0;
      if (!m.motion_clear(mo, mult, &escape_extra)) return kHybridInf;
      c += cost(mo, prev, mult);
      prev = &mo;
    }
    return c;
  };
  const auto analytic = [&](const Pose2& from, const HybridMotion* before, double escape_extra, std::vector<HybridMotion>& out,
                            double& c) {
    out.clear();
    c = kHybridInf;
    const CarPath path = o.motion_model == HybridMotionModel::Dubins ? shortest_dubins_path(from, goal, r_turn)
                                                                      : shortest_reeds_shepp_path(from, goal, r_turn);
    if (!(o.analytic_expansion_max_length_m > 0.0 && path.length > o.analytic_expansion_max_length_m)) {
      append_hybrid_curve(path, out);
      c = free_cost(out, before, escape_extra);
    }
    if (hybrid_turns_on_the_spot(o.motion_model)) {
      // Turn towards the goal, drive straight to it, turn to its heading (omni: also straight,
      // sideways, turn); the cheapest free one.
      std::vector<HybridMotion> turn_drive_turn;
      Pose2 at = from;
      const double dist = std::hypot(goal.x - from.x, goal.y - from.y);
      if (dist > 1e-12) {
        const double bearing = std::atan2(goal.y - from.y, goal.x - from.x);
        const double turn1 = angle_diff(bearing, from.yaw);
        if (turn1 != 0.0) turn_drive_turn.push_back({HybridMotion::Kind::Rotate, at, 0.0, turn1});
        at = Pose2(from.x, from.y, from.yaw + turn1);
        turn_drive_turn.push_back({HybridMotion::Kind::Arc, at, 0.0, dist});
        at = turn_drive_turn.back().end();
      }
      const double turn2 = angle_diff(goal.yaw, at.yaw);
      if (turn2 != 0.0) turn_drive_turn.push_back({HybridMotion::Kind::Rotate, at, 0.0, turn2});
      const bool short_enough = !(o.analytic_expansion_max_length_m > 0.0 && dist > o.analytic_expansion_max_length_m);
      if (short_enough && !turn_drive_turn.empty()) {
        const double c2 = free_cost(turn_drive_turn, before, escape_extra);
        if (c2 < c) {
          c = c2;
          out = std::move(turn_drive_turn);
        }
      }
      if (short_enough && o.motion_model == HybridMotionModel::Omni && dist > 1e-12) {
        // Omni: straight along the heading, sideways, then turn to the goal's heading.
        const double cy = std::cos(from.yaw), sy = std::sin(from.yaw);
        const double along = cy * (goal.x - from.x) + sy * (goal.y - from.y);
        const double across = -sy * (goal.x - from.x) + cy * (goal.y - from.y);
        std::vector<HybridMotion> slide;
        Pose2 p = from;
        if (along != 0.0) {
          slide.push_back({HybridMotion::Kind::Arc, p, 0.0, along});
          p = slide.back().end();
        }
        if (across != 0.0) {
          slide.push_back({HybridMotion::Kind::Sideways, p, 0.0, across});
          p = slide.back().end();
        }
        const double turn = angle_diff(goal.yaw, p.yaw);
        if (turn != 0.0) slide.push_back({HybridMotion::Kind::Rotate, p, 0.0, turn});
        const double c3 = free_cost(slide, before, escape_extra);
        if (c3 < c) {
          c = c3;
          out = std::move(slide);
        }
      }
    }
    return c < kHybridInf;
  };

  std::vector<HybridSearchNode> nodes;
  std::unordered_map<std::uint64_t, std::int32_t> index;
  std::priority_queue<HybridOpenEntry, std::vector<HybridOpenEntry>, std::greater<>> open;
  std::uint64_t seq = 0;
  bool inside = false;
  nodes.push_back({start, 0.0, -1, kHybridNoMotion, false, start_escape});
  r.generated = 1;
  std::vector<HybridMotion> curve;
  double curve_cost = 0.0;
  std::int32_t reached = -1;
  // The curve from the start first, as the search's first expansion would try it: when it is
  // free, no heuristic is needed at all (the easy queries answer in the time of one curve check).
  if (analytic(start, nullptr, start_escape, curve, curve_cost)) {
    r.expanded = 1;
    reached = 0;
  } else {
    const double h0 = heuristic(start);
    if (h0 == kHybridInf) return finish(PlanStatus::NoPath);  // the centre cannot reach the goal's cells
    index.emplace(key_of(start, inside), 0);
    open.push({o.heuristic_weight * h0, 0.0, seq++, 0});
  }
  const double w = o.heuristic_weight;
  int since_analytic = 0;
  while (reached < 0 && !open.empty()) {
    const HybridOpenEntry e = open.top();
    open.pop();
    HybridSearchNode& n = nodes[static_cast<std::size_t>(e.node)];
    if (n.closed || e.g > n.g) continue;  // stale entry
    n.closed = true;
    ++r.expanded;
    if (r.expanded > max_expansions) return finish(PlanStatus::ExpansionLimit);
    if ((r.expanded & 63) == 0) {
      if (limits.cancel && limits.cancel->load()) return finish(PlanStatus::Cancelled);
      if (budget > 0.0 && std::chrono::duration<double>(Clock::now() - t0).count() > budget)
        return finish(PlanStatus::TimeLimit);
    }
    const Pose2 pose = n.pose;
    const double g = n.g;
    const std::int32_t id = e.node;
    const std::uint8_t came_by = n.motion;
    const double escape_extra = n.escape_extra;
    HybridMotion before_motion;
    if (came_by != kHybridNoMotion) before_motion = make_motion(nodes[static_cast<std::size_t>(n.parent)].pose, came_by);
    const HybridMotion* before = came_by != kHybridNoMotion ? &before_motion : nullptr;

    // Analytic expansion, more often near the goal (Nav2: every max(1, h / ratio) expansions, h in cells).
    // (The start's was tried before the search.)
    const double h = (e.f - g) / w;
    const int every = std::max(1, static_cast<int>(std::floor(h / res / o.analytic_expansion_ratio)));
    if (id != 0 && ++since_analytic >= every) {
      since_analytic = 0;
      if (analytic(pose, before, escape_extra, curve, curve_cost)) {
        reached = id;
        break;
      }
    }
    for (int k = 0; k < prims; ++k) {
      const HybridMotion mo = make_motion(pose, k);
      const Pose2 child = mo.end();
      const std::uint64_t key = key_of(child, inside);
      if (!inside) continue;
      const auto found = index.find(key);
      if (found != index.end() && nodes[static_cast<std::size_t>(found->second)].closed) continue;
      double mult = 1.0;
      double child_escape = escape_extra;
      if (!m.motion_clear(mo, mult, &child_escape)) continue;
      const double g2 = g + cost(mo, before, mult);
      std::int32_t cid;
      if (found == index.end()) {
        cid = static_cast<std::int32_t>(nodes.size());
        nodes.push_back({child, g2, id, static_cast<std::uint8_t>(k), false, child_escape});
        index.emplace(key, cid);
      } else {
        cid = found->second;
        HybridSearchNode& c = nodes[static_cast<std::size_t>(cid)];
        if (!(g2 < c.g)) continue;
        c = {child, g2, id, static_cast<std::uint8_t>(k), false, child_escape};
      }
      const double hc = heuristic(child);
      if (hc == kHybridInf) continue;
      open.push({g2 + w * hc, g2, seq++, cid});
      ++r.generated;
    }
  }
  if (reached < 0) return finish(PlanStatus::NoPath);

  // The motions: the search's from the start, then the curve.
  std::vector<std::int32_t> chain;
  for (std::int32_t k = reached; k >= 0; k = nodes[static_cast<std::size_t>(k)].parent) chain.push_back(k);
  std::reverse(chain.begin(), chain.end());
  for (std::size_t i = 1; i < chain.size(); ++i) {
    const HybridSearchNode& c = nodes[static_cast<std::size_t>(chain[i])];
    motions_.push_back(make_motion(nodes[static_cast<std::size_t>(c.parent)].pose, c.motion));
  }
  motions_.insert(motions_.end(), curve.begin(), curve.end());

  // Each motion's mean multiplier, so a path's cost is a sum over its motions.
  std::vector<double> mults(motions_.size(), 1.0);
  for (std::size_t i = 0; i < motions_.size(); ++i) {
    double mu = 1.0;
    m.motion_clear(motions_[i], mu);
    mults[i] = mu;
  }
  const auto total_cost = [&](const std::vector<HybridMotion>& ms, const std::vector<double>& mu) {
    double c = 0.0;
    for (std::size_t i = 0; i < ms.size(); ++i) c += cost(ms[i], i > 0 ? &ms[i - 1] : nullptr, mu[i]);
    return c;
  };
  // One shortest curve from the start needs no shortcut: every part of it is already the shortest
  // curve between its ends.
  if (o.smooth && motions_.size() > 1 && chain.size() > 1) {
    // Shortcuts: from each anchor, the farthest later pose (tried at halving distances) that the
    // shortest free curve reaches more cheaply replaces the motions between them.
    std::size_t i = 0;
    while (i + 1 < motions_.size()) {
      bool replaced = false;
      const double before_total = total_cost(motions_, mults);
      for (std::size_t span = motions_.size() - i; span >= 2; span = span / 2) {
        const std::size_t j = i + span;  // replace motions [i, j)
        const Pose2 a = motions_[i].start, b = motions_[j - 1].end();
        const CarPath path = o.motion_model == HybridMotionModel::Dubins ? shortest_dubins_path(a, b, r_turn)
                                                                          : shortest_reeds_shepp_path(a, b, r_turn);
        std::vector<HybridMotion> shortcut;
        append_hybrid_curve(path, shortcut);
        std::vector<double> mu;
        bool clear = true;
        for (const HybridMotion& mo : shortcut) {
          double x = 1.0;
          if (!m.motion_clear(mo, x)) {
            clear = false;
            break;
          }
          mu.push_back(x);
        }
        if (!clear) continue;
        std::vector<HybridMotion> ms(motions_.begin(), motions_.begin() + static_cast<std::ptrdiff_t>(i));
        std::vector<double> mus(mults.begin(), mults.begin() + static_cast<std::ptrdiff_t>(i));
        ms.insert(ms.end(), shortcut.begin(), shortcut.end());
        mus.insert(mus.end(), mu.begin(), mu.end());
        const std::size_t resume = ms.size();
        ms.insert(ms.end(), motions_.begin() + static_cast<std::ptrdiff_t>(j), motions_.end());
        mus.insert(mus.end(), mults.begin() + static_cast<std::ptrdiff_t>(j), mults.end());
        if (total_cost(ms, mus) < before_total - 1e-9) {
          motions_ = std::move(ms);
          mults = std::move(mus);
          i = resume;
          replaced = true;
          break;
        }
      }
      if (!replaced) ++i;
    }
  }

  const double path_step = o.path_step_m > 0.0 ? o.path_step_m : res;
  if (motions_.empty()) {
    r.path_poses = {start};
    r.path_reversing = {0};
  } else {
    sample_hybrid_motions(motions_, path_step, r.path_poses, r.path_reversing);
  }
  r.path_world.reserve(r.path_poses.size());
  for (const Pose2& p : r.path_poses) {
    r.path_world.emplace_back(p.x, p.y);
    const Cell c = m.geometry.world_to_cell_unchecked({p.x, p.y});
    if (r.path_cells.empty() || !(r.path_cells.back().x == c.x && r.path_cells.back().y == c.y)) r.path_cells.push_back(c);
  }
  r.cost = total_cost(motions_, mults);
  r.length = hybrid_path_length(motions_);
  (void)curve_cost;
  return finish(PlanStatus::Found);
}

// ---- the GlobalPlanner role -------------------------------------------------------------------------

namespace {

class HybridAStarGlobalPlanner final : public GlobalPlanner {
 public:
  explicit HybridAStarGlobalPlanner(const HybridAStarOptions& o) : options_(o) {}
  std::string_view name() const override { return "hybrid_astar"; }
  PlanResult plan(const PlanningLayers& /*layers*/, Cell /*start*/, Cell /*goal*/,
                  std::span<const CellChange> /*changed*/) override {
    throw Error("planner 'hybrid_astar' plans between poses: it needs the start and goal headings", {}, 0, "planner");
  }
  PlanResult plan_poses(const PlanningLayers& layers, const PlanQuery& query,
                        std::span<const CellChange> /*changed*/) override {
    if (!layers.occupancy) throw Error("planner 'hybrid_astar' needs an occupancy layer", {}, 0, "planner");
    if (!query.goal_heading)
      throw Error("planner 'hybrid_astar' plans to a goal pose: give the goal's heading", {}, 0, "goal.yaw_deg");
    // The distance field and costs are built once per map: kept while the map is unchanged.
    const OccupancyGrid& map = *layers.occupancy;
    if (!planner_ || !same_map(map)) {
      planner_.reset();
      planner_ = std::make_unique<HybridAStar>(map, options_);
      built_for_ = map;
    }
    return planner_->plan(query.start_pose, query.goal_pose);
  }

 private:
  bool same_map(const OccupancyGrid& map) const {
    const GridGeometry &a = map.geometry(), &b = built_for_.geometry();
    if (a.width != b.width || a.height != b.height || a.resolution != b.resolution || a.y_down != b.y_down ||
        a.origin.x != b.origin.x || a.origin.y != b.origin.y || a.origin.yaw != b.origin.yaw)
      return false;
    const std::span<const std::int8_t> x = map.data(), y = built_for_.data();
    return std::equal(x.begin(), x.end(), y.begin(), y.end());
  }

  HybridAStarOptions options_;
  std::unique_ptr<HybridAStar> planner_;
  OccupancyGrid built_for_;  // the map planner_ was built on
};

}  // namespace

GlobalPlannerDef hybrid_astar_global_planner() {
  GlobalPlannerDef d;
  d.info.role = Role::GlobalPlanner;
  d.info.name = "hybrid_astar";
  d.info.section = "hybrid_astar";
  d.info.summary = "Hybrid-A* (Nav2 Smac): SE2 search with Reeds-Shepp/Dubins expansions and the footprint checked";
  d.info.capabilities = {Capability::Occupancy, Capability::NeedsHeadings, Capability::ChecksFootprint};
  d.info.params = hybrid_astar_params().specs();
  d.make = [](const GlobalPlannerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GlobalPlanner> {
    HybridAStarOptions o = configured(hybrid_astar_params(), settings, ctx.file);
    const auto set = [&](std::string_view key) {
      return std::any_of(settings.begin(), settings.end(), [&](const ParamSetting& s) { return s.key == key; });
    };
    // In navigation the planner checks the robot's own body and turns no tighter than it can.
    if (ctx.robot_footprint && !set("robot_radius_m") && !set("footprint_length_m") && !set("footprint_width_m") &&
        !set("footprint_center_x_m")) {
      const FootprintModel& f = *ctx.robot_footprint;
      o.robot_radius_m = f.circle ? f.radius_m : o.robot_radius_m;
      o.footprint_length_m = f.circle ? 0.0 : 2.0 * f.half_length_m;
      o.footprint_width_m = f.circle ? 0.0 : 2.0 * f.half_width_m;
      o.footprint_center_x_m = f.center_x_m;
    }
    if (ctx.robot_min_turning_radius_m > 0.0 && !set("minimum_turning_radius_m"))
      o.minimum_turning_radius_m = ctx.robot_min_turning_radius_m;
    o.unknown_is_free = ctx.grid.unknown_is_free;
    o.thresholds = ctx.grid.thresholds;
    try {
      o.validate();
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
    return std::make_unique<HybridAStarGlobalPlanner>(o);
  };
  return d;
}

}  // namespace starnav
