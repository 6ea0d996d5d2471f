#include "core/slam/match/bow.h"

#include <cstddef>

namespace ale::slam {

int search_by_bow(const MatchContext& ctx, const BowTarget& target, const map::MapStore& map, map::KeyframeId keyframe,
                  const place::FeatureVector& keyframe_fv) {
  const Span<const map::KeyframeFeature> kf_features = map.features_of(keyframe);
  const Span<const map::LandmarkId> kf_landmarks = map.keypoint_landmarks_of(keyframe);
  const FrameFeatures& frame = target.frame;
  if (kf_features.empty() || frame.count <= 0) return 0;
  std::vector<int>& matched = ctx.scratch.matched;  // frame keypoint -> keyframe keypoint
  matched.assign(static_cast<std::size_t>(frame.count), kNoMatch);

  const place::FeatureVector& fa = keyframe_fv;
  const place::FeatureVector& fb = target.fv;
  std::size_t i = 0, j = 0;
  while (i < fa.size() && j < fb.size()) {
    if (fa[i].node < fb[j].node) {
      ++i;
      continue;
    }
    if (fb[j].node < fa[i].node) {
      ++j;
      continue;
    }
    // the runs of one node in both
    const place::NodeId node = fa[i].node;
    std::size_t i_end = i, j_end = j;
    while (i_end < fa.size() && fa[i_end].node == node) ++i_end;
    while (j_end < fb.size() && fb[j_end].node == node) ++j_end;
    for (std::size_t a = i; a < i_end; ++a) {
      const int kp = static_cast<int>(fa[a].feature);
      if (kp >= kf_features.size()) continue;
      const map::LandmarkId lm = kf_landmarks[kp];
      if (!lm.valid() || map.landmark(lm) == nullptr) continue;
      Best2 best;
      for (std::size_t b = j; b < j_end; ++b) {
        const int f = static_cast<int>(fb[b].feature);
        if (f >= frame.count || target.landmarks[static_cast<std::size_t>(f)].valid() ||
            matched[static_cast<std::size_t>(f)] != kNoMatch)
          continue;
        best.offer(features::hamming_distance(kf_features[kp].descriptor, frame.features[f].descriptor), f, 0);
      }
      if (best.index == kNoMatch || best.dist > ctx.params.th_low) continue;
      if (static_cast<float>(best.dist) >= ctx.params.ratio_bow * static_cast<float>(best.dist2)) continue;
      matched[static_cast<std::size_t>(best.index)] = kp;
    }
    i = i_end;
    j = j_end;
  }

  if (ctx.params.rotation.enabled) {
    const FrameFeatures kf{kf_features.data(), kf_features.size(), nullptr};
    drop_inconsistent_rotations(frame, kf, ctx.params.rotation.bins, matched, ctx.scratch.bins);
  }
  int n = 0;
  for (int f = 0; f < frame.count; ++f) {
    const int kp = matched[static_cast<std::size_t>(f)];
    if (kp == kNoMatch) continue;
    target.landmarks[static_cast<std::size_t>(f)] = kf_landmarks[kp];
    ++n;
  }
  return n;
}

}  // namespace ale::slam
