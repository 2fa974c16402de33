#pragma once
// The simulator's sensor samples, handed out as they are taken (truth included: a LiDAR scan carries
// the sensor's true pose and its world points), to whoever subscribed, in stages: estimators first
// (odometry integration, localizers, SLAM: their estimate then includes the sample), then the
// navigation that uses that estimate, then recorders and pictures; within a stage, in the order of
// subscription. The stage, not the order in which the parts were built, says who sees a sample
// first. Roles never subscribe here: the localization chain turns samples into the sensor-frame
// messages a robot's drivers publish (sense/sensor_messages.hpp) before any role sees them.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace starnav {

enum class SampleStage : std::uint8_t { Estimate, Navigate, Record };

template <class Sample>
class SampleFeed {
 public:
  using Handler = std::function<void(const Sample&)>;

  void subscribe(SampleStage stage, Handler handler) {
    handlers_[static_cast<std::size_t>(stage)].push_back(std::move(handler));
  }
  void publish(const Sample& sample) const {
    for (const std::vector<Handler>& stage : handlers_)
      for (const Handler& h : stage) h(sample);
  }

 private:
  std::array<std::vector<Handler>, 3> handlers_;
};

}  // namespace starnav
