#include "core/slam/keyframe_policy.h"

#include <algorithm>

namespace ale::slam {

bool KeyframePolicy::needs_keyframe(int inliers, const map::MapStore& map, map::KeyframeId reference,
                                    double timestamp_s) const {
  if (frames_since_keyframe_ < static_cast<std::uint64_t>(std::min(params_.min_frames, params_.urgent_min_frames)))
    return false;
  const map::Keyframe* ref = map.keyframe(reference);
  if (!ref) return frames_since_keyframe_ >= static_cast<std::uint64_t>(params_.min_frames);
  // landmarks of the reference keyframe with enough observations to be trusted
  const int min_obs = map.stats().map_keyframes <= 2 ? 2 : 3;
  const map::LandmarkId* ids = map.keypoint_landmarks(reference);
  int ref_tracked = 0;
  for (int i = 0; i < ref->num_features; ++i) {
    const map::Landmark* lm = map.landmark(ids[i]);
    if (lm && lm->num_observations >= min_obs) ++ref_tracked;
  }
  if (inliers <= params_.min_inliers) return false;
  const bool revisit = params_.revisit_age_s > 0.0 && timestamp_s - ref->timestamp_s > params_.revisit_age_s;
  if (frames_since_keyframe_ >= static_cast<std::uint64_t>(params_.min_frames))
    return inliers < (revisit ? params_.revisit_ratio : params_.ref_ratio) * ref_tracked;
  return inliers < params_.urgent_ratio * ref_tracked;
}

}  // namespace ale::slam
