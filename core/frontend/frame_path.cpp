#include "core/frontend/frame_path.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/stage_probe.h"
#include "core/enhance/noise.h"

namespace ale::frontend {

using features::ExtractorMode;
using features::kEdgePx;

Status FramePath::configure(const features::ExtractorConfig& config) {
  ALE_RETURN_IF_ERROR(features::validate(config));
  ALE_RETURN_IF_ERROR(grade_.configure(config));
  config_ = config;
  const int levels = config_.num_levels;
  pyramid_.configure(levels, config_.scale_factor, config_.mode == ExtractorMode::kAle);
  level_enhance_.configure(config_);
  detector_.configure(config_);
  // ORB-SLAM's split: a geometric series over the levels, the last level takes the rest.
  const double factor = 1.0 / config_.scale_factor;
  double per_level = config_.num_features * (1.0 - factor) / (1.0 - std::pow(factor, levels));
  int sum = 0;
  for (int l = 0; l < levels - 1; ++l) {
    budgets_[static_cast<std::size_t>(l)] = static_cast<int>(std::lround(per_level));
    sum += budgets_[static_cast<std::size_t>(l)];
    per_level *= factor;
  }
  budgets_[static_cast<std::size_t>(levels - 1)] = std::max(config_.num_features - sum, 0);
  configured_ = true;
  return {};
}

Status FramePath::set_enhance(const enhance::EnhanceParams& params) {
  if (!configured_) return invalid_argument("features: set_enhance() before configure()");
  if (Status s = enhance::validate(params); !s.ok()) return invalid_argument("enhance." + s.message());
  ALE_RETURN_IF_ERROR(grade_.set_enhance(params));
  config_.enhance = params;
  level_enhance_.configure(config_);
  return {};
}

Status FramePath::append_stage(FrameStage& stage) {
  if (kFrontEndStages.size() + appended_.size() >= kMaxFrameStages)
    return invalid_argument(std::string("frame path: no room for stage '") + stage.name() + "' (" +
                            std::to_string(kMaxFrameStages) + " stages at most)");
  appended_.push_back(&stage);
  return {};
}

Status FramePath::extract(const FrameId& id, GrayView image, std::vector<features::Keypoint>& keypoints,
                          std::vector<features::Descriptor>& descriptors) {
  keypoints.clear();
  descriptors.clear();
  timings_.clear();
  if (!configured_) return invalid_argument("features: extract() before configure()");
  ALE_RETURN_IF_ERROR(check_view(image, "features image"));
  if (image.width < 2 * kEdgePx + 1 || image.height < 2 * kEdgePx + 1 || image.width > 32767 ||
      image.height > 32767)
    return invalid_argument("features: image " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                            " must be " + std::to_string(2 * kEdgePx + 1) + "..32767 pixels in each direction");
  StageProbeRun probes(kFrontEndStages.size() + appended_.size());  // for the instruction counter
  std::int64_t t = clock_();
  const auto mark = [&](const char* stage) {
    const std::int64_t now = clock_();
    timings_.add(stage, now - t);
    t = now;
    probes.next();
  };
  const int levels = config_.num_levels;
  stats_ = features::ExtractionStats{};
  stats_.levels = levels;

  pyramid_.plan(image.width, image.height);
  detector_.plan(pyramid_);
  describer_.plan(pyramid_);
  pyramid_.load(image);
  if (config_.mode == ExtractorMode::kAle)
    ALE_RETURN_IF_ERROR(grade_.run(pyramid_, level_enhance_.context(), plan_, level0_stats_, stats_));
  else if (config_.mode == ExtractorMode::kHe || config_.mode == ExtractorMode::kGamma)
    ALE_RETURN_IF_ERROR(grade_.run_global(pyramid_, stats_));
  const bool enhanced_frame = config_.mode == ExtractorMode::kAle && plan_.brightness != BrightnessClass::kNormal;
  detector_.set_frame_retry(config_.mode == ExtractorMode::kAle && config_.cell_retry &&
                            (config_.retry_normal_frames || enhanced_frame));
  if (enhanced_frame && config_.noise_gate > 0.0) {
    // The gamma changes the noise (a bright frame's inversion does not): measured again after it.
    if (plan_.gamma == 1.0)
      stats_.noise_sigma = stats_.raw_noise_sigma;
    else if (stats_.denoised_estimate > 0.0)  // the Laplacian estimate is biased on a filtered image: its ratio only
      stats_.noise_sigma = stats_.raw_noise_sigma * enhance::estimate_noise_sigma(pyramid_.plain(0)) / stats_.denoised_estimate;
    else
      stats_.noise_sigma = enhance::estimate_noise_sigma(pyramid_.plain(0));
    stats_.noise_gate_score = static_cast<int>(std::ceil(config_.noise_gate * stats_.noise_sigma));
  }
  detector_.set_frame_gate(stats_.noise_gate_score);
  mark(kFrontEndStages[0]);

  pyramid_.build();
  mark(kFrontEndStages[1]);

  ALE_RETURN_IF_ERROR(level_enhance_.run(pyramid_, plan_, level0_stats_, stats_));
  mark(kFrontEndStages[2]);

  for (int l = 0; l < levels; ++l) {
    const std::size_t li = static_cast<std::size_t>(l);
    features::LevelStats& ls = stats_.level[li];
    const GrayView img = pyramid_.image(l);
    ls.width = img.width;
    ls.height = img.height;
    ls.budget = budgets_[li];
    ALE_RETURN_IF_ERROR(detector_.detect_level(pyramid_, l, candidates_[li], ls));
  }
  mark(kFrontEndStages[3]);

  for (int l = 0; l < levels; ++l) {
    const std::size_t li = static_cast<std::size_t>(l);
    const GrayView img = pyramid_.image(l);
    kept_[li].clear();
    distribute_quadtree(candidates_[li], {kEdgePx, kEdgePx, img.width - 2 * kEdgePx, img.height - 2 * kEdgePx},
                        budgets_[li], quadtree_, kept_[li]);
    stats_.level[li].kept = static_cast<int>(kept_[li].size());
  }
  mark(kFrontEndStages[4]);

  for (int l = 0; l < levels; ++l)
    describer_.describe_level(pyramid_, l, kept_[static_cast<std::size_t>(l)], keypoints, descriptors);
  stats_.total = static_cast<int>(keypoints.size());
  mark(kFrontEndStages[5]);

  const FrameOutput output{id, image, keypoints, descriptors, stats_};
  for (FrameStage* stage : appended_) {
    ALE_RETURN_IF_ERROR(stage->run(output));
    mark(stage->name());
  }
  return {};
}

}  // namespace ale::frontend
