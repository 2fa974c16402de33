#include "starnav/harness/encoder_odometry.hpp"

#include "starnav/robot/robot_model.hpp"

namespace starnav {

namespace {

// The odometry and the model it keeps a reference to, owned together.
struct ModelAndOdometry {
  std::unique_ptr<RobotModel> model;
  std::unique_ptr<WheelOdometry> odometry;
};

}  // namespace

std::shared_ptr<const WheelOdometry> attach_encoder_odometry(Simulation& sim, EncoderOdometryHook after) {
  const ScenarioSpec& spec = sim.spec();
  if (!spec.encoders) return nullptr;
  auto owner = std::make_shared<ModelAndOdometry>();
  owner->model = make_robot_model(spec.vehicle.robot);
  owner->odometry = std::make_unique<WheelOdometry>(*owner->model, spec.encoders->config.ticks_per_rev, spec.start);
  sim.encoder_feed.subscribe(SampleStage::Estimate, [owner, after = std::move(after)](const EncoderSample& e) {
    owner->odometry->add_ticks(e.ticks);
    if (after) after(e, owner->odometry->pose());
  });
  return std::shared_ptr<const WheelOdometry>(owner, owner->odometry.get());
}

}  // namespace starnav
