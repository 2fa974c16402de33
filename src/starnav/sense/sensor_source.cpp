#include "starnav/sense/sensor_source.hpp"

namespace starnav {

void play_onto_bus(SensorSource& source, SensorBus& bus, const std::function<void(std::size_t)>& published) {
  source.play([&](const SensorMessage& m) { bus.publish(m); },
              [&](std::size_t k) {
                bus.deliver_all();
                if (published) published(k);
              });
}

}  // namespace starnav
