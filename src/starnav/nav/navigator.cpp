#include "starnav/nav/navigator.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/polyline.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/path_smoothing.hpp"

namespace starnav {

const char* nav_status_name(NavStatus s) {
  switch (s) {
    case NavStatus::Waiting: return "waiting";
    case NavStatus::Navigating: return "navigating";
    case NavStatus::Arrived: return "arrived";
    case NavStatus::NoPath: return "no_path";
  }
  return "unknown";
}

void RecoveryConfig::validate() const {
  const auto positive_finite = [](double v, const char* field) {
    if (!(v > 0.0) || !std::isfinite(v)) throw Error("must be > 0", "", 0, field);
  };
  positive_finite(blocked_patience_s, "recovery.blocked_patience_s");
  if (max_recoveries < 0 || max_recoveries > 1000) throw Error("must be in [0, 1000]", "", 0, "recovery.max_recoveries");
}

void NavigatorConfig::validate() const {
  if (geometry.width <= 0 || geometry.height <= 0 || !(geometry.resolution > 0.0) || geometry.y_down)
    throw Error("the map grid must have a positive size and resolution, rows bottom-up", "", 0, "navigation.map");
  map.validate();
  if (!(goal_tolerance_m > 0.0) || !std::isfinite(goal_tolerance_m))
    throw Error("must be > 0", "", 0, "navigation.goal_tolerance_m");
  if (!(no_return_clear_m >= 0.0) || !std::isfinite(no_return_clear_m))
    throw Error("must be >= 0", "", 0, "navigation.map.no_return_clear_m");
  if (!(no_path_retry_s >= 0.0) || !std::isfinite(no_path_retry_s))
    throw Error("must be >= 0", "", 0, "navigation.no_path_retry_s");
  if (!(goal_yaw_tolerance_rad > 0.0) || !(goal_yaw_tolerance_rad <= kPi))
    throw Error("must be in (0, 180] deg", "", 0, "navigation.goal_yaw_tolerance_deg");
  recovery.validate();
  if (!prior_obstacles.empty() && prior_obstacles.size() != geometry.cell_count())
    throw Error("the prior map does not cover the navigation grid", "", 0, "navigation.map.prior");
}

namespace {

GridPlannerOptions search_options() {
  GridPlannerOptions o;
  o.connectivity = 8;
  o.unknown_is_free = true;  // plan optimistically through unobserved cells (Li et al. 2019; docs/navigation.md)
  return o;
}

// A* from scratch on the current map (the paper's planner, and the comparison beside D* Lite).
PlanResult astar_from_scratch(const OccupancyGrid& map, Cell start, Cell goal) {
  return make_grid_planner("astar", map, search_options())->plan(start, goal);
}

// The grid path's turning points: the first cell, every cell where the move direction changes,
// the last cell.
std::vector<Cell> turning_cells(const std::vector<Cell>& cells) {
  std::vector<Cell> out;
  if (cells.empty()) return out;
  out.push_back(cells.front());
  for (std::size_t i = 1; i + 1 < cells.size(); ++i) {
    const int dx0 = cells[i].x - cells[i - 1].x, dy0 = cells[i].y - cells[i - 1].y;
    const int dx1 = cells[i + 1].x - cells[i].x, dy1 = cells[i + 1].y - cells[i].y;
    if (dx0 != dx1 || dy0 != dy1) out.push_back(cells[i]);
  }
  if (cells.size() > 1) out.push_back(cells.back());
  return out;
}

}  // namespace

namespace {

// The recoveries' motion check: the robot's rectangle against the obstacles of the navigation map,
// read off its distance field.
class FootprintMotionCheck final : public MotionCheck {
 public:
  FootprintMotionCheck(const Footprint& footprint, LayeredCostmap& map) : checker_(rectangle(footprint)), map_(&map) {}
  bool clear(const Pose2& pose, const BodyTwist& twist, double duration_s) const override {
    return checker_.clear(map_->clearance(), pose, twist, duration_s);
  }

 private:
  static FootprintModel rectangle(const Footprint& f) {
    FootprintModel m;
    m.circle = false;
    m.half_length_m = 0.5 * f.length_m;
    m.half_width_m = 0.5 * f.width_m;
    return m;
  }
  FootprintMotionChecker checker_;
  LayeredCostmap* map_;
};

}  // namespace

Navigator::Navigator(const NavigatorConfig& config, const RobotConfig& robot, NavigatorParts parts, const Vec2& goal,
                     std::optional<double> goal_yaw)
    : config_(config),
      goal_(goal),
      map_((config.validate(), config.geometry), config.map, std::move(parts.layers)),
      planner_(std::move(parts.planner)),
      controller_(std::move(parts.controller)),
      goal_checker_(std::move(parts.goal_checker)),
      progress_checker_(std::move(parts.progress_checker)),
      recoveries_list_(std::move(parts.recoveries)),
      controller_capabilities_(parts.controller_capabilities),
      footprint_(footprint_of(robot)),
      limits_(velocity_limits_of(robot)) {
  if (!planner_ || !controller_ || !goal_checker_ || !progress_checker_)
    throw Error("a navigator needs a planner, a controller, a goal checker and a progress checker", "", 0, "navigation");
  for (const auto& r : recoveries_list_)
    if (!r) throw Error("a recovery is missing", "", 0, "navigation.recoveries");
  warnings_ = config_.warnings;
  if (parts.planner_capabilities.has(Capability::NeedsElevation))
    throw Error("planner '" + std::string(planner_->name()) + "' plans on elevation maps; navigation plans on its occupancy map",
                "", 0, "navigation.planner");
  if (parts.planner_capabilities.has(Capability::NeedsHeadings) && !goal_yaw)
    throw Error("planner '" + std::string(planner_->name()) + "' plans to a goal pose: give the goal's yaw_deg", "", 0,
                "navigation.goal.yaw_deg");
  incremental_ = parts.planner_capabilities.has(Capability::Incremental);
  planner_checks_footprint_ = parts.planner_capabilities.has(Capability::ChecksFootprint);
  if (incremental_) pending_mark_.assign(config_.geometry.cell_count(), 0);
  motion_check_ = std::make_unique<FootprintMotionCheck>(footprint_, map_);
  set_goal(goal, goal_yaw);
}

void Navigator::set_goal(const Vec2& goal, std::optional<double> goal_yaw) {
  if (goal_yaw && !std::isfinite(*goal_yaw)) throw Error("the goal heading is not finite", "", 0, "navigation.goal.yaw_deg");
  if (goal_yaw && !controller_capabilities_.has(Capability::GoalHeading))
    throw Error("the " + std::string(controller_->name()) + " controller cannot turn to a goal heading (give the goal without yaw_deg)",
                "", 0, "navigation.goal.yaw_deg");
  const auto g = config_.geometry.world_to_cell(goal);
  if (!g) throw Error("the goal lies outside the navigation map", "", 0, "navigation.goal");
  goal_ = goal;
  goal_yaw_ = goal_yaw;
  goal_checker_->reset();
  goal_cell_ = *g;
  status_ = NavStatus::Waiting;
  no_path_reason_.clear();
  arrival_t_ = -1.0;
  replan_cause_.clear();
  controller_->clear();
  progress_ = 0;
  held_ = {};
  next_control_t_ = -1.0;
  recovery_ = recoveries_list_.size();
  blocked_since_ = -1.0;
  progress_checker_->reset();
  recoveries_ = 0;
  no_path_since_ = -1.0;
}

Navigator::~Navigator() = default;

NavCycle Navigator::on_scan(const LidarScan& scan, const Pose2& pose, double t) {
  return after_update(map_.integrate(scan, config_.no_return_clear_m), pose, t);
}

NavCycle Navigator::on_points(const Vec3& sensor_origin, std::span<const Vec3> points, const Pose2& pose, double t) {
  return after_update(map_.integrate(sensor_origin, points), pose, t);
}

void Navigator::note_changes(const CostmapUpdate& update) {
  if (!incremental_ || plans_.empty()) return;
  // Cells that changed since the last plan; the planner gets their values at the next plan, so
  // a cell that flickered and came back costs nothing (D* Lite ignores unchanged passability).
  for (const Cell& c : update.occupancy_changed) {
    const std::size_t i = config_.geometry.index(c.x, c.y);
    if (!pending_mark_[i]) {
      pending_mark_[i] = 1;
      pending_.push_back({c, 0});
    }
  }
}

CostmapUpdate Navigator::add_scan(const LidarScan& scan) {
  CostmapUpdate update = map_.integrate(scan, config_.no_return_clear_m);
  note_changes(update);
  return update;
}

NavCycle Navigator::after_update(CostmapUpdate update, const Pose2& pose, double t) {
  NavCycle cycle;
  cycle.t_s = t;
  note_changes(update);
  cycle.update = std::move(update);
  if (status_ == NavStatus::Arrived || status_ == NavStatus::NoPath) return cycle;

  std::string cause;
  if (status_ == NavStatus::Waiting) {
    cause = "initial";
  } else {
    advance_progress(pose.translation());
    if (remaining_path_blocked()) cause = "blocked";
    else if (!replan_cause_.empty()) cause = replan_cause_;
  }
  if (!cause.empty()) {
    plan(pose, t, cause);
    cycle.planned = true;
    cycle.cause = cause;
  }
  return cycle;
}

void Navigator::advance_progress(const Vec2& p) {
  if (plans_.empty()) return;
  const std::vector<Cell>& cells = plans_.back().cells;
  if (cells.empty()) return;
  // The nearest cell centre within a window ahead; progress never goes back, so cells already
  // passed (and perhaps now inside a band behind the robot) never trigger a replan.
  const std::size_t window = 64;
  const std::size_t end = std::min(cells.size(), progress_ + window);
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = progress_;
  for (std::size_t i = progress_; i < end; ++i) {
    const double d = (config_.geometry.cell_center(cells[i]) - p).squaredNorm();
    if (d < best) {
      best = d;
      best_i = i;
    }
  }
  progress_ = best_i;
}

bool Navigator::remaining_path_blocked() const {
  if (plans_.empty()) return false;
  const NavPlan& plan = plans_.back();
  for (std::size_t i = progress_; i < plan.cells.size(); ++i) {
    const Cell& c = plan.cells[i];
    // The escape prefix runs inside the band by design; only a raw obstacle on it matters.
    const bool hit = i < plan.escape_cells ? map_.raw_blocked(c.x, c.y) : map_.blocked(c.x, c.y);
    if (hit) return true;
  }
  return false;
}

double Navigator::distance_to_path(const Vec2& p) const {
  if (!controller_->has_path()) return 0.0;
  return distance_to_polyline(p, controller_->path());
}

std::vector<Vec2> Navigator::follower_points(const std::vector<Cell>& cells, const Vec2& robot) const {
  std::vector<Cell> vertices;
  if (controller_->wants_smoothed_path()) {
    // An Ackermann robot cannot take 45 degree grid corners: line-of-sight smoothing (docs/navigation.md).
    const GridSearchMap search(map_.occupancy(), OccupancyThresholds{}, true);
    vertices = remove_redundant_nodes(search, cells);
  } else {
    vertices = turning_cells(cells);
  }
  std::vector<Vec2> points;
  points.push_back(robot);  // the robot starts on its own position, not its cell's centre
  for (std::size_t i = 1; i + 1 < vertices.size(); ++i) points.push_back(config_.geometry.cell_center(vertices[i]));
  points.push_back(goal_);  // the goal itself, within half a cell of its cell's centre
  return points;
}

void Navigator::plan(const Pose2& pose, double t, const std::string& cause) {
  NavPlan p;
  p.id = static_cast<int>(plans_.size()) + 1;
  p.t_s = t;
  p.cause = cause;
  p.from = pose;
  replan_cause_.clear();

  const auto fail = [&](const std::string& status, const std::string& reason) {
    p.status = status;
    plans_.push_back(std::move(p));
    progress_ = 0;
    controller_->clear();
    // Among moving people a blocked start or a cut-off goal may be a person passing: wait and
    // plan again at every cycle for a while before giving up.
    if (no_path_since_ < 0.0) no_path_since_ = t;
    if (t - no_path_since_ < config_.no_path_retry_s) {
      if (t == no_path_since_) events_.push_back({t, "no_path_wait", reason});
      status_ = NavStatus::Waiting;
    } else {
      status_ = NavStatus::NoPath;
      no_path_reason_ = reason;
    }
    if (on_plan) on_plan(*this, plans_.back());
  };

  const auto robot_cell = config_.geometry.world_to_cell(pose.translation());
  if (!robot_cell) return fail("start_outside_map", "the robot left the navigation map");
  std::vector<Cell> escape;
  Cell start = *robot_cell;
  // (A planner that checks the footprint plans from the robot's pose as it is.)
  if (!planner_checks_footprint_ && map_.blocked(start.x, start.y)) {
    const auto e = map_.escape_cell(start, &escape);
    if (!e) {
      return fail("start_blocked", map_.raw_blocked(start.x, start.y)
                                       ? "the robot's own cell is an obstacle cell"
                                       : "no way out of the expansion band around the robot");
    }
    start = *e;
  }

  // A planner that checks the footprint itself plans on the obstacles, not on the expanded map.
  const PlanningLayers layers{planner_checks_footprint_ ? &map_.raw_occupancy() : &map_.occupancy(), nullptr};
  // The poses for planners between poses (the others plan between the cells): the robot's own
  // pose and the goal with its heading when it has one.
  PlanQuery query;
  query.start = start;
  query.goal = goal_cell_;
  query.start_pose = pose;
  query.goal_pose = Pose2(goal_.x(), goal_.y(), goal_yaw_.value_or(0.0));
  query.goal_heading = goal_yaw_.has_value();
  PlanResult r;
  if (incremental_) {
    const OccupancyGrid& occ = map_.occupancy();
    for (CellChange& c : pending_) {
      c.occupancy = occ.at(c.cell.x, c.cell.y);
      pending_mark_[config_.geometry.index(c.cell.x, c.cell.y)] = 0;
    }
    r = planner_->plan_poses(layers, query, pending_);
    pending_.clear();
    if (config_.compare_astar) {
      const PlanResult a = astar_from_scratch(map_.occupancy(), start, goal_cell_);
      p.compared = true;
      p.astar_expanded = a.expanded;
      p.astar_cost_m = a.cost;
      p.astar_status = plan_status_reason(a.status);
      const PlanResult b = astar_from_scratch(map_.occupancy(), goal_cell_, start);
      p.astar_backward_expanded = b.expanded;
      p.astar_backward_cost_m = b.cost;
      p.astar_backward_status = plan_status_reason(b.status);
    }
  } else {
    r = planner_->plan_poses(layers, query, {});
  }
  p.status = plan_status_reason(r.status);
  p.expanded = r.expanded;
  p.cost_m = r.cost;
  p.time_ms = r.time_ms;
  if (!r.found()) {
    const std::string reason = r.status == PlanStatus::GoalBlocked ? "the goal lies in an obstacle or its expansion band"
                               : r.status == PlanStatus::StartBlocked
                                   ? "the robot's footprint holds obstacle cells of the current map"
                                   : "the goal is cut off by obstacles on the current map (unknown cells counted as free)";
    return fail(p.status, reason);
  }

  // Cells: the escape prefix (robot cell .. escape cell), then the path from the escape cell.
  p.escape_cells = escape.empty() ? 0 : escape.size() - 1;
  p.cells = escape;
  if (!p.cells.empty()) p.cells.pop_back();  // the escape cell starts the planned path
  p.cells.insert(p.cells.end(), r.path_cells.begin(), r.path_cells.end());
  if (!r.path_poses.empty()) {
    // A planner between poses: its poses and directions as they are (they start at the robot's pose).
    p.poses = std::move(r.path_poses);
    p.reversing = std::move(r.path_reversing);
    for (const Pose2& q : p.poses) p.points.push_back(q.translation());
    controller_->set_path_poses(p.poses, p.reversing);
  } else {
    p.points = follower_points(p.cells, pose.translation());
    controller_->set_path(p.points);
  }
  progress_ = 0;
  status_ = NavStatus::Navigating;
  no_path_since_ = -1.0;
  plans_.push_back(std::move(p));
  if (on_plan) on_plan(*this, plans_.back());
}

BodyTwist Navigator::command(const Pose2& pose, double t, const BodyTwist& velocity) {
  if (status_ != NavStatus::Navigating) return {};
  GoalCheckInput goal;
  goal.t_s = t;
  goal.pose = pose;
  goal.velocity = velocity;
  goal.goal = goal_;
  goal.goal_yaw = goal_yaw_;
  goal.xy_tolerance_m = config_.goal_tolerance_m;
  goal.yaw_tolerance_rad = config_.goal_yaw_tolerance_rad;
  if (goal_checker_->reached(goal)) {
    status_ = NavStatus::Arrived;
    arrival_t_ = t;
    controller_->clear();
    recovery_ = recoveries_list_.size();
    return {};
  }
  if (const std::optional<BodyTwist> r = recovery_twist(pose, t)) return *r;
  if (status_ != NavStatus::Navigating) return {};
  // Progress: a robot that makes none recovers (with no recoveries, nothing happens).
  if (!progress_checker_->check(pose, t) && !recoveries_list_.empty()) {
    if (!start_recovery(pose, t, "no_progress")) return {};
    if (const std::optional<BodyTwist> r = recovery_twist(pose, t)) return *r;
  }
  const double period = controller_->control_period_s();
  if (period > 0.0 && t < next_control_t_ - 1e-9) return held_;
  ControlInput in;
  in.t_s = t;
  in.pose = pose;
  in.velocity = velocity;
  in.local_map = &map_.raw_occupancy();
  // The distance field, brought up to date, for a controller that checks its footprint against it.
  if (controller_capabilities_.has(Capability::ChecksFootprint)) in.clearance = &map_.clearance();
  in.footprint = footprint_;
  in.limits = limits_;
  const std::optional<double> speed_limit = speed_limit_at(pose);
  if (speed_limit) in.limits = with_speed_limit(limits_, *speed_limit);
  if (speed_limit != speed_limit_) {
    events_.push_back({t, "speed_limit", speed_limit ? format_number(*speed_limit) : "none"});
    speed_limit_ = speed_limit;
  }
  in.goal = goal_;
  in.goal_yaw = goal_yaw_;
  in.goal_tolerance_m = config_.goal_tolerance_m;
  in.goal_yaw_tolerance_rad = config_.goal_yaw_tolerance_rad;
  in.goal_xy_reached = goal_checker_->position_reached();
  const ControlOutput out = controller_->compute(in);
  control_status_ = out.status;
  next_control_t_ = t + period;
  held_ = {};
  if (out.status == ControlStatus::Arrived || out.status == ControlStatus::CannotReach) {
    // The controller ended its path outside the goal tolerance: plan again at the next cycle.
    replan_cause_ = "missed";
    return {};
  }
  if (out.status == ControlStatus::AtCusp) {
    // The rest of a path with reversals, planned from the pose the robot reached (what it drove
    // so far is never exactly the plan; the next direction starts from where it is).
    replan_cause_ = "cusp";
    return {};
  }
  if (out.status == ControlStatus::Blocked) {
    if (blocked_since_ < 0.0) {
      blocked_since_ = t;
      replan_cause_ = "controller_blocked";  // perhaps the path runs into something new
    } else if (!recoveries_list_.empty() && t - blocked_since_ >= config_.recovery.blocked_patience_s) {
      blocked_since_ = -1.0;
      if (!start_recovery(pose, t, "controller_blocked")) return {};
      if (const std::optional<BodyTwist> r = recovery_twist(pose, t)) return *r;
    }
    return {};
  }
  blocked_since_ = -1.0;
  held_ = out.twist;
  return out.twist;
}

std::optional<double> Navigator::speed_limit_at(const Pose2& pose) const {
  // The body's rectangle (centred on base_link) in the map frame: a zone limits the robot as soon
  // as any part of it is inside, so that the whole body, not only its centre, keeps to the limit.
  const double hl = 0.5 * footprint_.length_m, hw = 0.5 * footprint_.width_m;
  const std::array<Vec2, 4> corners{pose.transform(Vec2(hl, hw)), pose.transform(Vec2(-hl, hw)), pose.transform(Vec2(-hl, -hw)),
                                    pose.transform(Vec2(hl, -hw))};
  return map_.speed_limit_mps(corners);
}

void Navigator::hold(double t) {
  progress_checker_->restart_clock(t);
  blocked_since_ = -1.0;
  next_control_t_ = -1.0;
  held_ = {};
}

RecoveryInput Navigator::recovery_input(const Pose2& pose, double t) const {
  RecoveryInput in;
  in.t_s = t;
  in.pose = pose;
  in.motion = motion_check_.get();
  in.look_period_s = controller_->control_period_s();
  return in;
}

bool Navigator::start_recovery(const Pose2& pose, double t, const std::string& why) {
  if (recoveries_ >= config_.recovery.max_recoveries) {
    events_.push_back({t, "stuck", why});
    status_ = NavStatus::NoPath;
    no_path_reason_ = "stuck: " + std::to_string(recoveries_) + " recoveries did not free the robot (" + why + ")";
    controller_->clear();
    recovery_ = recoveries_list_.size();
    return false;
  }
  ++recoveries_;
  events_.push_back({t, "recovery", why});
  goal_checker_->reset();  // the recovery moves the robot: the goal must be reached again
  recovery_ = 0;
  recoveries_list_[recovery_]->start(recovery_input(pose, t));
  return true;
}

std::optional<BodyTwist> Navigator::recovery_twist(const Pose2& pose, double t) {
  if (recovery_ >= recoveries_list_.size()) return std::nullopt;
  const RecoveryInput in = recovery_input(pose, t);
  for (;;) {
    if (const std::optional<BodyTwist> twist = recoveries_list_[recovery_]->step(in)) return twist;
    if (++recovery_ < recoveries_list_.size()) {
      events_.push_back({t, "recovery", std::string(recoveries_list_[recovery_]->name())});
      recoveries_list_[recovery_]->start(in);
      continue;
    }
    // Every recovery ran: plan again from where the robot is.
    events_.push_back({t, "recovery", "replan"});
    replan_cause_ = "recovery";
    progress_checker_->reset();
    next_control_t_ = -1.0;
    return BodyTwist{};
  }
}

}  // namespace starnav
