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
  const bool planar = slam.space() == SlamSpace::Planar;
  // Each message to the role's call for its type, on the streams the run listens to.
  const auto deliver = [&](const SensorMessage& message) {
    const std::string& stream = header_of(message).stream;
    const WallTimer timer(times.slam_wall_s);
    if (const auto* m = std::get_if<OdometryMessage>(&message)) {
      if (stream == streams.odometry) slam.on_odometry(*m);
    } else if (const auto* s = std::get_if<ScanMessage>(&message)) {
      if (planar && stream == streams.scan) slam.on_scan(*s);
    } else if (const auto* c = std::get_if<CloudMessage>(&message)) {
      if (!planar && stream == streams.cloud) slam.on_cloud(*c);
    } else if (const auto* i = std::get_if<ImuMessage>(&message)) {
      if (stream == streams.imu) slam.on_imu(*i);
    }
  };
  const std::size_t total = source.readings();
  const double cpu0 = thread_cpu_s();
  const auto wall0 = std::chrono::steady_clock::now();
  if (progress) progress(0, total);
  source.play(deliver, [&](std::size_t done) {
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
