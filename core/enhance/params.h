// Every tunable of the lighting-adaptive front end, with its default, in one place. The app
// parses and validates its config file into these; the core only reads them. Why each default
// has its value (the measurement on ../shared/data behind it) is in docs/enhancement.md.
#pragma once

#include <string>

#include "core/base/config_table.h"
#include "core/enhance/clahe.h"

namespace ale::enhance {

// Brightness classes by frame mean (spec section 1), with hysteresis.
struct GradingParams {
  double t_very_low = 50.0;  // mean below: extremely dark
  double t_low = 70.0;       // mean below (and >= t_very_low): dark
  double t_high = 180.0;     // mean above: bright
  // Once a class is held, the mean must pass a threshold by this many grey levels to leave it.
  double hysteresis = 4.0;
};

// CDF-driven gamma (spec section 2): gamma = alpha / cdf(cdf_point), clamped to [gamma_min, 1].
struct GammaParams {
  int cdf_point = 128;
  double alpha = 0.5;
  double gamma_min = 0.4;
  // > 0: instead of the CDF rule, the gamma that maps the frame's mean to this grey,
  // log(target / 255) / log(mean / 255) (clamped as above): it grows continuously to 1 as the mean
  // approaches the target, so there is no jump at the extremely-dark/dark boundary when the
  // target sits there.
  double target_mean = 0.0;
  // > 0 (with target_mean): the lift stops where it would raise the frame's noise at its mean
  // above this sigma (grey levels). The noise is measured before the gamma (Immerkaer's estimate,
  // noise.h) and a gamma g that maps the mean m to the target T multiplies it there by its slope,
  // g * T / m; the target falls until that product is at most noise_max, down to m itself (no
  // gamma) when the frame's own noise already reaches it. A clean dark frame (the gain of a short
  // exposure, a scaled-down image) is lifted in full, a frame dark because of high analogue gain
  // hardly: there the lift scaled noise and signal alike and only lowered every FAST threshold in
  // contrast-to-noise terms (docs/features.md, issue 13).
  double noise_max = 0.0;
};

// Contrast-guided CLAHE per pyramid level (spec section 5):
//   tile edge T = int(tile_base + tile_scale * s), at least tile_min pixels;
//   clip C = clip_base + clip_contrast * sigma / median, clamped to [clip_min, clip_max].
// The grid is round(W / T) x round(H / T) tiles (at least 1x1).
struct LevelClaheParams {
  double tile_base = 16.0;
  double tile_scale = 64.0;
  int tile_min = 8;
  double clip_base = 1.5;
  double clip_contrast = 1.0;
  double clip_min = 1.0;
  double clip_max = 4.0;
};

struct EnhanceParams {
  GradingParams grading;
  GammaParams gamma;
  LevelClaheParams clahe;  // level 0 (s = 1) for the frame enhancement
};

// The named parameter sets. The frame enhancer (ale-enhance) uses the defaults above.
inline EnhanceParams frame_enhance_params() { return {}; }
// The feature front end's (ale-slamd, ale-features): the same except the per-level CLAHE's clip
// limit, fixed at 1 (clip_base 1, no contrast term): on the held-out relit frames
// (tests/host/core/features/lighting_ablation_test.cpp, docs/features.md) every contrast weight
// and every larger base matched worse.
// Its gamma follows the mean (target_mean = t_very_low + hysteresis = 54, so the lifted frame
// lands at the boundary to the dark class): the CDF rule gives 0.5 to every frame whose median
// is dark, which lifted noise that then outranked real corners (docs/features.md, issue 13).
inline EnhanceParams feature_level_params() {
  EnhanceParams p;
  p.clahe.clip_base = 1.0;
  p.clahe.clip_contrast = 0.0;
  p.gamma.target_mean = p.grading.t_very_low + p.grading.hysteresis;
  p.gamma.noise_max = 4.0;
  return p;
}

// The configuration tables (core/base/config_table.h): keys are the members' paths, e.g.
// "grading.t_low", "clahe.clip_base".
const ConfigTable& enhance_params_table();
const ConfigTable& level_clahe_table();  // LevelClaheParams, also the features' cell CLAHE

// kInvalidArgument naming the first field that is out of range (by the table) or inconsistent
// (policy.cpp).
Status validate(const EnhanceParams& p);
Status validate(const LevelClaheParams& p, const std::string& prefix);

}  // namespace ale::enhance
