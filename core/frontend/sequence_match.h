// Frame-to-frame matching over a sequence (the light-level report of ale-features and its test):
// every frame through one frame path in order, so that grading keeps its memory as in a replay,
// then features::match_pair (core/features/pair_match.h) on the pairs (i, i + gap).
#pragma once

#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/features/orb.h"
#include "core/features/pair_match.h"

namespace ale::frontend {

struct GapFigures {
  int gap = 0;
  std::vector<features::PairMatchFigures> pairs;  // pair (i, i + gap) at index i
  double mean_keypoints() const;  // of both frames
  double mean_matches() const;
  double mean_inliers() const;
};

// kInvalidArgument for a bad configuration, a gap < 1 or frames of different sizes; pairs for
// gaps not shorter than the sequence are simply absent.
Result<std::vector<GapFigures>> match_sequence(const std::vector<GrayImage>& frames,
                                               const features::ExtractorConfig& config, const std::vector<int>& gaps,
                                               const features::PairMatchParams& params);

}  // namespace ale::frontend
