#pragma once
// Who commands the robot at each step (docs/papers/ren2022.md): a bumper contact stops it, a
// manual command outranks the navigation, the navigation drives otherwise. After a contact ends
// the robot waits resume_delay_s, then the lower sources command again.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/robot/robot_model.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

enum class CommandSource : std::uint8_t { Autonomous, Manual, BumperStop, BumperWait };
const char* command_source_name(CommandSource s);  // "autonomous", "manual", "bumper_stop", "bumper_wait"

struct CommandArbiterConfig {
  bool bumper_stop = true;      // false: contacts are recorded but change nothing
  double resume_delay_s = 0.5;  // wait after a contact ends before moving again
};

struct ArbiterEvent {
  double t_s = 0.0;
  std::string kind;  // the source that took over: bumper_stop, bumper_wait, manual, autonomous
};

class CommandArbiter {
 public:
  // `manual` in time order, not overlapping (as the scenario parser guarantees).
  CommandArbiter(const CommandArbiterConfig& config, std::vector<ScenarioManualCommand> manual);

  struct Decision {
    CommandSource source = CommandSource::Autonomous;
    BodyTwist twist;  // zero for the bumper states; the manual twist for Manual; unset for Autonomous
  };
  // The source at time t (non-decreasing across calls) with the bumper's current state.
  Decision decide(double t, bool bumper_contact);
  const std::vector<ArbiterEvent>& events() const { return events_; }
  CommandSource current() const { return current_; }

 private:
  CommandArbiterConfig config_;
  std::vector<ScenarioManualCommand> manual_;
  std::size_t next_manual_ = 0;
  double released_t_ = -1e300;  // when the last contact ended
  bool contact_ = false;
  CommandSource current_ = CommandSource::Autonomous;
  std::vector<ArbiterEvent> events_;
};

}  // namespace starnav
