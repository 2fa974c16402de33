#include "starnav/harness/command_arbiter.hpp"

#include <utility>

namespace starnav {

const char* command_source_name(CommandSource s) {
  switch (s) {
    case CommandSource::Autonomous: return "autonomous";
    case CommandSource::Manual: return "manual";
    case CommandSource::BumperStop: return "bumper_stop";
    case CommandSource::BumperWait: return "bumper_wait";
  }
  return "unknown";
}

CommandArbiter::CommandArbiter(const CommandArbiterConfig& config, std::vector<ScenarioManualCommand> manual)
    : config_(config), manual_(std::move(manual)) {}

CommandArbiter::Decision CommandArbiter::decide(double t, bool bumper_contact) {
  Decision d;
  if (contact_ && !bumper_contact) released_t_ = t;
  contact_ = bumper_contact;
  while (next_manual_ < manual_.size() && t >= manual_[next_manual_].t_s + manual_[next_manual_].duration_s) ++next_manual_;
  if (config_.bumper_stop && bumper_contact) {
    d.source = CommandSource::BumperStop;
  } else if (config_.bumper_stop && t < released_t_ + config_.resume_delay_s) {
    d.source = CommandSource::BumperWait;
  } else if (next_manual_ < manual_.size() && t >= manual_[next_manual_].t_s) {
    d.source = CommandSource::Manual;
    d.twist = manual_[next_manual_].twist;
  }
  if (d.source != current_) {
    events_.push_back({t, command_source_name(d.source)});
    current_ = d.source;
  }
  return d;
}

}  // namespace starnav
