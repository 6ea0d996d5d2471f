// The grade-and-global-LUT stage of the frame path (ALE mode): the frame's moments, its class from
// the enhancement policy (core/enhance/policy.h, with hysteresis), the histogram where the plan
// needs one, and the plan's global LUT (negative and/or gamma) applied to level 0 in place before
// the pyramid is built from it. Only executes the policy's decisions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/policy.h"
#include "core/features/frame_pyramid.h"
#include "core/features/orb.h"

namespace ale::frontend {

class GradeStage {
 public:
  // `config` is valid.
  Status configure(const features::ExtractorConfig& config);
  // Fills plan, stats' grading figures and, when plan.clahe, level0_stats (of level 0 after the
  // LUT) with level 0's tile histograms counted in `level_clahe` for the level stage to reuse.
  Status run(features::FramePyramid& pyramid, enhance::ClaheContext& level_clahe, enhance::FramePlan& plan,
             enhance::FrameStats& level0_stats, features::ExtractionStats& stats);
  // kHe / kGamma: the mode's global LUT on level 0 (every frame), from its histogram.
  Status run_global(features::FramePyramid& pyramid, features::ExtractionStats& stats);
  // The enhancement parameters (grading thresholds, gamma, level CLAHE) from the next frame on;
  // the held brightness class stays. kInvalidArgument naming the bad field, nothing changed then.
  Status set_enhance(const enhance::EnhanceParams& params);
  void reset() { policy_.reset(); }

 private:
  features::ExtractorConfig config_;
  enhance::EnhancePolicy policy_;
  enhance::FrameStats stats_scratch_;
  enhance::Lut lut_{};
  std::vector<std::uint16_t> denoise_rows_;
  std::vector<std::uint8_t> denoise_bytes_;
};

}  // namespace ale::frontend
