#include "starnav/cloud/lidar_recording_source.hpp"

#include <algorithm>
#include <utility>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

LidarRecordingSource::LidarRecordingSource(const LidarRecording& recording, std::size_t frames, LidarRecordingStreams streams)
    : recording_(recording),
      count_(frames == 0 ? recording.frames.frames.size() : std::min(frames, recording.frames.frames.size())),
      streams_(std::move(streams)) {}

void LidarRecordingSource::play(SensorBus& bus, const std::function<void(std::size_t)>& published) {
  const std::vector<LidarFrameRecord>& frames = recording_.frames.frames;
  for (std::size_t i = 1; i < count_; ++i)
    if (frames[i].t_s < frames[i - 1].t_s)
      throw Error("frame " + std::to_string(i) + " is stamped " + format_fixed6(frames[i].t_s) + " s, before the frame before it (" +
                      format_fixed6(frames[i - 1].t_s) + " s)",
                  recording_.path, 0, "t_s");
  recording_.for_each_cloud(count_, [&](std::size_t i, PointCloud&& cloud) {
    const LidarFrameRecord& f = frames[i];
    if (f.odometry) {
      OdometryMessage o;
      o.header = {f.t_s, streams_.odometry};
      o.pose = *f.odometry;
      bus.publish(std::move(o));
    }
    CloudMessage c;
    c.header = {f.t_s, streams_.cloud};
    c.mount = recording_.frames.mount;
    c.points = std::move(cloud);
    bus.publish(std::move(c));
    if (published) published(i + 1);
  });
}

}  // namespace starnav
