#include "app/daemon/frame_pipeline.h"

#include <cerrno>
#include <cstring>

namespace ale::app {

Status FramePipeline::configure(const DaemonConfig& config) {
  ALE_RETURN_IF_ERROR(extractor_.configure(config.features));
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
  ALE_RETURN_IF_ERROR(extractor_.extract(frame.image, keypoints_, descriptors_));
  const ale::features::ExtractionStats& stats = extractor_.stats();
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

FrameLog::~FrameLog() { (void)close(); }

Status FrameLog::open(const std::string& path) {
  path_ = path;
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) return io_error("frame log " + path + ": " + std::strerror(errno));
  std::fprintf(file_,
               "#timestamp_ns,sequence,state,brightness,mean,sigma,gamma,clip,negative,features,inliers,"
               "frame_time_ms\n");
  return {};
}

Status FrameLog::append(const FrameRecord& r) {
  if (file_ == nullptr) return {};
  const int n = std::fprintf(file_, "%lld,%llu,%s,%s,%.2f,%.2f,%.4f,%.3f,%d,%d,%d,%.3f\n",
                             static_cast<long long>(r.status.timestamp_ns),
                             static_cast<unsigned long long>(r.pose.frame_sequence), to_string(r.status.state),
                             to_string(r.status.brightness), r.enhance.mean, r.enhance.sigma, r.enhance.gamma,
                             r.enhance.clip, r.enhance.negative ? 1 : 0, r.status.features, r.status.inliers,
                             static_cast<double>(r.status.frame_time_ms));
  if (n < 0) return io_error("frame log " + path_ + ": write failed: " + std::strerror(errno));
  return {};
}

Status FrameLog::close() {
  if (file_ == nullptr) return {};
  const bool write_error = std::ferror(file_) != 0;
  const bool close_error = std::fclose(file_) != 0;
  file_ = nullptr;
  if (write_error || close_error) return io_error("frame log " + path_ + ": data lost on write or close");
  return {};
}

}  // namespace ale::app
