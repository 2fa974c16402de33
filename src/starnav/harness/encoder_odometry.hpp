#pragma once
// Wheel odometry as a robot's base driver computes it: integrated from the simulator's encoder
// samples (with their slip and quantisation), the way every recorder and experiment that needs
// the robot's own odometry attaches it.
#include <functional>
#include <memory>

#include "starnav/estimate/wheel_odometry.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

// Subscribes to the simulation's encoder samples as an estimator (SampleStage::Estimate): each
// sample is integrated into the returned odometry, then calls `after` with the sample and the new pose. Null when the
// scenario has no encoders. The odometry starts at the scenario's start pose.
using EncoderOdometryHook = std::function<void(const EncoderSample&, const Pose2&)>;
std::shared_ptr<const WheelOdometry> attach_encoder_odometry(Simulation& sim, EncoderOdometryHook after = {});

}  // namespace starnav
