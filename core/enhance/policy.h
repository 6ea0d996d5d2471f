// The per-frame enhancement policy (spec sections 1-5), in one place for every user: the daemon's
// frame path, ale-features, ale-enhance and the tests. It decides; the callers execute.
//
//   grade the frame mean (with hysteresis), then
//   extremely dark -> gamma, then CLAHE;  dark -> CLAHE;  normal -> unchanged (CLAHE if kAlways);
//   bright -> negative path: invert, grade the negative (extremely dark -> gamma), CLAHE, invert
//   back.
// The global part (negative, gamma) is one composed LUT before CLAHE (`pre`) and the inversion
// back after it (`post`). Where the CLAHE runs is the caller's: at level 0 in ale-enhance, on every
// pyramid level in the feature front end.
#pragma once

#include "core/base/frame_state.h"
#include "core/base/status.h"
#include "core/enhance/gamma.h"
#include "core/enhance/grading.h"
#include "core/enhance/params.h"

namespace ale::enhance {

// When the contrast-guided CLAHE runs (the frame enhancer always uses kNonNormalFrames).
enum class LevelEnhance { kNever, kNonNormalFrames, kAlways };

struct FramePlan {
  BrightnessClass brightness = BrightnessClass::kNormal;  // the class acted on (after hysteresis)
  bool clahe = false;            // the contrast-guided CLAHE follows the global LUT
  bool negative = false;         // the negative path: `pre` inverts, `post` inverts back
  bool needs_histogram = false;  // global_lut() or the CLAHE read the frame's histogram
  // Filled by global_lut():
  BrightnessClass negative_brightness = BrightnessClass::kNormal;  // grade of the negative
  double gamma = 1.0;      // 1: no gamma
  bool has_pre = false;    // apply `pre` to the frame before CLAHE
  Lut pre{};               // negative then gamma, composed
  bool has_post = false;   // apply `post` after CLAHE
  Lut post{};
};

class EnhancePolicy {
 public:
  EnhancePolicy() = default;
  // kInvalidArgument naming the bad field; the previous parameters stay in force then.
  Status configure(const EnhanceParams& params, LevelEnhance clahe_when);
  const EnhanceParams& params() const { return params_; }
  // New parameters from the next frame on, keeping the held class (configure() forgets it).
  // kInvalidArgument naming the bad field; the previous parameters stay in force then.
  Status set_params(const EnhanceParams& params);

  // Grades `mean` with hysteresis and plans the frame (global_lut() completes it).
  FramePlan grade(double mean);
  // The plan for a frame graded `cls`; the grading memory is not touched.
  FramePlan plan_for(BrightnessClass cls) const;
  // The global LUT of `plan` from the frame's statistics before any LUT (read only when
  // plan.needs_histogram) and its noise sigma before any LUT (0: unknown; the gamma's noise_max
  // needs it, params.h).
  void global_lut(const FrameStats& stats, FramePlan& plan, double noise_sigma = 0.0) const;
  // The class by the thresholds alone (no memory).
  BrightnessClass classify(double mean) const { return enhance::classify(mean, params_.grading); }
  // Forgets the held class (a new sequence starts).
  void reset() { grader_.reset(); }

 private:
  EnhanceParams params_;
  LevelEnhance clahe_when_ = LevelEnhance::kNonNormalFrames;
  BrightnessGrader grader_{params_.grading};
};

}  // namespace ale::enhance
