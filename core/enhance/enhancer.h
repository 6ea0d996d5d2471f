// The lighting-adaptive enhancement of whole frames (ale-enhance, tests): the policy of
// core/enhance/policy.h with its CLAHE at level 0 (scale 1). Nothing is allocated per frame once
// a frame of the largest size has been processed.
#pragma once

#include "core/base/frame_state.h"
#include "core/base/image.h"
#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/level_clahe.h"
#include "core/enhance/params.h"
#include "core/enhance/policy.h"

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
  const EnhanceParams& params() const { return policy_.params(); }

  // Grades with hysteresis and enhances into dst (same size; may be src).
  Status process(GrayView src, MutableGrayView dst, EnhanceReport& report);
  // Enhances as if the frame were graded `cls`; the grading memory is not touched.
  Status enhance_as(BrightnessClass cls, GrayView src, MutableGrayView dst, EnhanceReport& report);
  // Forgets the held class (a new sequence starts).
  void reset() { policy_.reset(); }

 private:
  Status execute(FramePlan& plan, GrayView src, MutableGrayView dst, EnhanceReport& report);

  EnhancePolicy policy_;
  ClaheContext clahe_;
  FrameStats stats_;
  FrameStats work_stats_;
};

}  // namespace ale::enhance
