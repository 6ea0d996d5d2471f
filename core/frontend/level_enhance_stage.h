// The per-level enhancement stage of the frame path. ALE: where the policy's plan says so, the
// contrast-guided CLAHE of each level with its own scale (spec section 5) into the pyramid's
// enhanced levels, the plain levels kept for ranking and description; CLAHE-everywhere mode: the
// fixed CLAHE on every level in place. Then the plan's inversion back (the negative path) on both.
// Owns the CLAHE context, which the grade stage also uses to count level 0 (one pass gives its
// histogram and its tile histograms).
#pragma once

#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/policy.h"
#include "core/features/frame_pyramid.h"
#include "core/features/orb.h"

namespace ale::frontend {

class LevelEnhanceStage {
 public:
  void configure(const features::ExtractorConfig& config) { config_ = config; }
  // level0_stats: of level 0 after the global LUT, its tile histograms counted in context()
  // (ALE with plan.clahe only).
  Status run(features::FramePyramid& pyramid, const enhance::FramePlan& plan, const enhance::FrameStats& level0_stats,
             features::ExtractionStats& stats);
  enhance::ClaheContext& context() { return clahe_; }

 private:
  features::ExtractorConfig config_;
  enhance::ClaheContext clahe_;
};

}  // namespace ale::frontend
