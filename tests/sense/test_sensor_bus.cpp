// The sensor bus: delivery in time order whatever the publication order, ties in publication
// order, a message published during a delivery delivered in the same call when due, subscriptions
// by type and stream, and the past refused; in receipt order (recordings), publication order.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/sense/sensor_bus.hpp"

namespace starnav {
namespace {

ScanMessage scan_at(double t, const std::string& stream) {
  ScanMessage m;
  m.header = {t, stream};
  return m;
}
OdometryMessage odom_at(double t) {
  OdometryMessage m;
  m.header = {t, "odom"};
  return m;
}

TEST(SensorBus, DeliversInTimeOrderTiesInPublicationOrder) {
  SensorBus bus;
  std::vector<std::string> seen;
  bus.subscribe<ScanMessage>("", [&](const ScanMessage& m) { seen.push_back(m.header.stream + "@" + std::to_string(m.header.t_s)); });
  bus.publish(scan_at(0.3, "a"));
  bus.publish(scan_at(0.1, "b"));
  bus.publish(scan_at(0.3, "c"));
  bus.publish(scan_at(0.2, "d"));
  bus.deliver_until(0.25);
  EXPECT_EQ(seen, (std::vector<std::string>{"b@0.100000", "d@0.200000"}));
  EXPECT_EQ(bus.queued(), 2u);
  bus.deliver_all();
  EXPECT_EQ(seen, (std::vector<std::string>{"b@0.100000", "d@0.200000", "a@0.300000", "c@0.300000"}));
  EXPECT_EQ(bus.delivered(), 4u);
}

TEST(SensorBus, AMessagePublishedWhileDeliveringFollowsTheDataNotTheConstructionOrder) {
  SensorBus bus;
  std::vector<std::string> seen;
  // The localizer subscribes before the integrator that feeds it: it still gets the odometry of
  // t = 1 before the scan of t = 1.5, and the odometry made from the ticks of t = 1 right after them.
  bus.subscribe<OdometryMessage>("odom", [&](const OdometryMessage& m) { seen.push_back("odom " + std::to_string(m.header.t_s)); });
  bus.subscribe<ScanMessage>("lidar", [&](const ScanMessage&) { seen.push_back("scan"); });
  bus.subscribe<EncoderMessage>("encoders", [&](const EncoderMessage& m) {
    seen.push_back("ticks");
    bus.publish(odom_at(m.header.t_s));
  });
  EncoderMessage e;
  e.header = {1.0, "encoders"};
  bus.publish(e);
  bus.publish(scan_at(1.5, "lidar"));
  bus.publish(scan_at(1.0, "lidar"));
  bus.deliver_until(2.0);
  EXPECT_EQ(seen, (std::vector<std::string>{"ticks", "scan", "odom 1.000000", "scan"}));
}

TEST(SensorBus, SubscriptionsAreByTypeAndStream) {
  SensorBus bus;
  int front = 0, any = 0, odom = 0;
  bus.subscribe<ScanMessage>("lidar/front", [&](const ScanMessage&) { ++front; });
  bus.subscribe<ScanMessage>("", [&](const ScanMessage&) { ++any; });
  bus.subscribe<OdometryMessage>("", [&](const OdometryMessage&) { ++odom; });
  bus.publish(scan_at(0.0, "lidar/front"));
  bus.publish(scan_at(0.0, "lidar/rear"));
  bus.publish(odom_at(0.0));
  bus.deliver_all();
  EXPECT_EQ(front, 1);
  EXPECT_EQ(any, 2);
  EXPECT_EQ(odom, 1);
}

TEST(SensorBus, ThePastCannotChange) {
  SensorBus bus;
  bus.publish(scan_at(1.0, "lidar"));
  bus.deliver_all();
  EXPECT_THROW(bus.publish(scan_at(0.5, "lidar")), Error);
  EXPECT_THROW(bus.publish(scan_at(std::numeric_limits<double>::quiet_NaN(), "lidar")), Error);
  bus.publish(scan_at(1.0, "lidar"));  // the same time is not the past
}

TEST(SensorBus, InReceiptOrderAStampGoingBackIsDeliveredAsReceived) {
  // A recording whose driver's clock stepped back: played as received, as a robot's middleware
  // delivers it, where a time-ordered bus refuses it.
  SensorBus bus(SensorBus::Order::Receipt);
  std::vector<double> seen;
  bus.subscribe<ScanMessage>("", [&](const ScanMessage& m) { seen.push_back(m.header.t_s); });
  bus.publish(scan_at(2.0, "lidar"));
  bus.publish(scan_at(1.0, "lidar"));
  bus.publish(scan_at(3.0, "lidar"));
  bus.deliver_until(2.5);  // up to the first message stamped after the bound
  EXPECT_EQ(seen, (std::vector<double>{2.0, 1.0}));
  bus.deliver_all();
  bus.publish(scan_at(0.5, "lidar"));  // before what was delivered: still taken
  bus.deliver_all();
  EXPECT_EQ(seen, (std::vector<double>{2.0, 1.0, 3.0, 0.5}));
  EXPECT_THROW(bus.publish(scan_at(std::numeric_limits<double>::quiet_NaN(), "lidar")), Error);
  SensorBus timed;
  timed.publish(scan_at(2.0, "lidar"));
  timed.deliver_all();
  EXPECT_THROW(timed.publish(scan_at(1.0, "lidar")), Error);
}

}  // namespace
}  // namespace starnav
