#pragma once
// The one time-ordered dispatcher of sensor messages (sense/sensor_messages.hpp). Sources (the
// simulator's sensors, a recorded log) publish; consumers (odometry integration, localizers, SLAM,
// costmap layers, recorders) subscribe by message type and stream. Delivery is in time order, ties
// in publication order, so what a consumer sees follows from the data (a wheel-odometry integrator
// that turns encoder ticks into an odometry message publishes it at the ticks' time, and the
// localizer subscribed to odometry gets it next), not from the order in which the parts were built.
//
//   SensorBus bus;
//   bus.subscribe<ScanMessage>("lidar", [&](const ScanMessage& s) { localizer.on_scan(s); });
//   bus.publish(scan);          // queued
//   bus.deliver_until(t);       // every message stamped <= t, in order
//
// A message published while another is being delivered joins the queue: when stamped no later
// than the bound of the running deliver_until it is delivered in the same call, after the ones
// already queued for its time.
//
// Two orders. A simulation publishes in time order and its bus (Order::Time) refuses the past. A
// recording is played in the order its messages were received (Order::Receipt), as a robot's
// middleware delivers them: a log whose stamps go backwards now and then (a driver's clock stepping
// back) is played as recorded, each message after the ones published before it, whatever its stamp.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <queue>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "starnav/sense/sensor_messages.hpp"

namespace starnav {

using SensorMessage = std::variant<ScanMessage, CloudMessage, ImuMessage, EncoderMessage, OdometryMessage, BumperMessage>;

// The stream a message was published on, whatever its type.
const SensorHeader& header_of(const SensorMessage& message);

class SensorBus {
 public:
  enum class Order : std::uint8_t { Time, Receipt };
  explicit SensorBus(Order order = Order::Time) : queue_(Later{order == Order::Receipt}), order_(order) {}

  template <class M>
  using Handler = std::function<void(const M&)>;

  // `handler` gets every message of type M published on `stream` ("" : on any stream), in the order
  // of delivery; several handlers of one message are called in the order they subscribed.
  template <class M>
  void subscribe(std::string stream, Handler<M> handler) {
    static_assert(is_message<M>(), "not a sensor message type");
    subscribers_.push_back({SensorMessage(std::in_place_type<M>).index(), std::move(stream),
                            [h = std::move(handler)](const SensorMessage& m) { h(std::get<M>(m)); }});
  }

  // Queues `message`. Error when its time is not finite or, in time order, lies before a message
  // already delivered: the past cannot change.
  void publish(SensorMessage message);
  // Time order: delivers every queued message stamped at or before `t`, in time order, ties in
  // publication order. Receipt order: the queued messages in publication order up to the first
  // stamped after `t`.
  void deliver_until(double t);
  // Delivers everything queued (and whatever that publishes).
  void deliver_all();

  Order order() const { return order_; }
  std::size_t queued() const { return queue_.size(); }
  double last_delivered_t() const { return last_t_; }
  std::uint64_t delivered() const { return delivered_; }

 private:
  template <class M>
  static constexpr bool is_message() {
    return std::is_same_v<M, ScanMessage> || std::is_same_v<M, CloudMessage> || std::is_same_v<M, ImuMessage> ||
           std::is_same_v<M, EncoderMessage> || std::is_same_v<M, OdometryMessage> || std::is_same_v<M, BumperMessage>;
  }
  struct Subscriber {
    std::size_t type;
    std::string stream;
    std::function<void(const SensorMessage&)> call;
  };
  struct Queued {
    double t;
    std::uint64_t sequence;
    SensorMessage message;
  };
  struct Later {
    bool receipt = false;
    bool operator()(const Queued& a, const Queued& b) const {
      if (receipt || a.t == b.t) return a.sequence > b.sequence;
      return a.t > b.t;
    }
  };
  void deliver(const SensorMessage& m);

  std::vector<Subscriber> subscribers_;
  std::priority_queue<Queued, std::vector<Queued>, Later> queue_;
  Order order_;
  std::uint64_t sequence_ = 0;
  std::uint64_t delivered_ = 0;
  double last_t_ = -1e300;
};

}  // namespace starnav
