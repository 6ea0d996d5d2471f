#include "core/enhance/enhancer.h"

#include <string>

#include "core/enhance/gamma.h"

namespace ale::enhance {

Status FrameEnhancer::configure(const EnhanceParams& params) {
  return policy_.configure(params, LevelEnhance::kNonNormalFrames);
}

Status FrameEnhancer::process(GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(src, "enhance source"));
  compute_stats(src, stats_);
  FramePlan plan = policy_.grade(stats_.mean);
  return execute(plan, src, dst, report);
}

Status FrameEnhancer::enhance_as(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(src, "enhance source"));
  compute_stats(src, stats_);
  FramePlan plan = policy_.plan_for(cls);
  return execute(plan, src, dst, report);
}

// dst = post[CLAHE(pre[src])], where the CLAHE measures pre[src] through the statistics of src
// carried through `pre` (no second pass over the pixels).
Status FrameEnhancer::execute(FramePlan& plan, GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(dst, "enhance destination"));
  if (src.width != dst.width || src.height != dst.height)
    return invalid_argument("enhance: source " + std::to_string(src.width) + "x" + std::to_string(src.height) +
                            " and destination " + std::to_string(dst.width) + "x" + std::to_string(dst.height) +
                            " differ");
  report = EnhanceReport{};
  report.brightness = plan.brightness;
  report.raw_brightness = policy_.classify(stats_.mean);
  report.mean = stats_.mean;
  report.sigma = stats_.sigma;
  report.median = stats_.median;
  policy_.global_lut(stats_, plan);
  report.negative = plan.negative;
  report.negative_brightness = plan.negative_brightness;
  report.gamma = plan.gamma;

  GrayView clahe_src = src;
  const FrameStats* clahe_stats = &stats_;
  if (plan.has_pre) {
    ALE_RETURN_IF_ERROR(apply_lut(src, dst, plan.pre));
    remap_stats(stats_, plan.pre, work_stats_);
    clahe_stats = &work_stats_;
    clahe_src = dst;
  }
  if (plan.clahe) {
    LevelClaheSettings used;
    ALE_RETURN_IF_ERROR(
        contrast_guided_clahe(clahe_, policy_.params().clahe, 1.0, *clahe_stats, clahe_src, dst, &used));
    report.clip = used.clahe.clip_limit;
    report.tiles_x = used.clahe.tiles_x;
    report.tiles_y = used.clahe.tiles_y;
  } else if (!plan.has_pre && src.data != dst.data) {
    copy_pixels(src, dst);
  }
  if (plan.has_post) ALE_RETURN_IF_ERROR(apply_lut(dst, dst, plan.post));
  return {};
}

}  // namespace ale::enhance
