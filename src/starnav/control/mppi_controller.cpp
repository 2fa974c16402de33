#include "starnav/control/mppi_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

// The noise's own stream of the scenario's seed.
constexpr std::uint64_t kMppiNoiseStream = 0x4d505049;  // "MPPI"

ParamRange non_positive() {
  ParamRange r;
  r.hi = 0.0;
  return r;
}

// Each critic's cost_weight and cost_power, and its threshold_to_consider_m where it has one.
void critic_params(ParamTable<MppiConfig>& t, const std::string& name, MppiCriticConfig MppiConfig::*member, const char* what,
                   bool threshold, const char* threshold_doc = "") {
  t.real(name + ".cost_weight", [member](MppiConfig& c) -> double& { return (c.*member).cost_weight; }, non_negative(), "",
         std::string("weight of the ") + what);
  t.integer(name + ".cost_power", [member](MppiConfig& c) -> int& { return (c.*member).cost_power; }, closed(1, 8), "",
            "power of the weighted term: (weight x term)^power");
  if (threshold)
    t.real(name + ".threshold_to_consider_m", [member](MppiConfig& c) -> double& { return (c.*member).threshold_to_consider_m; },
           non_negative(), "m", threshold_doc);
}

}  // namespace

const ParamTable<MppiConfig>& mppi_params() {
  static const ParamTable<MppiConfig> table = [] {
    using C = MppiConfig;
    const double deg = kPi / 180.0;
    ParamTable<C> t;
    t.choice("motion_model", {"auto", "diff_drive", "omni", "ackermann"}, [](C& c, const std::string& v) { c.motion_model = v; },
             [](const C& c) { return c.motion_model; },
             "the rollouts' motion model: auto takes the robot's drive (mecanum: omni, differential: diff_drive, ackermann)");
    t.name_list("critics", {"constraint", "obstacles", "goal", "goal_angle", "path_align", "path_follow", "path_angle", "prefer_forward", "twirling"},
                [](C& c, const std::vector<std::string>& v) { c.critics = v; }, [](const C& c) { return c.critics; },
                "the critics that score the samples (docs/local_planning.md, MPPI)");
    t.integer("iteration_count", &C::iteration_count, closed(1, 100), "", "optimisation iterations per control step");
    t.integer("batch_size", &C::batch_size, closed(1, 100000), "", "sampled control sequences per iteration");
    t.integer("time_steps", &C::time_steps, closed(2, 1000), "", "steps of each sequence (horizon = time_steps x model_dt_s)");
    t.real("model_dt_s", &C::model_dt_s, open(0.0, 10.0), "s", "duration of one step of a sequence");
    t.real("vx_std_mps", &C::vx_std_mps, non_negative(), "m/s", "standard deviation of the vx noise");
    t.real("vy_std_mps", &C::vy_std_mps, non_negative(), "m/s", "standard deviation of the vy noise (omni)");
    t.real("wz_std_degps", &C::wz_std_radps, non_negative(), "deg/s", "standard deviation of the yaw-rate noise", deg);
    t.real("vx_max_mps", &C::vx_max_mps, non_negative(), "m/s", "forward speed limit (and the robot's)");
    t.real("vx_min_mps", &C::vx_min_mps, non_positive(), "m/s", "reverse speed limit (<= 0; and the robot's)");
    t.real("vy_max_mps", &C::vy_max_mps, non_negative(), "m/s", "sideways speed limit (omni; and the robot's)");
    t.real("wz_max_degps", &C::wz_max_radps, positive(), "deg/s", "yaw-rate limit (and the robot's, but for Ackermann)", deg);
    t.real("ax_max_mps2", &C::ax_max_mps2, positive(), "m/s^2", "acceleration limit of |vx| rising (and the wheels')");
    t.real("ax_min_mps2", &C::ax_min_mps2, non_positive(), "m/s^2", "... of |vx| falling (<= 0; 0: never slows down)");
    t.real("ay_max_mps2", &C::ay_max_mps2, positive(), "m/s^2", "acceleration limit of |vy| rising (omni)");
    t.real("ay_min_mps2", &C::ay_min_mps2, non_positive(), "m/s^2", "... of |vy| falling (<= 0)");
    t.real("az_max_degps2", &C::az_max_radps2, positive(), "deg/s^2", "yaw acceleration limit", deg);
    t.real("temperature", &C::temperature, positive(), "", "softmax temperature: lower follows the best samples more closely");
    t.real("gamma", &C::gamma, non_negative(), "", "weight of the control cost (smoothness against energy)");
    t.boolean("regenerate_noises", &C::regenerate_noises,
              "draw new noise every step (false: drawn once from the seed, as Nav2's default, and rotated in time by a random offset every iteration)");
    t.integer("retry_attempt_limit", &C::retry_attempt_limit, closed(0, 100), "",
              "when every sample collides: resets of the sequence and tries again before the step is blocked");
    t.real("reset_period_s", &C::reset_period_s, positive(), "s", "after this long without a step, the sequence starts from rest again");
    t.real("prune_distance_m", &C::prune_distance_m, positive(), "m", "length of the path ahead the critics see");
    t.real("inversion_xy_tolerance_m", &C::inversion_xy_tolerance_m, positive(), "m",
           "a path with reversals: the next stretch once the robot is this close to the cusp");
    t.real("inversion_yaw_tolerance_deg", &C::inversion_yaw_tolerance_rad, open(0.0, 180.0), "deg",
           "... and within this angle of the cusp's heading", deg);
    t.boolean("replan_at_cusps", &C::replan_at_cusps,
              "at a cusp, ask the navigator to plan the rest from the pose reached (false: follow the path's next stretch, Nav2's way)");
    t.real("stall_time_s", &C::stall_time_s, non_negative(), "s",
           "a path with reversals: stopped this long short of a stretch's end, ask for a new plan from here (0: never)");
    t.real("stretch_time_s", &C::stretch_time_s, non_negative(), "s",
           "a path with reversals: a stretch not done after this long plus its length at the top speed, ask for a new plan "
           "from here (0: never; a car creeping back and forth short of a cusp it cannot reach)");
    t.real("control_period_s", &C::control_period_s, open(0.0, 10.0), "s", "time between two commands (the command is held)");
    t.real("ackermann_constraints.min_turning_r_m", &C::min_turning_r_m, non_negative(), "m",
           "Ackermann: the samples' minimum turning radius; 0: the robot's (wheelbase / tan(max_steer_rad))");
    t.boolean("ackermann_constraints.sample_curvature", &C::sample_curvature,
              "Ackermann: sample speed and curvature (yaw rate = speed x curvature, the steering kept through a stop and in reverse); "
              "false: Nav2's speed and yaw-rate samples, the yaw rate clipped to |speed| / R_min");
    t.real("ackermann_constraints.curvature_std_per_m", &C::curvature_std_per_m, non_negative(), "1/m",
           "Ackermann with sample_curvature: standard deviation of the curvature noise; 0: half of 1 / R_min");
    t.real("ackermann_constraints.noise_correlation_time_s", &C::noise_correlation_time_s, non_negative(), "s",
           "Ackermann with sample_curvature: time constant of the speed and curvature noises (a first-order low-pass of white "
           "noise, the same standard deviation); 0: white, as Nav2's");
    t.real("trajectory_validator.collision_lookahead_time_s", &C::collision_lookahead_time_s, non_negative(), "s",
           "the optimal trajectory must be collision-free this long (0: not checked)");
    t.boolean("trajectory_validator.consider_footprint", &C::validator_consider_footprint,
              "check the optimal trajectory with the footprint (false: the inscribed circle)");
    t.integer("diagnostics_samples", &C::diagnostics_samples, closed(0, 100000), "",
              "sampled trajectories kept in the diagnostics (evenly over the batch; with the chosen one)");

    critic_params(t, "constraint", &C::constraint, "speed beyond the limits", false);
    critic_params(t, "goal", &C::goal, "distance to the goal", true, "active within this distance of the goal");
    critic_params(t, "goal_angle", &C::goal_angle, "heading error to the goal's heading", true,
                  "active within this distance of the goal");
    critic_params(t, "path_align", &C::path_align, "distance from the path", true, "off within this distance of the goal");
    t.integer("path_align.offset_from_furthest", [](C& c) -> int& { return c.path_align.offset_from_furthest; }, closed(0, 100000), "",
              "path points the batch must reach before the alignment counts");
    t.real("path_align.max_path_occupancy_ratio", &C::path_align_max_path_occupancy_ratio, closed(0.0, 1.0), "",
           "off when more of the path up to the furthest reached point is blocked");
    t.integer("path_align.trajectory_point_step", &C::path_align_trajectory_point_step, closed(1, 1000), "",
              "every this many poses of a trajectory are compared with the path");
    critic_params(t, "path_follow", &C::path_follow, "distance to a path point ahead", true, "off within this distance of the goal");
    t.integer("path_follow.offset_from_furthest", [](C& c) -> int& { return c.path_follow.offset_from_furthest; }, closed(0, 100000),
              "", "path points beyond the furthest reached one to drive to");
    critic_params(t, "path_angle", &C::path_angle, "heading error to a path point ahead", true, "off within this distance of the goal");
    t.integer("path_angle.offset_from_furthest", [](C& c) -> int& { return c.path_angle.offset_from_furthest; }, closed(0, 100000), "",
              "path points beyond the furthest reached one to turn toward");
    t.real("path_angle.max_angle_to_furthest_deg", &C::path_angle_max_angle_to_furthest_rad, closed(0.0, 180.0), "deg",
           "active when the robot's heading is off the direction to that point by more", deg);
    t.integer("path_angle.mode", &C::path_angle_mode, closed(0, 1), "", "0: prefer driving forward; 1: either direction");
    critic_params(t, "prefer_forward", &C::prefer_forward, "reverse motion", true, "off within this distance of the goal");
    critic_params(t, "twirling", &C::twirling, "yaw rate (for holonomic robots)", false);
    t.real("obstacles.critical_weight", [](C& c) -> double& { return c.obstacles.critical_weight; }, non_negative(), "",
           "weight of the collisions and of the gap within collision_margin_distance_m");
    t.real("obstacles.repulsion_weight", [](C& c) -> double& { return c.obstacles.repulsion_weight; }, non_negative(), "",
           "weight of the proximity within inflation_radius_m");
    t.integer("obstacles.cost_power", [](C& c) -> int& { return c.obstacles.power; }, closed(1, 8), "", "power of the critic's term");
    t.boolean("obstacles.consider_footprint", [](C& c) -> bool& { return c.obstacles.consider_footprint; },
              "collisions of the footprint (the robot's body box); false: of its inscribed circle");
    t.real("obstacles.collision_cost", [](C& c) -> double& { return c.obstacles.collision_cost; }, non_negative(), "",
           "cost of a colliding sample (times critical_weight)");
    t.real("obstacles.collision_margin_distance_m", [](C& c) -> double& { return c.obstacles.collision_margin_distance_m; },
           non_negative(), "m", "gap to the obstacles below which poses pay the critical cost");
    t.real("obstacles.near_goal_distance_m", [](C& c) -> double& { return c.obstacles.near_goal_distance_m; }, non_negative(), "m",
           "no repulsion within this distance of the goal");
    t.real("obstacles.inflation_radius_m", [](C& c) -> double& { return c.obstacles.inflation_radius_m; }, non_negative(), "m",
           "distance from the obstacles within which the repulsion acts");
    return t;
  }();
  return table;
}

MppiController::MppiController(const MppiConfig& config, const RobotConfig& robot, std::uint64_t seed)
    : config_(config), robot_(robot), rng_(Rng(seed).fork(kMppiNoiseStream)) {
  robot_.validate();
  const MppiConfig& c = config_;
  if (c.vx_min_mps > c.vx_max_mps) throw Error("vx_min_mps is above vx_max_mps", {}, 0, "vx_min_mps");
  const MppiMotionModel robot_model = robot_.drive == DriveKind::Mecanum     ? MppiMotionModel::Omni
                                      : robot_.drive == DriveKind::Ackermann ? MppiMotionModel::Ackermann
                                                                             : MppiMotionModel::DiffDrive;
  if (c.motion_model == "auto") model_ = robot_model;
  else if (c.motion_model == "omni") model_ = MppiMotionModel::Omni;
  else if (c.motion_model == "ackermann") model_ = MppiMotionModel::Ackermann;
  else if (c.motion_model == "diff_drive") model_ = MppiMotionModel::DiffDrive;
  else throw Error("unknown motion model '" + c.motion_model + "'", {}, 0, "motion_model");
  if (model_ == MppiMotionModel::Omni && robot_.drive != DriveKind::Mecanum)
    throw Error("the omni motion model needs a robot that translates sideways (drive mecanum)", {}, 0, "motion_model");
  if (model_ != MppiMotionModel::Ackermann && robot_.drive == DriveKind::Ackermann)
    throw Error("an Ackermann robot cannot turn in place: use the ackermann (or auto) motion model", {}, 0, "motion_model");

  // The robot's own limits within the configuration's: its wheels' speeds and accelerations along
  // each axis alone (the acceleration as velocity_limits_of derives the speeds).
  const VelocityLimits v = velocity_limits_of(robot_);
  const double wheel_acc = robot_.max_wheel_accel_radps2 * robot_.wheel_radius_m;
  limits_.model = model_;
  limits_.vx_max = std::min(c.vx_max_mps, v.max_vx_mps);
  limits_.vx_min = std::max(c.vx_min_mps, -v.max_vx_mps);
  limits_.vy_max = model_ == MppiMotionModel::Omni ? std::min(c.vy_max_mps, v.max_vy_mps) : 0.0;
  limits_.wz_max = model_ == MppiMotionModel::Ackermann ? c.wz_max_radps : std::min(c.wz_max_radps, v.max_yaw_rate_radps);
  limits_.ax_max = std::min(c.ax_max_mps2, wheel_acc);
  limits_.ax_min = std::max(c.ax_min_mps2, -wheel_acc);
  const double lateral = robot_.drive == DriveKind::Mecanum ? wheel_acc * std::tan(robot_.roller_angle_rad) : wheel_acc;
  limits_.ay_max = std::min(c.ay_max_mps2, lateral);
  limits_.ay_min = std::max(c.ay_min_mps2, -lateral);
  const double yaw_acc = robot_.drive == DriveKind::Mecanum        ? wheel_acc / (robot_.half_track_m + robot_.half_wheelbase_m)
                         : robot_.drive == DriveKind::Differential ? wheel_acc / robot_.half_track_m
                                                                   : c.az_max_radps2;
  limits_.az_max = std::min(c.az_max_radps2, yaw_acc);
  const double robot_radius = min_turning_radius_of(robot_);
  if (model_ == MppiMotionModel::Ackermann) {
    if (c.min_turning_r_m > 0.0 && robot_.drive == DriveKind::Ackermann && c.min_turning_r_m < robot_radius - 1e-9)
      throw Error(format_readable(c.min_turning_r_m) + " m is below the robot's minimum turning radius " + format_readable(robot_radius) + " m",
                  {}, 0, "ackermann_constraints.min_turning_r_m");
    limits_.min_turning_r = c.min_turning_r_m > 0.0 ? c.min_turning_r_m : robot_radius;
  }

  // The footprint: the robot's body box (Ackermann: ahead of base_link, the rear axle).
  checker_ = FootprintChecker(body_footprint_model(robot_), 0.0);
  validator_checker_ = checker_;

  const auto find = [&](const char* n) { return std::find(c.critics.begin(), c.critics.end(), n) != c.critics.end(); };
  const auto add = [&](const char* n, auto make) {
    if (find(n)) critics_.push_back(make());
  };
  add("constraint", [&] { return std::make_unique<MppiConstraintCritic>(c.constraint.cost_weight, c.constraint.cost_power); });
  add("obstacles", [&] {
    auto o = std::make_unique<MppiObstaclesCritic>(c.obstacles);
    obstacles_ = o.get();
    return o;
  });
  add("goal", [&] { return std::make_unique<MppiGoalCritic>(c.goal.cost_weight, c.goal.cost_power, c.goal.threshold_to_consider_m); });
  add("goal_angle", [&] {
    return std::make_unique<MppiGoalAngleCritic>(c.goal_angle.cost_weight, c.goal_angle.cost_power, c.goal_angle.threshold_to_consider_m);
  });
  add("path_align", [&] {
    MppiPathAlignOptions o;
    o.threshold_m = c.path_align.threshold_to_consider_m;
    o.offset_from_furthest = c.path_align.offset_from_furthest;
    o.max_path_occupancy_ratio = c.path_align_max_path_occupancy_ratio;
    o.trajectory_point_step = c.path_align_trajectory_point_step;
    return std::make_unique<MppiPathAlignCritic>(c.path_align.cost_weight, c.path_align.cost_power, o);
  });
  add("path_follow", [&] {
    return std::make_unique<MppiPathFollowCritic>(c.path_follow.cost_weight, c.path_follow.cost_power,
                                                  c.path_follow.threshold_to_consider_m, c.path_follow.offset_from_furthest);
  });
  add("path_angle", [&] {
    return std::make_unique<MppiPathAngleCritic>(c.path_angle.cost_weight, c.path_angle.cost_power, c.path_angle.threshold_to_consider_m,
                                                 c.path_angle.offset_from_furthest, c.path_angle_max_angle_to_furthest_rad, c.path_angle_mode);
  });
  add("prefer_forward", [&] {
    return std::make_unique<MppiPreferForwardCritic>(c.prefer_forward.cost_weight, c.prefer_forward.cost_power,
                                                     c.prefer_forward.threshold_to_consider_m);
  });
  add("twirling", [&] { return std::make_unique<MppiTwirlingCritic>(c.twirling.cost_weight, c.twirling.cost_power); });

  noise_.resize(c.batch_size, c.time_steps);
  draw_noise();
  reset_optimizer();
}

MppiController::~MppiController() = default;

void MppiController::draw_noise() {
  const auto fill = [&](Eigen::ArrayXXf& a, double sd) {
    for (Eigen::Index j = 0; j < a.cols(); ++j)
      for (Eigen::Index i = 0; i < a.rows(); ++i) a(i, j) = static_cast<float>(sd * rng_.normal());
  };
  fill(noise_.vx, config_.vx_std_mps);
  if (model_ == MppiMotionModel::Omni) fill(noise_.vy, config_.vy_std_mps);
  if (curvature_sampling()) {
    noise_.curvature.resize(noise_.vx.rows(), noise_.vx.cols());
    fill(noise_.curvature, curvature_std());
    // Correlated in time: n_t = rho n_(t-1) + sqrt(1 - rho^2) e_t keeps the standard deviation.
    if (config_.noise_correlation_time_s > 0.0) {
      const float rho = static_cast<float>(std::exp(-config_.model_dt_s / config_.noise_correlation_time_s));
      const float keep = std::sqrt(1.0f - rho * rho);
      for (Eigen::ArrayXXf* a : {&noise_.vx, &noise_.curvature})
        for (Eigen::Index j = 1; j < a->cols(); ++j) a->col(j) = rho * a->col(j - 1) + keep * a->col(j);
    }
  } else {
    fill(noise_.wz, config_.wz_std_radps);
  }
}

double MppiController::curvature_std() const {
  return config_.curvature_std_per_m > 0.0 ? config_.curvature_std_per_m : 0.5 / limits_.min_turning_r;
}

void MppiController::reset_optimizer() {
  sequence_.reset(config_.time_steps);
  history_ = {};
  curvature_history_ = {};
  last_t_s_.reset();
}

void MppiController::shift_sequence(int steps) {
  const Eigen::Index n = sequence_.vx.size();
  steps = std::clamp(steps, 0, static_cast<int>(n) - 1);
  if (steps == 0) return;
  for (Eigen::ArrayXf* a : {&sequence_.vx, &sequence_.vy, &sequence_.wz, &sequence_.curvature}) {
    const Eigen::ArrayXf old = *a;
    a->head(n - steps) = old.tail(n - steps);
    a->tail(steps).setConstant(old(n - 1));
  }
}

void MppiController::set_path(std::span<const Vec2> points) {
  if (points.empty()) throw Error("empty path", {}, 0, "path");
  for (const Vec2& p : points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw Error("a path point is not finite", {}, 0, "path");
  std::vector<Pose2> poses;
  for (const Vec2& p : points)
    if (poses.empty() || (p - poses.back().translation()).norm() > 1e-9) poses.emplace_back(p.x(), p.y(), 0.0);
  std::vector<std::uint8_t> forward(poses.size(), 0);
  take_path(std::move(poses), std::move(forward), false);
}

void MppiController::set_path_poses(std::span<const Pose2> poses, std::span<const std::uint8_t> reversing) {
  if (poses.empty()) throw Error("empty path", {}, 0, "path");
  if (poses.size() != reversing.size()) throw Error("a direction for every pose of the path", {}, 0, "path");
  for (const Pose2& p : poses)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.yaw)) throw Error("a path pose is not finite", {}, 0, "path");
  take_path({poses.begin(), poses.end()}, {reversing.begin(), reversing.end()}, true);
}

void MppiController::take_path(std::vector<Pose2> poses, std::vector<std::uint8_t> reversing, bool pose_path) {
  poses_ = std::move(poses);
  reversing_ = std::move(reversing);
  // A cusp is a pose whose leaving direction differs from its arriving one: a stretch ends there
  // and the next starts from it.
  stretches_.clear();
  std::size_t first = 0;
  for (std::size_t i = 1; i + 1 < poses_.size(); ++i)
    if ((reversing_[i] != 0) != (reversing_[i - 1] != 0)) {
      stretches_.emplace_back(first, i);
      first = i;
    }
  stretches_.emplace_back(first, poses_.size() - 1);
  full_path_.clear();
  for (const Pose2& p : poses_) full_path_.push_back(p.translation());
  pose_path_ = pose_path;
  // Stretches that end within the inversion tolerances of where the path starts (a plan from a
  // cusp may begin with a wiggle) are done already.
  std::size_t k = 0;
  while (k + 1 < stretches_.size() && at_pose(poses_.front(), poses_[stretches_[k].second])) ++k;
  load_stretch(k);
}

bool MppiController::at_pose(const Pose2& robot, const Pose2& cusp) const {
  return (robot.translation() - cusp.translation()).norm() <= config_.inversion_xy_tolerance_m &&
         std::abs(wrap_angle(cusp.yaw - robot.yaw)) <= config_.inversion_yaw_tolerance_rad;
}

void MppiController::load_stretch(std::size_t k) {
  stretch_ = k;
  path_.clear();
  for (std::size_t i = stretches_[k].first; i <= stretches_[k].second; ++i) {
    const Vec2 p = poses_[i].translation();
    if (path_.empty() || (p - path_.back()).norm() > 1e-9) path_.push_back(p);
  }
  along_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i) along_[i] = along_[i - 1] + (path_[i] - path_[i - 1]).norm();
  segment_ = 0;
  stalled_since_s_.reset();
  stretch_since_s_.reset();
}

void MppiController::clear() {
  path_.clear();
  full_path_.clear();
  poses_.clear();
  reversing_.clear();
  stretches_.clear();
  stretch_ = 0;
  along_.clear();
  segment_ = 0;
  reset_optimizer();
}

namespace {

Vec2 closest_on(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double s = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + s * ab;
}

}  // namespace

void MppiController::update_progress(const Vec2& p) {
  if (path_.size() < 2) return;
  // The nearest segment within twice the pruned length ahead (progress never goes back, so a path
  // passing near itself is followed in order).
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = segment_;
  const double end = along_[segment_] + 2.0 * config_.prune_distance_m + 1.0;
  for (std::size_t i = segment_; i + 1 < path_.size() && along_[i] <= end; ++i) {
    const double d = (closest_on(p, path_[i], path_[i + 1]) - p).squaredNorm();
    if (d < best) best = d, best_i = i;
  }
  segment_ = best_i;
}

void MppiController::build_local_path(MppiScene& s) const {
  s.path.clear();
  const double step = map_.resolution();
  const Vec2 p = s.pose.translation();
  if (path_.size() == 1) {
    s.path.push_back(path_[0]);
  } else {
    // From the robot's place on the path, every `step` along it, up to prune_distance_m; the end
    // always included.
    Vec2 from = closest_on(p, path_[segment_], path_[segment_ + 1]);
    s.path.push_back(from);
    double left = config_.prune_distance_m, carry = 0.0;
    for (std::size_t i = segment_ + 1; i < path_.size() && left > 0.0; ++i) {
      const Vec2 d = path_[i] - from;
      const double len = d.norm();
      double at = step - carry;
      while (at <= len && left > 0.0) {
        s.path.push_back(from + d * (at / len));
        left -= step;
        at += step;
      }
      carry = len - (at - step);
      from = path_[i];
      if (i + 1 == path_.size() && left > 0.0 && (s.path.back() - path_[i]).norm() > 1e-9) s.path.push_back(path_[i]);
    }
  }
  s.path_free.assign(s.path.size(), 1);
  for (std::size_t i = 0; i < s.path.size(); ++i) {
    const Cell c = map_.cell_of(s.path[i]);
    if (map_.contains(c.x, c.y) && map_.clearance_m(map_.index(c.x, c.y)) < s.inscribed_radius_m) s.path_free[i] = 0;
  }
}

bool MppiController::iterate(MppiScene& s, const BodyTwist& velocity) {
  const bool omni = model_ == MppiMotionModel::Omni;
  // The noise drawn once, rotated in time by a new offset at every iteration: white noise still,
  // but not the same samples every time (the same ones settle on a fixed point short of the goal).
  const Eigen::Index steps = noise_.vx.cols();
  const Eigen::Index offset = config_.regenerate_noises ? 0 : static_cast<Eigen::Index>(rng_.uniform_int(0, steps - 1));
  const auto noised = [&](const Eigen::ArrayXXf& noise, const Eigen::ArrayXf& mean, Eigen::ArrayXXf& out) {
    out.resize(noise.rows(), steps);
    for (Eigen::Index t = 0; t < steps; ++t) out.col(t) = noise.col((t + offset) % steps) + mean(t);
  };
  noised(noise_.vx, sequence_.vx, samples_.vx);
  if (omni) noised(noise_.vy, sequence_.vy, samples_.vy);
  else samples_.vy.setZero(noise_.vx.rows(), steps);
  if (curvature_sampling()) {
    noised(noise_.curvature, sequence_.curvature, samples_.curvature);
    samples_.wz.resize(noise_.vx.rows(), steps);
  } else {
    noised(noise_.wz, sequence_.wz, samples_.wz);
  }
  mppi_apply_limits(s.limits, velocity, config_.model_dt_s, samples_);
  mppi_integrate(s.pose, config_.model_dt_s, samples_, trajectories_);
  s.controls = &samples_;
  s.trajectories = &trajectories_;
  s.furthest_cache.reset();
  costs_.total.setZero(samples_.vx.rows());
  costs_.failed = false;
  for (const auto& critic : critics_) critic->score(s, costs_);
  // The control cost of the noise, as Nav2 (gamma / std^2 x sum over steps of noise x mean).
  const auto control_cost = [&](const Eigen::ArrayXXf& u, const Eigen::ArrayXf& mean, double sd) {
    if (!(sd > 0.0) || config_.gamma == 0.0) return;
    const float g = static_cast<float>(config_.gamma / (sd * sd));
    costs_.total += g * ((u.rowwise() - mean.transpose()).rowwise() * mean.transpose()).rowwise().sum();
  };
  control_cost(samples_.vx, sequence_.vx, config_.vx_std_mps);
  if (omni) control_cost(samples_.vy, sequence_.vy, config_.vy_std_mps);
  if (curvature_sampling()) control_cost(samples_.curvature, sequence_.curvature, curvature_std());
  else control_cost(samples_.wz, sequence_.wz, config_.wz_std_radps);
  if (costs_.failed) return false;
  mppi_softmax_weights(costs_.total, config_.temperature, weights_);
  mppi_weighted_mean(samples_, weights_, sequence_);
  return true;
}

bool MppiController::trajectory_collides(const MppiScene& s, const MppiTrajectories& t, int steps) const {
  const double r_in = s.inscribed_radius_m;
  for (int p = 0; p < std::min<int>(steps, static_cast<int>(t.x.cols())); ++p) {
    const Pose2 pose(t.x(0, p), t.y(0, p), t.yaw(0, p));
    const float d = s.clearance_at(t.x(0, p), t.y(0, p));
    const bool hit = config_.validator_consider_footprint
                         ? d <= static_cast<float>(s.circumscribed_radius_m + map_.resolution()) && validator_checker_.collides(map_, pose)
                         : d < static_cast<float>(r_in);
    if (hit) return true;
  }
  return false;
}

ControlOutput MppiController::compute(const ControlInput& in) {
  if (keep_) last_ = {};
  if (path_.empty()) return {};
  if (!in.local_map && !in.clearance) throw Error("the MPPI controller needs a local obstacle map", "", 0, "local_map");
  const Vec2 p = in.pose.translation();
  // At a cusp (within the inversion tolerances of its pose): the next stretch, from rest.
  while (stretch_ + 1 < stretches_.size()) {
    if (!at_pose(in.pose, poses_[stretches_[stretch_].second])) break;
    if (config_.replan_at_cusps) {
      reset_optimizer();
      if (keep_) record(in, MppiScene{}, {{}, ControlStatus::AtCusp});
      return {{}, ControlStatus::AtCusp};
    }
    load_stretch(stretch_ + 1);
    reset_optimizer();
  }
  const bool last_stretch = stretch_ + 1 >= stretches_.size();
  const bool stretch_reverse = !reversing_.empty() && reversing_[stretches_[stretch_].first] != 0;
  const Vec2 goal = path_.back();
  const double to_goal = (p - goal).norm();
  if (last_stretch && (in.goal_xy_reached || to_goal <= in.goal_tolerance_m) &&
      (!in.goal_yaw || std::abs(wrap_angle(*in.goal_yaw - in.pose.yaw)) <= in.goal_yaw_tolerance_rad)) {
    reset_optimizer();
    if (keep_) record(in, MppiScene{}, {{}, ControlStatus::Arrived});
    return {{}, ControlStatus::Arrived};
  }

  // The sequence moves on by the time that passed (from rest after a long pause).
  if (last_t_s_) {
    const double elapsed = in.t_s - *last_t_s_;
    if (elapsed < 0.0 || elapsed > config_.reset_period_s) reset_optimizer();
    else shift_sequence(static_cast<int>(std::lround(elapsed / config_.model_dt_s)));
  }
  last_t_s_ = in.t_s;

  // The step's limits: a speed-limit zone (the input's) lowers the robot's.
  MppiLimits limits = limits_;
  const double speed_cap = std::min(in.limits.max_speed_mps, in.limits.max_vx_mps);
  limits.vx_max = std::min(limits.vx_max, speed_cap);
  limits.vx_min = std::max(limits.vx_min, -speed_cap);
  limits.vy_max = std::min({limits.vy_max, in.limits.max_vy_mps, in.limits.max_speed_mps});
  if (model_ != MppiMotionModel::Ackermann) limits.wz_max = std::min(limits.wz_max, in.limits.max_yaw_rate_radps);

  // The window of obstacles: every pose the batch can reach, and the path the critics see.
  const double reach = std::max({limits.vx_max, -limits.vx_min, std::hypot(limits.vx_max, limits.vy_max)}) * config_.time_steps * config_.model_dt_s;
  const FootprintModel& fm = checker_.model();
  const double res = in.clearance ? in.clearance->geometry().resolution : in.local_map->resolution();
  const double half = std::max(reach, config_.prune_distance_m) + res;
  const double pad = std::max(config_.obstacles.inflation_radius_m, fm.bounding_radius_m()) + 2.0 * res;
  if (in.clearance) map_.build(*in.clearance, p, half, pad);
  else map_.build(*in.local_map, p, half, pad);

  MppiScene s;
  s.pose = in.pose;
  s.goal = goal;
  // Before the last cusp the stretch's end is the local goal, with the heading the planner gave it.
  s.goal_yaw = last_stretch ? in.goal_yaw : std::optional<double>(poses_[stretches_[stretch_].second].yaw);
  s.reversing = stretch_reverse;
  s.goal_tolerance_m = in.goal_tolerance_m;
  s.model_dt_s = config_.model_dt_s;
  s.limits = limits;
  s.map = &map_;
  s.prepare_map();
  s.footprint = &checker_;
  s.inscribed_radius_m = fm.inscribed_radius_m();
  s.circumscribed_radius_m = fm.bounding_radius_m();
  update_progress(p);
  build_local_path(s);
  if (pose_path_ && path_.size() >= 2) {
    const Vec2 on = closest_on(p, path_[segment_], path_[segment_ + 1]);
    s.path_left_m = along_.back() - along_[segment_] - (on - path_[segment_]).norm();
  } else if (pose_path_) {
    s.path_left_m = to_goal;
  }

  // Keep the mean within this step's limits before sampling round it.
  const auto bound_sequence = [&] {
    sequence_.vx = sequence_.vx.cwiseMax(static_cast<float>(limits.vx_min)).cwiseMin(static_cast<float>(limits.vx_max));
    sequence_.vy = sequence_.vy.cwiseMax(static_cast<float>(-limits.vy_max)).cwiseMin(static_cast<float>(limits.vy_max));
    sequence_.wz = sequence_.wz.cwiseMax(static_cast<float>(-limits.wz_max)).cwiseMin(static_cast<float>(limits.wz_max));
    if (curvature_sampling()) {
      const float k_max = static_cast<float>(1.0 / limits.min_turning_r);
      sequence_.curvature = sequence_.curvature.cwiseMax(-k_max).cwiseMin(k_max);
      sequence_.wz = sequence_.vx * sequence_.curvature;
    } else if (model_ == MppiMotionModel::Ackermann) {
      const Eigen::ArrayXf bound = sequence_.vx.abs() * static_cast<float>(1.0 / limits.min_turning_r);
      sequence_.wz = sequence_.wz.cwiseMax(-bound).cwiseMin(bound);
    }
  };
  if (config_.regenerate_noises) draw_noise();
  const int steps_checked = static_cast<int>(std::ceil(config_.collision_lookahead_time_s / config_.model_dt_s - 1e-9));
  MppiTrajectories optimal;
  bool ok = false;
  for (int attempt = 0; attempt <= config_.retry_attempt_limit && !ok; ++attempt) {
    if (attempt > 0) sequence_.reset(config_.time_steps);  // a soft reset: from rest again
    bound_sequence();
    ok = true;
    for (int i = 0; i < config_.iteration_count && ok; ++i) {
      ok = iterate(s, in.velocity);
      bound_sequence();
    }
    if (!ok) continue;
    // The optimal sequence's own trajectory (within the limits from the robot's velocity) must be free.
    MppiControls mean;
    mean.vx = sequence_.vx.transpose();
    mean.vy = sequence_.vy.transpose();
    mean.wz = sequence_.wz.transpose();
    if (curvature_sampling()) mean.curvature = sequence_.curvature.transpose();
    mppi_apply_limits(limits, in.velocity, config_.model_dt_s, mean);
    mppi_integrate(in.pose, config_.model_dt_s, mean, optimal);
    if (steps_checked > 0 && trajectory_collides(s, optimal, steps_checked)) ok = false;
  }
  if (!ok) {
    reset_optimizer();
    const ControlOutput out{{}, ControlStatus::Blocked};
    if (keep_) record(in, s, out);
    return out;
  }

  // Smoothing with the last four commands before the sequence, then its first control.
  std::array<float, 4> hx{}, hy{}, hw{};
  for (std::size_t i = 0; i < 4; ++i) {
    hx[i] = static_cast<float>(history_[i].vx);
    hy[i] = static_cast<float>(history_[i].vy);
    hw[i] = static_cast<float>(history_[i].wz);
  }
  mppi_savitzky_golay(sequence_.vx, hx);
  if (model_ == MppiMotionModel::Omni) mppi_savitzky_golay(sequence_.vy, hy);
  if (curvature_sampling()) mppi_savitzky_golay(sequence_.curvature, curvature_history_);
  else mppi_savitzky_golay(sequence_.wz, hw);
  bound_sequence();
  const BodyTwist command{sequence_.vx(0), sequence_.vy(0), sequence_.wz(0)};
  for (std::size_t i = 0; i + 1 < 4; ++i) history_[i] = history_[i + 1];
  history_[3] = command;
  if (curvature_sampling()) {
    for (std::size_t i = 0; i + 1 < 4; ++i) curvature_history_[i] = curvature_history_[i + 1];
    curvature_history_[3] = sequence_.curvature(0);
  }
  // A path with reversals: stopped short of a stretch's end (the motion model cannot turn tight
  // enough to reach its pose from here) for stall_time_s, a new plan from here is asked for; or
  // moving, but not done with the stretch in its time.
  constexpr double kStoppedMps = 0.02;
  const bool stopped = pose_path_ && config_.stall_time_s > 0.0 && std::abs(command.vx) < kStoppedMps &&
                       std::abs(in.velocity.vx) < kStoppedMps;
  if (!stopped) stalled_since_s_.reset();
  else if (!stalled_since_s_) stalled_since_s_ = in.t_s;
  if (!stretch_since_s_) stretch_since_s_ = in.t_s;
  const bool overdue = pose_path_ && config_.stretch_time_s > 0.0 &&
                       in.t_s - *stretch_since_s_ >= config_.stretch_time_s +
                                                         along_.back() / std::max(stretch_reverse ? -limits_.vx_min : limits_.vx_max, 1e-3);
  if (overdue || (stopped && in.t_s - *stalled_since_s_ >= config_.stall_time_s)) {
    stalled_since_s_.reset();
    reset_optimizer();
    const ControlOutput stop{{}, last_stretch ? ControlStatus::CannotReach : ControlStatus::AtCusp};
    if (keep_) record(in, s, stop);
    return stop;
  }
  const ControlOutput out{command, ControlStatus::Tracking};
  if (keep_) {
    record(in, s, out);
    ControlCandidate chosen;
    chosen.twist = command;
    for (Eigen::Index t = 0; t < optimal.x.cols(); ++t) chosen.trajectory.emplace_back(optimal.x(0, t), optimal.y(0, t), optimal.yaw(0, t));
    chosen.cost = 0.0;
    last_.candidates.push_back(std::move(chosen));
    last_.chosen = static_cast<int>(last_.candidates.size()) - 1;
  }
  return out;
}

void MppiController::record(const ControlInput& in, const MppiScene& s, const ControlOutput& out) {
  last_.t_s = in.t_s;
  last_.pose = in.pose;
  last_.status = out.status;
  last_.command = out.twist;
  if (out.status == ControlStatus::Arrived) return;
  // Some samples of the last iteration, evenly over the batch, with their costs.
  const Eigen::Index n = trajectories_.x.rows();
  const int keep = static_cast<int>(std::min<Eigen::Index>(config_.diagnostics_samples, n));
  for (int i = 0; i < keep; ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i) * n / keep;
    ControlCandidate c;
    c.twist = {samples_.vx(k, 0), samples_.vy(k, 0), samples_.wz(k, 0)};
    c.cost = costs_.total.size() > k ? costs_.total(k) : 0.0;
    bool hit = false;
    for (Eigen::Index t = 0; t < trajectories_.x.cols(); ++t) {
      const Pose2 pose(trajectories_.x(k, t), trajectories_.y(k, t), trajectories_.yaw(k, t));
      c.trajectory.push_back(pose);
      if (obstacles_ && !hit && s.map) hit = obstacles_->collides(s, pose, s.clearance_at(trajectories_.x(k, t), trajectories_.y(k, t)));
    }
    c.status = hit ? CandidateStatus::Collides : CandidateStatus::Valid;
    last_.candidates.push_back(std::move(c));
  }
  if (!s.path.empty()) last_.points.emplace_back("path ahead", s.path.back());
  if (costs_.total.size() > 0) last_.terms.emplace_back("min_cost", costs_.total.minCoeff());
  if (weights_.size() > 0) last_.terms.emplace_back("max_weight", weights_.maxCoeff());
}

std::optional<ControlDiagnostics> MppiController::diagnostics() const {
  if (!keep_) return std::nullopt;
  return last_;
}

LocalControllerDef mppi_controller() {
  LocalControllerDef d;
  d.info.role = Role::LocalController;
  d.info.name = "mppi";
  d.info.section = "mppi";
  d.info.summary = "Nav2's MPPI: sampled control sequences rolled out on the motion model (diff, omni, Ackermann), scored by critics, "
                   "softmax-averaged and smoothed";
  d.info.capabilities = {Capability::GoalHeading, Capability::ChecksFootprint, Capability::VelocitySpace};
  // Its keys are Nav2's with their units' suffixes, the critics' in sections named after them
  // (GoalCritic.cost_weight: goal.cost_weight): a Nav2 parameter file maps onto them (docs/ros2.md).
  d.info.nav2_counterpart = "nav2_mppi_controller::MPPIController";
  d.info.params = mppi_params().specs();
  d.make = [](const LocalControllerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<LocalController> {
    const MppiConfig c = configured(mppi_params(), settings, ctx.file);
    try {
      return std::make_unique<MppiController>(c, ctx.robot, ctx.seed);
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
