#include "core/slam/slam_pipeline.h"

#include <string>
#include <utility>

namespace ale::slam {

Status SlamPipeline::TrackStage::run(const frontend::FrameOutput& frame) {
  features_.clear();
  for (std::size_t i = 0; i < frame.keypoints.size(); ++i) {
    const features::Keypoint& kp = frame.keypoints[i];
    map::KeyframeFeature f;
    f.u = kp.x;
    f.v = kp.y;
    f.level = static_cast<std::int16_t>(kp.level);
    f.angle_deg = kp.angle_deg;
    f.descriptor = frame.descriptors[i];
    features_.push_back(f);
  }
  return system_.track_frame(static_cast<double>(frame.id.timestamp_ns) * 1e-9, frame.id.sequence, features_);
}

SlamPipeline::SlamPipeline(std::unique_ptr<SlamSystem> system, int width, int height)
    : system_(std::move(system)),
      adjust_(*system_, kAdjustStage, &SlamSystem::finish_mapping),
      track_(*system_),
      map_(*system_, kMapStage, &SlamSystem::map_frame),
      width_(width),
      height_(height) {}

Result<std::unique_ptr<SlamPipeline>> SlamPipeline::create(const features::ExtractorConfig& features,
                                                           const SlamParams& slam, const geometry::Camera& camera,
                                                           std::shared_ptr<const place::Vocabulary> vocabulary) {
  Result<std::unique_ptr<SlamSystem>> system = SlamSystem::create(
      slam, camera, features.num_levels, static_cast<float>(features.scale_factor), std::move(vocabulary));
  if (!system.ok()) return system.status();
  const geometry::CameraIntrinsics& k = camera.intrinsics();
  std::unique_ptr<SlamPipeline> p(new SlamPipeline(std::move(*system), k.width, k.height));
  ALE_RETURN_IF_ERROR(p->path_.configure(features));
  ALE_RETURN_IF_ERROR(p->path_.append_stage(p->adjust_));
  ALE_RETURN_IF_ERROR(p->path_.append_stage(p->track_));
  ALE_RETURN_IF_ERROR(p->path_.append_stage(p->map_));
  const std::size_t n = static_cast<std::size_t>(features.num_features);
  p->keypoints_.reserve(n);
  p->descriptors_.reserve(n);
  return p;
}

Status SlamPipeline::process(const frontend::FrameId& id, GrayView image) {
  if (image.width != width_ || image.height != height_) {
    return frame_rejected("frame " + std::to_string(id.sequence) + " is " + std::to_string(image.width) + "x" +
                            std::to_string(image.height) + ", the camera's calibration is for " +
                            std::to_string(width_) + "x" + std::to_string(height_));
  }
  return path_.extract(id, image, keypoints_, descriptors_);
}

void SlamPipeline::reset() {
  system_->reset();
  path_.reset();
}

}  // namespace ale::slam
