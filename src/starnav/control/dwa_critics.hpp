#pragma once
// The DWA controller's critics, one small class each as Nav2's DWB has them
// (docs/local_planning.md, "Critics"). A critic returns a cost >= 0 for a rolled-out sample
// (lower is better; kInvalidTrajectory rejects it); the controller adds the costs times their
// weights. Distances are in metres, angles in radians.
//
//   path_align      distance from the path of a point forward_point_m ahead of the rollout's end
//                   (ahead along the heading, or along the motion for a holonomic robot); near
//                   the goal, from the path carried on past the goal (DwaScene::align_path);
//                   off within forward_point_m of the goal (DWB's rule)
//   path_dist       distance from the path of the rollout's end
//   goal_align      distance of the forward point to the local goal (through free cells), or
//                   near the goal to the end of the carried-on path; off like path_align
//   goal_dist       distance to the local goal of the rollout's end (through free cells; at least
//                   the straight-line distance); unreachable ends are rejected
//   obstacle        the largest proximity cost along the rollout: exp(-k (d - r_in)) within the
//                   inflation radius, d the distance to the nearest obstacle, r_in the footprint's
//                   inscribed radius
//   velocity        1 - speed / max speed: prefers progress
//   twirling        |wz| / max wz: a holonomic robot should not spin while it translates (holonomic
//                   robots only)
//   path_angle      |heading at the rollout's end - the path's direction at the robot| (or the
//                   goal's heading on the final approach, DwaConfig::holonomic_approach_m): turns
//                   the body along the path, from rest too, where the alignment critics pull
//                   both ways
//   prefer_forward  backwards speed / max speed
//   oscillation     1 for a sample that reverses an axis (vx, vy or wz) that has already
//                   reversed since the robot last moved oscillation_reset_m, turned
//                   oscillation_reset_rad or came to rest: damps back-and-forth
//   rotate_to_goal  in the goal window: the yaw error where the robot would stop turning
//                   (current yaw + wz T + wz |wz| / (2 a)); 0 elsewhere
#include <array>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "starnav/control/dwa.hpp"

namespace starnav {

inline constexpr double kInvalidTrajectory = std::numeric_limits<double>::infinity();

class DwaCritic {
 public:
  explicit DwaCritic(double weight) : weight_(weight) {}
  virtual ~DwaCritic() = default;
  virtual std::string_view name() const = 0;
  double weight() const { return weight_; }
  // Once per control step, before the samples are scored.
  virtual void prepare(const DwaScene& /*scene*/) {}
  virtual double score(const DwaScene& scene, const DwaRollout& rollout) const = 0;
  // The command chosen at this step (critics with memory update it here).
  virtual void chosen(const DwaScene& /*scene*/, const BodyTwist& /*twist*/) {}
  // A new path: forget what was remembered.
  virtual void reset() {}

 private:
  double weight_;
};

// The point forward_m ahead of `end`, along the heading or (align_by_motion and moving) along the
// direction of the twist's translation.
Vec2 dwa_forward_point(const Pose2& end, const BodyTwist& twist, double forward_m, bool align_by_motion);
// Distance to the local goal at a world point: the wavefront's value at its cell less one cell
// diagonal, but at least the straight-line distance; +inf outside the window or unreachable.
double dwa_goal_distance(const DwaScene& scene, const Vec2& p);

class PathAlignCritic final : public DwaCritic {
 public:
  PathAlignCritic(double weight, double forward_m) : DwaCritic(weight), forward_m_(forward_m) {}
  std::string_view name() const override { return "path_align"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;

 private:
  double forward_m_;
};

class PathDistCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "path_dist"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class GoalAlignCritic final : public DwaCritic {
 public:
  GoalAlignCritic(double weight, double forward_m) : DwaCritic(weight), forward_m_(forward_m) {}
  std::string_view name() const override { return "goal_align"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;

 private:
  double forward_m_;
};

class GoalDistCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "goal_dist"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class ObstacleCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "obstacle"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class VelocityCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "velocity"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class TwirlingCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "twirling"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class PathAngleCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "path_angle"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class PreferForwardCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "prefer_forward"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

class OscillationCritic final : public DwaCritic {
 public:
  OscillationCritic(double weight, double reset_m, double reset_rad)
      : DwaCritic(weight), reset_m_(reset_m), reset_rad_(reset_rad) {}
  std::string_view name() const override { return "oscillation"; }
  void prepare(const DwaScene& scene) override;
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
  void chosen(const DwaScene& scene, const BodyTwist& twist) override;
  void reset() override;
  // Per axis (vx, vy, wz): the sign of the last non-zero command, and whether that axis has
  // reversed since the robot last moved far enough.
  const std::array<int, 3>& last_sign() const { return sign_; }
  const std::array<bool, 3>& reversed() const { return reversed_; }

 private:
  double reset_m_, reset_rad_;
  std::array<int, 3> sign_{};
  std::array<bool, 3> reversed_{};
  std::array<Pose2, 3> reversed_at_{};
};

class RotateToGoalCritic final : public DwaCritic {
 public:
  using DwaCritic::DwaCritic;
  std::string_view name() const override { return "rotate_to_goal"; }
  double score(const DwaScene& scene, const DwaRollout& rollout) const override;
};

// The critics of `config` with a non-zero weight, in the order listed above (twirling only for a
// holonomic robot).
std::vector<std::unique_ptr<DwaCritic>> make_dwa_critics(const DwaConfig& config, bool holonomic);

}  // namespace starnav
