#pragma once
// The progress-checker role (Nav2's ProgressChecker): whether the robot keeps making progress. The
// navigator asks it at every control step while it drives; when it says no, the navigator starts
// its recoveries. Built by name from the registry (navigation.progress_checker).
#include <string>
#include <string_view>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"

namespace starnav {

class ProgressChecker {
 public:
  virtual ~ProgressChecker() = default;
  virtual std::string_view name() const = 0;
  // Forget everything: the next check() starts measuring from where the robot is then.
  virtual void reset() = 0;
  // Something else drove the robot until t (a manual command, a bumper stop): the allowed time
  // starts again at t from the same reference.
  virtual void restart_clock(double t) = 0;
  // True while the robot makes progress. False once it has not: the checker then starts measuring
  // again from t.
  virtual bool check(const Pose2& pose, double t) = 0;
};

struct ProgressCheckerContext {
  std::string file;
};
using ProgressCheckerDef = ComponentDef<ProgressChecker, ProgressCheckerContext>;

}  // namespace starnav
