#include "core/enhance/enhancer.h"

#include <cmath>
#include <string>

namespace ale::enhance {
namespace {

Status check_range(double v, double lo, double hi, const char* name) {
  if (!(v >= lo && v <= hi))
    return invalid_argument(std::string(name) + " = " + std::to_string(v) + " is outside [" + std::to_string(lo) +
                            ", " + std::to_string(hi) + "]");
  return {};
}

Lut make_negative_lut() {
  Lut lut{};
  for (std::size_t v = 0; v < 256; ++v) lut[v] = static_cast<std::uint8_t>(255 - v);
  return lut;
}

const Lut kNegative = make_negative_lut();

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

Status FrameEnhancer::configure(const EnhanceParams& params) {
  ALE_RETURN_IF_ERROR(validate(params));
  params_ = params;
  grader_ = BrightnessGrader(params.grading);
  return {};
}

Status FrameEnhancer::process(GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(src, "enhance source"));
  compute_stats(src, stats_);
  const BrightnessClass cls = grader_.update(stats_.mean);
  return treat(cls, src, dst, report);
}

Status FrameEnhancer::enhance_as(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(src, "enhance source"));
  compute_stats(src, stats_);
  return treat(cls, src, dst, report);
}

Status FrameEnhancer::treat(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report) {
  ALE_RETURN_IF_ERROR(check_view(dst, "enhance destination"));
  if (src.width != dst.width || src.height != dst.height)
    return invalid_argument("enhance: source " + std::to_string(src.width) + "x" + std::to_string(src.height) +
                            " and destination " + std::to_string(dst.width) + "x" + std::to_string(dst.height) +
                            " differ");
  report = EnhanceReport{};
  report.brightness = cls;
  report.raw_brightness = classify(stats_.mean, params_.grading);
  report.mean = stats_.mean;
  report.sigma = stats_.sigma;
  report.median = stats_.median;

  switch (cls) {
    case BrightnessClass::kNormal:
      if (src.data != dst.data) copy_pixels(src, dst);
      return {};
    case BrightnessClass::kDark:
      return gamma_then_clahe(stats_, nullptr, src, dst, false, report);
    case BrightnessClass::kExtremelyDark:
      return gamma_then_clahe(stats_, nullptr, src, dst, true, report);
    case BrightnessClass::kBright: {
      report.negative = true;
      remap_stats(stats_, kNegative, work_stats_);
      report.negative_brightness = classify(work_stats_.mean, params_.grading);
      // A negative that is dark or even normal still gets CLAHE: the frame itself was too bright.
      const FrameStats negative_stats = work_stats_;
      ALE_RETURN_IF_ERROR(gamma_then_clahe(negative_stats, &kNegative, src, dst,
                                           report.negative_brightness == BrightnessClass::kExtremelyDark, report));
      return apply_lut(dst, dst, kNegative);
    }
  }
  return internal_error("enhance: unknown brightness class");
}

// dst = CLAHE(gamma(pre[src])) where `stats` are those of pre[src]; pre (nullptr: identity) and
// gamma are composed into a single LUT pass.
Status FrameEnhancer::gamma_then_clahe(const FrameStats& stats, const Lut* pre, GrayView src, MutableGrayView dst,
                                       bool with_gamma, EnhanceReport& report) {
  const bool has_pre = pre != nullptr;
  GrayView clahe_src = src;
  const FrameStats* clahe_stats = &stats;
  if (with_gamma || has_pre) {
    Lut g{};
    report.gamma = with_gamma ? cdf_gamma(stats, params_.gamma) : 1.0;
    gamma_lut(report.gamma, g);
    for (std::size_t v = 0; v < 256; ++v) lut_[v] = g[has_pre ? (*pre)[v] : v];
    ALE_RETURN_IF_ERROR(apply_lut(src, dst, lut_));
    if (with_gamma) {
      remap_stats(stats, g, work_stats_);
      clahe_stats = &work_stats_;
    }
    clahe_src = dst;
  }
  LevelClaheSettings used;
  ALE_RETURN_IF_ERROR(contrast_guided_clahe(clahe_, params_.clahe, 1.0, *clahe_stats, clahe_src, dst, &used));
  report.clip = used.clahe.clip_limit;
  report.tiles_x = used.clahe.tiles_x;
  report.tiles_y = used.clahe.tiles_y;
  return {};
}

}  // namespace ale::enhance
