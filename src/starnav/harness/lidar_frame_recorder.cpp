#include "starnav/harness/lidar_frame_recorder.hpp"

#include <cstdio>
#include <filesystem>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/encoder_odometry.hpp"
#include "starnav/io/file_bytes.hpp"

namespace starnav {

namespace fs = std::filesystem;

struct LidarFrameRecorder::State {
  std::string dir;
  int every = 1;
  std::int64_t scans = 0;
  std::vector<LidarFrameRecord> rows;
  std::shared_ptr<const WheelOdometry> odometry;  // null without encoders
  std::optional<double> imu_yaw_rate;
};

LidarFrameRecorder::LidarFrameRecorder(Simulation& sim, const std::string& dir, int every_n_scans)
    : state_(std::make_shared<State>()) {
  const ScenarioSpec& spec = sim.spec();
  if (!spec.lidar) throw Error("LiDAR frames need sensors.lidar", spec.file, 0, "outputs.lidar_frames");
  require(every_n_scans >= 1, "outputs.lidar_frames.every_n_scans", "must be >= 1");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error("cannot create the folder: " + ec.message(), dir, 0, "--out");
  state_->dir = dir;
  state_->every = every_n_scans;
  const LidarConfig& lidar = spec.lidar->config;
  write_file_bytes((fs::path(dir) / "sensor.yaml").string(),
                   lidar_sensor_yaml(lidar.model, lidar.lines(), lidar.beams, lidar.rate_hz, lidar.range_min, lidar.range_max,
                                     lidar.mount));
  state_->odometry = attach_encoder_odometry(sim);
  sim.imu_feed.subscribe(SampleStage::Record, [st = state_](const ImuModel::ImuReading& r) { st->imu_yaw_rate = r.yaw_rate_radps; });
  const Simulation* s = &sim;
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [st = state_, s](const LidarScan& scan) {
    if (st->scans++ % st->every != 0) return;
    LidarFrameRecord r;
    r.frame = static_cast<int>(st->rows.size());
    r.t_s = scan.time;
    char name[32];
    std::snprintf(name, sizeof name, "%06d.pcd", r.frame);
    r.cloud = name;
    if (st->odometry) r.odometry = st->odometry->pose();
    r.imu_yaw_rate_radps = st->imu_yaw_rate;
    r.truth = s->vehicle().state().pose;
    write_point_cloud((fs::path(st->dir) / name).string(), scan.points_sensor, PointCloudFormat::Pcd, PointCloudEncoding::Binary);
    st->rows.push_back(r);
  });
}

void LidarFrameRecorder::finish() const {
  std::string csv = lidar_frames_header();
  for (const LidarFrameRecord& r : state_->rows) csv += lidar_frame_row(r);
  write_file_bytes((fs::path(state_->dir) / "frames.csv").string(), csv);
}

std::size_t LidarFrameRecorder::frames() const { return state_->rows.size(); }

}  // namespace starnav
