#include "app/daemon/frame_pipeline.h"

namespace ale::app {

Status FramePipeline::configure(const DaemonConfig& config) {
  ALE_RETURN_IF_ERROR(path_.configure(config.features));
  keypoints_.reserve(static_cast<std::size_t>(config.features.num_features));
  descriptors_.reserve(static_cast<std::size_t>(config.features.num_features));
  return {};
}

Status FramePipeline::process(const ale::hal::Frame& frame, FrameRecord& record) {
  ALE_RETURN_IF_ERROR(check_view(frame.image, "frame"));
  if (width_ == 0) {
    width_ = frame.image.width;
    height_ = frame.image.height;
  }
  if (frame.image.width != width_ || frame.image.height != height_)
    return invalid_argument("frame " + std::to_string(frame.sequence) + " is " + std::to_string(frame.image.width) +
                            "x" + std::to_string(frame.image.height) + ", the stream started at " +
                            std::to_string(width_) + "x" + std::to_string(height_));
  ALE_RETURN_IF_ERROR(path_.extract(frame.image, keypoints_, descriptors_));
  const ale::features::ExtractionStats& stats = path_.stats();
  record.timings = path_.timings();
  record.enhance = {};
  record.enhance.brightness = stats.brightness;
  record.enhance.mean = stats.mean;
  record.enhance.sigma = stats.sigma;
  record.enhance.gamma = stats.gamma;
  record.enhance.clip = stats.level[0].clahe_clip;
  record.enhance.negative = stats.negative;

  record.pose = {};
  record.pose.timestamp_ns = frame.timestamp_ns;
  record.pose.frame_sequence = frame.sequence;
  record.pose.state = TrackingState::kNotInitialized;  // no SLAM core yet
  record.status = {};
  record.status.timestamp_ns = frame.timestamp_ns;
  record.status.state = record.pose.state;
  record.status.brightness = record.enhance.brightness;
  record.status.mean_intensity = static_cast<float>(record.enhance.mean);
  record.status.features = static_cast<int>(keypoints_.size());
  return {};
}

Status FramePipeline::reset_map() { return {}; }

FrameLogRow frame_log_row(const FrameRecord& r) {
  FrameLogRow row;
  row.timestamp_ns = static_cast<std::uint64_t>(r.status.timestamp_ns);  // camera clocks start at >= 0
  row.sequence = r.pose.frame_sequence;
  row.state = r.status.state;
  row.brightness = r.status.brightness;
  row.mean = r.enhance.mean;
  row.sigma = r.enhance.sigma;
  row.gamma = r.enhance.gamma;
  row.clip = r.enhance.clip;
  row.negative = r.enhance.negative;
  row.features = r.status.features;
  row.inliers = r.status.inliers;
  row.frame_time_ms = static_cast<double>(r.status.frame_time_ms);
  return row;
}

}  // namespace ale::app
