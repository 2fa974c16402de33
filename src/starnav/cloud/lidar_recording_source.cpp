#include "starnav/cloud/lidar_recording_source.hpp"

#include <algorithm>
#include <utility>


namespace starnav {

LidarRecordingSource::LidarRecordingSource(const LidarRecording& recording, std::size_t frames, LidarRecordingStreams streams)
    : recording_(recording),
      count_(frames == 0 ? recording.frames.frames.size() : std::min(frames, recording.frames.frames.size())),
      streams_(std::move(streams)) {}

void LidarRecordingSource::play(const SensorSink& sink, const std::function<void(std::size_t)>& published) {
  const std::vector<LidarFrameRecord>& frames = recording_.frames.frames;
  recording_.for_each_cloud(count_, [&](std::size_t i, PointCloud&& cloud) {
    const LidarFrameRecord& f = frames[i];
    if (f.odometry) {
      OdometryMessage o;
      o.header = {f.t_s, streams_.odometry};
      o.pose = *f.odometry;
      sink(SensorMessage(std::move(o)));
    }
    CloudMessage c;
    c.header = {f.t_s, streams_.cloud};
    c.mount = recording_.frames.mount;
    c.points = std::move(cloud);
    sink(SensorMessage(std::move(c)));
    if (published) published(i + 1);
  });
}

}  // namespace starnav
