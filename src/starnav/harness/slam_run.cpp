#include "starnav/harness/slam_run.hpp"

#include <chrono>

#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

std::unique_ptr<Slam> make_slam(const SlamChoice& choice) {
  const SlamDef& def = find_slam(choice.method, choice.field);
  SlamContext ctx;
  ctx.file = choice.file;
  ctx.seed = choice.seed;
  ctx.matcher = choice.matcher;
  return def.make(ctx, choice.settings);
}

namespace {

// Adds the wall time of a scope to a total.
class WallTimer {
 public:
  explicit WallTimer(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~WallTimer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  WallTimer(const WallTimer&) = delete;
  WallTimer& operator=(const WallTimer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

SlamDriveTimes drive_slam(Slam& slam, SensorSource& source, const SlamStreams& streams, const SlamProgress& progress) {
  SlamDriveTimes times;
  // The Slam role, as a simulation would drive it: the recording's messages on a bus, in the order
  // they were received, the role subscribed to the streams the run listens to (scans for a planar
  // method, clouds for a 3D one).
  SensorBus bus(SensorBus::Order::Receipt);
  const auto timed = [&times](auto call) {
    return [&times, call](const auto& message) {
      const WallTimer timer(times.slam_wall_s);
      call(message);
    };
  };
  bus.subscribe<OdometryMessage>(streams.odometry, timed([&slam](const OdometryMessage& m) { slam.on_odometry(m); }));
  if (slam.space() == SlamSpace::Planar)
    bus.subscribe<ScanMessage>(streams.scan, timed([&slam](const ScanMessage& m) { slam.on_scan(m); }));
  else
    bus.subscribe<CloudMessage>(streams.cloud, timed([&slam](const CloudMessage& m) { slam.on_cloud(m); }));
  bus.subscribe<ImuMessage>(streams.imu, timed([&slam](const ImuMessage& m) { slam.on_imu(m); }));
  const std::size_t total = source.readings();
  const double cpu0 = thread_cpu_s();
  const auto wall0 = std::chrono::steady_clock::now();
  if (progress) progress(0, total);
  play_onto_bus(source, bus, [&](std::size_t done) {
    if (progress && (done % 100 == 0 || done == total)) progress(done, total);
  });
  try {
    const WallTimer timer(times.slam_wall_s);
    slam.finish();
  } catch (const Error& e) {
    throw e.file().empty() ? e.with_file(source.origin()) : e;
  }
  times.cpu_s = thread_cpu_s() - cpu0;
  times.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return times;
}

}  // namespace starnav
