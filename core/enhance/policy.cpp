#include "core/enhance/policy.h"

#include <cstdio>
#include <string>

namespace ale::enhance {
namespace {

constexpr ConfigField kGradingFields[] = {
    number<&GradingParams::t_very_low>("t_very_low", 0, 255, "frame mean below: extremely dark (gamma, then CLAHE)"),
    number<&GradingParams::t_low>("t_low", 0, 255, "frame mean below (>= t_very_low): dark (CLAHE)"),
    number<&GradingParams::t_high>("t_high", 0, 255, "frame mean above (>= t_low): bright (the negative path)"),
    number<&GradingParams::hysteresis>("hysteresis", 0, 64,
                                       "grey levels a mean must pass a threshold by to leave the held class"),
};
constexpr ConfigTable kGradingTable = table_of<GradingParams>(kGradingFields);

constexpr ConfigField kGammaFields[] = {
    number<&GammaParams::cdf_point>("cdf_point", 0, 255, "intensity t of gamma = alpha / cdf(t)"),
    number<&GammaParams::alpha>("alpha", 1e-3, 1, "alpha of the CDF-driven gamma"),
    number<&GammaParams::gamma_min>("gamma_min", 0.05, 1, "the strongest gamma allowed"),
    number<&GammaParams::target_mean>("target_mean", 0, 254, "> 0: gamma maps the frame mean to this grey (not the CDF)"),
    number<&GammaParams::noise_max>("noise_max", 0, 64, "> 0: the target falls until the frame's noise sigma times the gamma's slope at its mean is at most this"),
};
constexpr ConfigTable kGammaTable = table_of<GammaParams>(kGammaFields);

constexpr ConfigField kLevelClaheFields[] = {
    number<&LevelClaheParams::tile_base>("tile_base", 0, 4096, "tile edge T = int(tile_base + tile_scale * s)"),
    number<&LevelClaheParams::tile_scale>("tile_scale", 0, 4096, "s: 1 at level 0, 1/scale_factor^n at level n"),
    number<&LevelClaheParams::tile_min>("tile_min", 8, 4096, "smallest tile edge"),
    number<&LevelClaheParams::clip_base>("clip_base", 0, 256, "clip C = clip_base + clip_contrast * sigma / median"),
    number<&LevelClaheParams::clip_contrast>("clip_contrast", 0, 256, "weight of the contrast term of C"),
    number<&LevelClaheParams::clip_min>("clip_min", 0, 256, "C is clamped to [clip_min, clip_max]"),
    number<&LevelClaheParams::clip_max>("clip_max", 0, 256, "(>= clip_min)"),
};
constexpr ConfigTable kLevelClaheTable = table_of<LevelClaheParams>(kLevelClaheFields);

constexpr ConfigField kEnhanceFields[] = {
    nested<&EnhanceParams::grading>("grading", kGradingTable),
    nested<&EnhanceParams::gamma>("gamma", kGammaTable),
    nested<&EnhanceParams::clahe>("clahe", kLevelClaheTable),
};
constexpr ConfigTable kEnhanceTable = table_of<EnhanceParams>(kEnhanceFields);

// "<key>: <v> must be >= <other> (<lo>)", `other` a sibling of `key`.
Status at_least(double v, double lo, const std::string& key, const char* other) {
  if (v >= lo) return {};
  char text[96];
  std::snprintf(text, sizeof text, ": %g must be >= %s (%g)", v, other, lo);
  return invalid_argument(key + text);
}

}  // namespace

const ConfigTable& enhance_params_table() { return kEnhanceTable; }
const ConfigTable& level_clahe_table() { return kLevelClaheTable; }

Status validate(const LevelClaheParams& c, const std::string& prefix) {
  ALE_RETURN_IF_ERROR(check_ranges(kLevelClaheTable, &c, prefix));
  return at_least(c.clip_max, c.clip_min, prefix + "clip_max", "clip_min");
}

Status validate(const EnhanceParams& p) {
  ALE_RETURN_IF_ERROR(check_ranges(kEnhanceTable, &p));
  const GradingParams& g = p.grading;
  ALE_RETURN_IF_ERROR(at_least(g.t_low, g.t_very_low, "grading.t_low", "t_very_low"));
  ALE_RETURN_IF_ERROR(at_least(g.t_high, g.t_low, "grading.t_high", "t_low"));
  return validate(p.clahe, "clahe.");
}

Status EnhancePolicy::configure(const EnhanceParams& params, LevelEnhance clahe_when) {
  ALE_RETURN_IF_ERROR(validate(params));
  params_ = params;
  clahe_when_ = clahe_when;
  grader_ = BrightnessGrader(params.grading);
  return {};
}

Status EnhancePolicy::set_params(const EnhanceParams& params) {
  ALE_RETURN_IF_ERROR(validate(params));
  params_ = params;
  grader_.set_params(params.grading);
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

void EnhancePolicy::global_lut(const FrameStats& stats, FramePlan& plan, double noise_sigma) const {
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
  plan.gamma = cdf_gamma(*graded, params_.gamma, noise_sigma);  // inverting keeps the noise's size
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
