#pragma once
// The MPPI local controller (registry name "mppi"): Nav2's Model Predictive Path Integral
// controller (nav2_mppi_controller; Williams et al. 2016). At every step it samples batch_size
// control sequences over time_steps x model_dt_s as the last optimal sequence (shifted by the time
// that passed) plus Gaussian noise, keeps them within the motion model's limits (mppi_optimizer.hpp),
// rolls them out, scores them with its critics (mppi_critics.hpp), and takes as the new sequence
// the softmax-weighted mean of the samples (temperature, plus Nav2's gamma term); repeated
// iteration_count times, then smoothed (Savitzky-Golay) and its first control commanded. The
// noise is drawn once from the scenario's seed (regenerate_noises: every step). docs/local_planning.md
// "MPPI" describes its choices.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/control/mppi_critics.hpp"
#include "starnav/control/mppi_optimizer.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/rng.hpp"

namespace starnav {

struct MppiCriticConfig {
  double cost_weight = 1.0;
  int cost_power = 1;
  double threshold_to_consider_m = 0.5;
  int offset_from_furthest = 0;
};

// Nav2's parameters and defaults in SI units (angles in degrees where the key says so).
struct MppiConfig {
  std::string motion_model = "auto";  // auto | diff_drive | omni | ackermann
  std::vector<std::string> critics = {"constraint", "obstacles", "goal", "goal_angle", "path_align", "path_follow", "path_angle", "prefer_forward"};
  int iteration_count = 1;
  int batch_size = 2000;
  int time_steps = 56;
  double model_dt_s = 0.05;
  double vx_std_mps = 0.2, vy_std_mps = 0.2, wz_std_radps = 0.2;
  double vx_max_mps = 0.5, vx_min_mps = -0.35, vy_max_mps = 0.5, wz_max_radps = 1.9;
  double ax_max_mps2 = 3.0, ax_min_mps2 = -3.0, ay_max_mps2 = 3.0, ay_min_mps2 = -3.0, az_max_radps2 = 3.5;
  double temperature = 0.3;
  double gamma = 0.015;
  bool regenerate_noises = false;
  int retry_attempt_limit = 1;
  double reset_period_s = 1.0;
  double prune_distance_m = 1.5;
  // A path with reversals (a planner between poses) is followed one direction at a time: the next
  // stretch once the robot is this close to the cusp's pose (Nav2's inversion tolerances).
  double inversion_xy_tolerance_m = 0.2;
  double inversion_yaw_tolerance_rad = 0.4;
  // At a cusp: ask the navigator for a new plan from the pose reached (false: follow the next
  // stretch of the same path, Nav2's way). Stopped this long short of a stretch's end: the same.
  bool replan_at_cusps = true;
  double stall_time_s = 1.0;
  double stretch_time_s = 0.0;
  double control_period_s = 0.05;
  double min_turning_r_m = 0.0;  // Ackermann; 0: the robot's own (wheelbase / tan(max steer))
  // Ackermann: samples of (vx, curvature) with wz = vx x curvature (false: Nav2's (vx, wz) samples
  // with wz clipped to |vx| / R_min); the curvature noise's standard deviation (0: half of 1 / R_min).
  bool sample_curvature = true;
  double curvature_std_per_m = 0.0;
  // ... and both noises correlated in time (a first-order low-pass of white noise with this time
  // constant, the same standard deviation): white noise over 56 steps averages out, so every
  // sample would turn about as much as the mean; a car's manoeuvre is an arc held for a while.
  double noise_correlation_time_s = 0.5;
  double collision_lookahead_time_s = 2.0;
  bool validator_consider_footprint = false;
  int diagnostics_samples = 64;

  MppiCriticConfig constraint{4.0, 1, 0.0, 0};
  MppiCriticConfig goal{5.0, 1, 1.4, 0};
  MppiCriticConfig goal_angle{3.0, 1, 0.5, 0};
  MppiCriticConfig path_align{10.0, 1, 0.5, 20};
  double path_align_max_path_occupancy_ratio = 0.07;
  int path_align_trajectory_point_step = 4;
  MppiCriticConfig path_follow{5.0, 1, 1.4, 6};
  MppiCriticConfig path_angle{2.2, 1, 0.5, 20};
  double path_angle_max_angle_to_furthest_rad = 0.7853981633974483;  // Nav2's 0.785398: pi / 4
  int path_angle_mode = 0;
  MppiCriticConfig prefer_forward{5.0, 1, 0.5, 0};
  MppiCriticConfig twirling{10.0, 1, 0.0, 0};
  MppiObstaclesOptions obstacles;
};

const ParamTable<MppiConfig>& mppi_params();

class MppiController final : public LocalController {
 public:
  // Throws Error naming the field for an invalid configuration or a robot the motion model does not fit.
  MppiController(const MppiConfig& config, const RobotConfig& robot, std::uint64_t seed);
  ~MppiController() override;

  std::string_view name() const override { return "mppi"; }
  void set_path(std::span<const Vec2> points) override;
  // A path with reversals is cut at its cusps: the stretch up to the next cusp is followed (its
  // direction preferred, its end pose the local goal) until the robot is within the inversion
  // tolerances of it, then the next.
  void set_path_poses(std::span<const Pose2> poses, std::span<const std::uint8_t> reversing) override;
  void clear() override;
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return full_path_; }
  ControlOutput compute(const ControlInput& input) override;
  double control_period_s() const override { return config_.control_period_s; }
  // A car cannot turn on the spot: it follows line-of-sight paths, not grid corners.
  bool wants_smoothed_path() const override { return model_ == MppiMotionModel::Ackermann; }
  void keep_diagnostics(bool on) override { keep_ = on; }
  std::optional<ControlDiagnostics> diagnostics() const override;

  const MppiConfig& config() const { return config_; }
  MppiMotionModel motion_model() const { return model_; }
  // The robot's own limits within the configuration's (a step's are lowered by its input's).
  const MppiLimits& limits() const { return limits_; }
  const std::vector<std::unique_ptr<MppiCritic>>& critics() const { return critics_; }
  // The current optimal control sequence (after the last step's smoothing).
  const MppiSequence& sequence() const { return sequence_; }
  // The last step's batch (its controls within the limits, trajectories and costs).
  const MppiControls& samples() const { return samples_; }
  const MppiTrajectories& trajectories() const { return trajectories_; }
  const Eigen::ArrayXf& costs() const { return costs_.total; }
  const FootprintChecker& footprint() const { return checker_; }

 private:
  void reset_optimizer();
  void draw_noise();
  void shift_sequence(int steps);
  void update_progress(const Vec2& p);
  // The path as given (set_path: headings 0, all forward), cut into its stretches.
  void take_path(std::vector<Pose2> poses, std::vector<std::uint8_t> reversing, bool pose_path);
  void load_stretch(std::size_t k);
  // `robot` within the inversion tolerances of `cusp`.
  bool at_pose(const Pose2& robot, const Pose2& cusp) const;
  void build_local_path(MppiScene& scene) const;
  // One iteration: sample, roll out, score, average. False when every sample collides.
  bool iterate(MppiScene& scene, const BodyTwist& velocity);
  // An Ackermann controller sampling in curvature (vx, curvature; wz = vx x curvature).
  bool curvature_sampling() const { return model_ == MppiMotionModel::Ackermann && config_.sample_curvature; }
  double curvature_std() const;
  bool trajectory_collides(const MppiScene& scene, const MppiTrajectories& t, int steps) const;
  void record(const ControlInput& in, const MppiScene& scene, const ControlOutput& out);

  MppiConfig config_;
  RobotConfig robot_;
  MppiMotionModel model_ = MppiMotionModel::DiffDrive;
  MppiLimits limits_;
  Rng rng_;
  std::vector<std::unique_ptr<MppiCritic>> critics_;
  const MppiObstaclesCritic* obstacles_ = nullptr;
  FootprintChecker checker_;
  FootprintChecker validator_checker_;
  std::vector<Vec2> full_path_;  // the whole path as given
  // Its stretches between cusps (one for a path without reversals): first and last pose index,
  // and the stretch followed now.
  std::vector<Pose2> poses_;
  std::vector<std::uint8_t> reversing_;
  std::vector<std::pair<std::size_t, std::size_t>> stretches_;
  std::size_t stretch_ = 0;
  bool pose_path_ = false;  // set by set_path_poses
  std::optional<double> stalled_since_s_;
  std::optional<double> stretch_since_s_;  // when the current stretch was first driven
  std::vector<Vec2> path_;       // the stretch followed now
  std::vector<double> along_;
  std::size_t segment_ = 0;
  ClearanceWindow map_;

  MppiSequence sequence_;
  std::array<BodyTwist, 4> history_{};
  std::array<float, 4> curvature_history_{};
  std::optional<double> last_t_s_;
  MppiControls noise_, samples_;
  MppiTrajectories trajectories_;
  MppiCosts costs_;
  Eigen::ArrayXf weights_;

  bool keep_ = false;
  ControlDiagnostics last_;
};

}  // namespace starnav
