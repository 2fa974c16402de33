#pragma once
// The DWA local controller (registry name "dwa"; dwa.hpp describes the method): the LocalController
// of the DWA, its path bookkeeping (progress along the path, the local path and goal inside the
// window), the goal window, and a record of its last step's samples for pictures.
#include <memory>
#include <optional>
#include <vector>

#include "starnav/control/dwa.hpp"
#include "starnav/control/dwa_critics.hpp"
#include "starnav/control/local_controller.hpp"

namespace starnav {

// What the last control step did.
struct DwaStepRecord {
  double t_s = 0.0;
  Pose2 pose;
  DynamicWindow window;
  std::vector<DwaSample> samples;  // in sampling order (vx outer, then vy, then wz)
  int chosen = -1;                 // index into samples; -1: none was valid
  ControlStatus status = ControlStatus::Idle;
  Vec2 local_goal = Vec2::Zero();
  double margin_cut_m = 0.0;  // how much of the safety margin this step gave up (the robot started inside it)
};

class DwaController final : public LocalController {
 public:
  // Throws Error naming the field for an invalid configuration or robot.
  DwaController(const DwaConfig& config, const RobotConfig& robot);
  ~DwaController() override;

  std::string_view name() const override { return "dwa"; }
  void set_path(std::span<const Vec2> points) override;
  void clear() override;
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  ControlOutput compute(const ControlInput& input) override;
  double control_period_s() const override { return config_.control_period_s; }

  const DwaConfig& config() const { return config_; }
  const RobotConfig& robot() const { return robot_; }
  const FootprintChecker& footprint() const { return checker_; }
  // The robot's own limits; a step's are those of its input (ControlInput::limits: a speed-limit
  // zone lowers them), within the configuration's.
  const DwaLimits& limits() const { return limits_; }
  // The local window on cells of `resolution`: its half-width (window_m / 2, or what a rollout, its
  // forward point and its footprint reach) and its padding (the footprint's reach and
  // inflation_radius_m, plus a cell).
  struct WindowExtent {
    double half_m = 0.0, pad_m = 0.0;
  };
  WindowExtent window_extent(double resolution) const;
  const std::vector<std::unique_ptr<DwaCritic>>& critics() const { return critics_; }
  // The last step's samples (kept only with keep_samples; then every sample's footprint is tested,
  // otherwise only those cheaper than the first clear one: the same choice either way).
  void keep_samples(bool on) { keep_samples_ = on; }
  void keep_diagnostics(bool on) override { keep_samples(on); }
  // Every sample of the last step with its rollout, the chosen one, the local goal.
  std::optional<ControlDiagnostics> diagnostics() const override;
  const DwaStepRecord& last_step() const { return last_; }
  // The local map of the last step.
  const ClearanceWindow& local_map() const { return map_; }

 private:
  void update_progress(const Vec2& p);
  void build_local_path(DwaScene& scene) const;
  // The footprint along poses_ (grown by extra_m) touches an obstacle.
  bool swept_footprint_collides(double extra_m);

  DwaConfig config_;
  RobotConfig robot_;
  std::unique_ptr<RobotModel> model_;
  bool holonomic_ = false;
  DwaLimits limits_;
  FootprintChecker checker_;
  std::vector<std::unique_ptr<DwaCritic>> critics_;
  std::vector<Vec2> path_;
  std::size_t segment_ = 0;   // progress: the path segment the robot is nearest (never goes back)
  bool in_goal_window_ = false;
  bool keep_samples_ = false;
  ClearanceWindow map_;
  DwaScene scene_;
  DwaStepRecord last_;
  std::vector<Pose2> poses_;           // rollout scratch
  std::vector<Vec2> headings_;         // (cos, sin) of each rollout pose
  std::vector<double> wheel_scratch_;
  std::vector<std::size_t> unsure_;
  struct Candidate {
    double cost;
    int index;
    BodyTwist twist;
    int n_check;
    double extra;
  };
  std::vector<Candidate> candidates_;
};

}  // namespace starnav
