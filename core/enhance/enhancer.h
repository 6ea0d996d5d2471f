// The per-frame lighting-adaptive enhancement (spec sections 1-5): grade the frame, then
//   extremely dark -> gamma, then CLAHE;  dark -> CLAHE;  normal -> unchanged;
//   bright -> negative path: invert, grade the negative (extremely dark -> gamma + CLAHE,
//   otherwise CLAHE), invert back.
// CLAHE here is the contrast-guided one at level 0 (scale 1). Nothing is allocated per frame once
// a frame of the largest size has been processed.
#pragma once

#include "core/base/frame_state.h"
#include "core/base/image.h"
#include "core/enhance/clahe.h"
#include "core/enhance/gamma.h"
#include "core/enhance/grading.h"
#include "core/enhance/level_clahe.h"
#include "core/enhance/params.h"

namespace ale::enhance {

struct EnhanceReport {
  BrightnessClass brightness = BrightnessClass::kNormal;  // the class acted on (after hysteresis)
  BrightnessClass raw_brightness = BrightnessClass::kNormal;  // by the thresholds alone
  double mean = 0.0;
  double sigma = 0.0;
  int median = 0;
  double gamma = 1.0;  // 1: no gamma applied
  double clip = 0.0;   // CLAHE clip limit (OpenCV units); 0: no CLAHE
  int tiles_x = 0;
  int tiles_y = 0;
  bool negative = false;  // the negative path ran
  BrightnessClass negative_brightness = BrightnessClass::kNormal;  // grade of the negative
};

class FrameEnhancer {
 public:
  FrameEnhancer() = default;
  // kInvalidArgument naming the bad field; the previous parameters stay in force then.
  Status configure(const EnhanceParams& params);
  const EnhanceParams& params() const { return params_; }

  // Grades with hysteresis and enhances into dst (same size; may be src).
  Status process(GrayView src, MutableGrayView dst, EnhanceReport& report);
  // Enhances as if the frame were graded `cls`; the grading memory is not touched.
  Status enhance_as(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report);
  // Forgets the held class (a new sequence starts).
  void reset() { grader_.reset(); }

 private:
  Status treat(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report);
  Status gamma_then_clahe(const FrameStats& stats, const Lut* pre, GrayView src, MutableGrayView dst,
                          bool with_gamma, EnhanceReport& report);

  EnhanceParams params_;
  BrightnessGrader grader_{params_.grading};
  ClaheContext clahe_;
  FrameStats stats_;
  FrameStats work_stats_;
  Lut lut_{};
};

}  // namespace ale::enhance
