#include "core/slam/match/fuse.h"

#include <algorithm>

#include "core/geometry/chi_square.h"

namespace ale::slam {

int search_for_fusion(const MatchContext& ctx, const FusionTarget& target, const map::Landmark& lm, float radius_px) {
  for (int i = 0; i < lm.num_observations; ++i) {
    if (lm.observations[static_cast<std::size_t>(i)].keyframe == target.keyframe) return kNoMatch;
  }
  const FrameFeatures& frame = target.frame;
  if (!frame.grid) return kNoMatch;
  const ScalePyramid& pyramid = ctx.pyramid;
  LandmarkView view;
  if (!landmark_in_view(lm, target.T_cw, target.centre_w, ctx.pinhole, frame.grid->bounds(), pyramid, &view))
    return kNoMatch;
  std::vector<int>& candidates = ctx.scratch.candidates;
  candidates.clear();
  frame.grid->query(view.u, view.v, radius_px * pyramid.scale[view.level], view.level - 1, view.level + 1, candidates);
  int best = ctx.params.th_low + 1, best_i = kNoMatch;
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int i : candidates) {
    const map::KeyframeFeature& f = frame.features[i];
    const double du = f.u - view.uv.x(), dv = f.v - view.uv.y();
    if ((du * du + dv * dv) * pyramid.inv_sigma2[std::clamp<int>(f.level, 0, pyramid.levels - 1)] > geometry::kChi2TwoDof95)
      continue;
    const int d = hamming(lm.descriptor, f.descriptor);
    if (d < best) {
      best = d;
      best_i = i;
    }
  }
  return best_i;
}

}  // namespace ale::slam
