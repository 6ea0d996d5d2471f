#include "core/frontend/grade_stage.h"


#include "core/enhance/gamma.h"
#include "core/enhance/level_clahe.h"
#include "core/enhance/noise.h"

namespace ale::frontend {


Status GradeStage::configure(const features::ExtractorConfig& config) {
  ALE_RETURN_IF_ERROR(policy_.configure(config.enhance, config.level_enhance));
  config_ = config;
  return {};
}

Status GradeStage::set_enhance(const enhance::EnhanceParams& params) {
  ALE_RETURN_IF_ERROR(policy_.set_params(params));
  config_.enhance = params;
  return {};
}

Status GradeStage::run(features::FramePyramid& pyramid, enhance::ClaheContext& level_clahe, enhance::FramePlan& plan,
                       enhance::FrameStats& level0_stats, features::ExtractionStats& stats) {
  MutableGrayView l0 = pyramid.plain(0);
  // Grading needs the mean alone; the histogram only where a LUT or the level CLAHE follows.
  const enhance::Moments moments = enhance::compute_moments(l0);
  stats.mean = moments.mean;
  stats.sigma = moments.sigma;
  plan = policy_.grade(moments.mean);
  // A bright frame that still has contrast gains nothing from the negative path's remapping,
  // which only reorders which corners win (docs/features.md).
  if (plan.brightness == BrightnessClass::kBright && config_.bright_min_sigma > 0.0 &&
      moments.sigma >= config_.bright_min_sigma)
    plan = policy_.plan_for(BrightnessClass::kNormal);
  stats.brightness = plan.brightness;
  const bool denoise = (config_.denoise == 1 && plan.brightness == BrightnessClass::kExtremelyDark) ||
                       (config_.denoise == 2 && plan.brightness != BrightnessClass::kNormal);
  double raw_unfiltered = 0.0;
  if (denoise) {
    raw_unfiltered = enhance::estimate_noise_sigma(l0);
    enhance::binomial3_in_place(l0, denoise_bytes_, denoise_rows_);
    stats.denoised_estimate = enhance::estimate_noise_sigma(l0);
  }
  // With the level CLAHE, level 0's tile histograms give its histogram (one pass, not two); they
  // follow the pre-LUT below and its CLAHE reuses them.
  if (plan.needs_histogram && plan.clahe)
    ALE_RETURN_IF_ERROR(
        enhance::count_level(level_clahe, config_.enhance.clahe, 1.0 / pyramid.scale(0), l0, stats_scratch_));
  else if (plan.needs_histogram)
    enhance::compute_stats(l0, stats_scratch_);
  // The noise before any LUT: the gamma's lift is limited by it, and (when no gamma follows) it is
  // the noise gate's estimate too (frame_path.cpp).
  if (plan.brightness != BrightnessClass::kNormal &&
      (config_.noise_gate > 0.0 || (config_.enhance.gamma.noise_max > 0.0 && config_.enhance.gamma.target_mean > 0.0)))
    stats.raw_noise_sigma = denoise ? enhance::kBinomial3NoiseGain * raw_unfiltered : enhance::estimate_noise_sigma(l0);
  policy_.global_lut(stats_scratch_, plan, stats.raw_noise_sigma);
  stats.negative = plan.negative;
  stats.gamma = plan.gamma;
  if (plan.has_pre) ALE_RETURN_IF_ERROR(enhance::apply_lut(l0, l0, plan.pre));
  if (plan.has_pre && plan.clahe) ALE_RETURN_IF_ERROR(level_clahe.remap_counts(l0, plan.pre));
  if (plan.clahe) {
    if (plan.has_pre)
      enhance::remap_stats(stats_scratch_, plan.pre, level0_stats);
    else
      level0_stats = stats_scratch_;
  }
  return {};
}

Status GradeStage::run_global(features::FramePyramid& pyramid, features::ExtractionStats& stats) {
  MutableGrayView l0 = pyramid.plain(0);
  enhance::compute_stats(l0, stats_scratch_);
  stats.mean = stats_scratch_.mean;
  stats.sigma = stats_scratch_.sigma;
  if (config_.mode == features::ExtractorMode::kHe) {
    enhance::equalisation_lut(stats_scratch_, lut_);
  } else {
    enhance::GammaParams cdf_rule = config_.enhance.gamma;
    cdf_rule.target_mean = 0.0;  // the article's gamma: the CDF rule, whatever ALE uses
    stats.gamma = enhance::cdf_gamma(stats_scratch_, cdf_rule);
    if (stats.gamma >= 1.0) return {};  // a frame at or above mid-grey median is left alone
    enhance::gamma_lut(stats.gamma, lut_);
  }
  return enhance::apply_lut(l0, l0, lut_);
}

}  // namespace ale::frontend
