#include "starnav/sense/sensor_bus.hpp"

#include <cmath>
#include <utility>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

const SensorHeader& header_of(const SensorMessage& message) {
  return std::visit([](const auto& m) -> const SensorHeader& { return m.header; }, message);
}

void SensorBus::publish(SensorMessage message) {
  const SensorHeader& h = header_of(message);
  if (!std::isfinite(h.t_s)) throw Error("a sensor message's time is not finite", "", 0, h.stream);
  if (order_ == Order::Time && h.t_s < last_t_)
    throw Error("a message stamped " + format_readable(h.t_s, 9) + " s arrived after one stamped " +
                    format_readable(last_t_, 9) + " s was delivered (sources must publish in time order)",
                "", 0, h.stream);
  const double t = h.t_s;
  queue_.push({t, sequence_++, std::move(message)});
}

void SensorBus::deliver(const SensorMessage& m) {
  const SensorHeader& h = header_of(m);
  const std::size_t type = m.index();
  last_t_ = h.t_s;
  ++delivered_;
  for (const Subscriber& s : subscribers_)
    if (s.type == type && (s.stream.empty() || s.stream == h.stream)) s.call(m);
}

void SensorBus::deliver_until(double t) {
  while (!queue_.empty() && queue_.top().t <= t) {
    // Moved out before delivery: a handler may publish, which reorders the heap.
    SensorMessage m = std::move(const_cast<Queued&>(queue_.top()).message);
    queue_.pop();
    deliver(m);
  }
}

void SensorBus::deliver_all() {
  while (!queue_.empty()) {
    SensorMessage m = std::move(const_cast<Queued&>(queue_.top()).message);
    queue_.pop();
    deliver(m);
  }
}

}  // namespace starnav
