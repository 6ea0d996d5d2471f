#include "core/frontend/level_enhance_stage.h"

#include "core/enhance/gamma.h"
#include "core/enhance/level_clahe.h"

namespace ale::frontend {

Status LevelEnhanceStage::run(features::FramePyramid& pyramid, const enhance::FramePlan& plan,
                              const enhance::FrameStats& level0_stats, features::ExtractionStats& stats) {
  const bool ale = config_.mode == features::ExtractorMode::kAle;
  const bool level_clahe = ale && plan.clahe;
  const bool has_post = ale && plan.has_post;
  for (int l = 0; l < pyramid.levels(); ++l) {
    MutableGrayView v = pyramid.plain(l);
    features::LevelStats& ls = stats.level[static_cast<std::size_t>(l)];
    if (config_.mode == features::ExtractorMode::kClahe) {
      ALE_RETURN_IF_ERROR(enhance::clahe(clahe_, config_.clahe_everywhere, v, v));
      ls.clahe_clip = config_.clahe_everywhere.clip_limit;
    } else if (level_clahe) {
      // Into its own buffer: the level before its CLAHE stays in the pyramid, because tile-local
      // mappings change BRIEF comparisons and FAST scores, the global pre-LUT (monotonic once
      // inverted back) does not.
      MutableGrayView enhanced = pyramid.enhanced(l);
      enhance::LevelClaheSettings used;
      const double scale = 1.0 / pyramid.scale(l);
      if (l == 0)  // its statistics are known from grading (remapped through the pre-LUT)
        ALE_RETURN_IF_ERROR(enhance::contrast_guided_clahe(clahe_, config_.enhance.clahe, scale, level0_stats, v,
                                                           enhanced, &used));
      else
        ALE_RETURN_IF_ERROR(enhance::contrast_guided_clahe(clahe_, config_.enhance.clahe, scale, v, enhanced, &used));
      ls.clahe_clip = used.clahe.clip_limit;
      if (has_post) ALE_RETURN_IF_ERROR(enhance::apply_lut(enhanced, enhanced, plan.post));
      pyramid.set_enhanced(l);
    }
    if (has_post) ALE_RETURN_IF_ERROR(enhance::apply_lut(v, v, plan.post));
  }
  return {};
}

}  // namespace ale::frontend
