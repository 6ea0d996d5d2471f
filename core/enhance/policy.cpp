#include "core/enhance/policy.h"

#include <string>

namespace ale::enhance {
namespace {

Status check_range(double v, double lo, double hi, const char* name) {
  if (!(v >= lo && v <= hi))
    return invalid_argument(std::string(name) + " = " + std::to_string(v) + " is outside [" + std::to_string(lo) +
                            ", " + std::to_string(hi) + "]");
  return {};
}

}  // namespace

Status validate(const EnhanceParams& p) {
  const GradingParams& g = p.grading;
  ALE_RETURN_IF_ERROR(check_range(g.t_very_low, 0, 255, "grading.t_very_low"));
  ALE_RETURN_IF_ERROR(check_range(g.t_low, g.t_very_low, 255, "grading.t_low (>= t_very_low)"));
  ALE_RETURN_IF_ERROR(check_range(g.t_high, g.t_low, 255, "grading.t_high (>= t_low)"));
  ALE_RETURN_IF_ERROR(check_range(g.hysteresis, 0, 64, "grading.hysteresis"));
  ALE_RETURN_IF_ERROR(check_range(p.gamma.cdf_point, 0, 255, "gamma.cdf_point"));
  ALE_RETURN_IF_ERROR(check_range(p.gamma.alpha, 1e-3, 1, "gamma.alpha"));
  ALE_RETURN_IF_ERROR(check_range(p.gamma.gamma_min, 0.05, 1, "gamma.gamma_min"));
  const LevelClaheParams& c = p.clahe;
  ALE_RETURN_IF_ERROR(check_range(c.tile_base, 0, 4096, "clahe.tile_base"));
  ALE_RETURN_IF_ERROR(check_range(c.tile_scale, 0, 4096, "clahe.tile_scale"));
  ALE_RETURN_IF_ERROR(check_range(c.tile_min, 8, 4096, "clahe.tile_min"));
  ALE_RETURN_IF_ERROR(check_range(c.clip_min, 0, 256, "clahe.clip_min"));
  ALE_RETURN_IF_ERROR(check_range(c.clip_max, c.clip_min, 256, "clahe.clip_max (>= clip_min)"));
  ALE_RETURN_IF_ERROR(check_range(c.clip_base, 0, 256, "clahe.clip_base"));
  ALE_RETURN_IF_ERROR(check_range(c.clip_contrast, 0, 256, "clahe.clip_contrast"));
  return {};
}

Status EnhancePolicy::configure(const EnhanceParams& params, LevelEnhance clahe_when) {
  ALE_RETURN_IF_ERROR(validate(params));
  params_ = params;
  clahe_when_ = clahe_when;
  grader_ = BrightnessGrader(params.grading);
  return {};
}

FramePlan EnhancePolicy::grade(double mean) { return plan_for(grader_.update(mean)); }

FramePlan EnhancePolicy::plan_for(BrightnessClass cls) const {
  FramePlan plan;
  plan.brightness = cls;
  plan.clahe = clahe_when_ == LevelEnhance::kAlways ||
               (clahe_when_ == LevelEnhance::kNonNormalFrames && cls != BrightnessClass::kNormal);
  plan.negative = cls == BrightnessClass::kBright;
  plan.needs_histogram = plan.clahe || cls == BrightnessClass::kBright || cls == BrightnessClass::kExtremelyDark;
  return plan;
}

void EnhancePolicy::global_lut(const FrameStats& stats, FramePlan& plan) const {
  // Only the LUTs in use are written (`pre` is not an identity table unless has_pre): this runs
  // on every frame.
  plan.has_pre = plan.has_post = false;
  plan.gamma = 1.0;
  plan.negative_brightness = BrightnessClass::kNormal;
  const FrameStats* graded = &stats;
  FrameStats negative;  // the negative's statistics, derived without touching pixels
  if (plan.negative) {
    // A negative that is dark or even normal still gets CLAHE: the frame itself was too bright.
    for (std::size_t v = 0; v < 256; ++v) plan.pre[v] = plan.post[v] = static_cast<std::uint8_t>(255 - v);
    plan.has_pre = plan.has_post = true;
    remap_stats(stats, plan.pre, negative);
    plan.negative_brightness = classify(negative.mean);
    graded = &negative;
  }
  const bool extremely_dark = plan.brightness == BrightnessClass::kExtremelyDark ||
                              (plan.negative && plan.negative_brightness == BrightnessClass::kExtremelyDark);
  if (!extremely_dark) return;
  plan.gamma = cdf_gamma(*graded, params_.gamma);
  if (plan.negative) {
    Lut g{};
    gamma_lut(plan.gamma, g);
    for (auto& v : plan.pre) v = g[v];  // gamma after the inversion
  } else {
    gamma_lut(plan.gamma, plan.pre);
  }
  plan.has_pre = true;
}

}  // namespace ale::enhance
