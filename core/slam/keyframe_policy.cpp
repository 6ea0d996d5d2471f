#include "core/slam/keyframe_policy.h"

#include "core/slam/local_map.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {

void KeyframePolicy::reserve(int keypoints) {
  landmarks_.reserve(static_cast<std::size_t>(keypoints));
  depths_.reserve(static_cast<std::size_t>(keypoints));
}

bool KeyframePolicy::revisit(const map::MapStore& map, map::KeyframeId reference, double timestamp_s,
                             const geometry::Vec3& centre_w) {
  const map::Keyframe& ref = *map.keyframe(reference);
  if (!(params_.revisit_age_s > 0.0) || timestamp_s - ref.timestamp_s <= params_.revisit_age_s) return false;
  const double depth = keyframe_median_depth(map, reference, landmarks_, depths_);
  // how far aside of the reference's line of sight (along it, the camera is on the same path)
  const geometry::Vec3 away = ref.T_cw * centre_w;  // in its camera
  return depth > 0.0 && std::hypot(away.x(), away.y()) <= params_.revisit_radius_depths * depth;
}

bool KeyframePolicy::needs_keyframe(int inliers, const map::MapStore& map, map::KeyframeId reference,
                                    double timestamp_s, const geometry::Vec3& centre_w) {
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
  if (frames_since_keyframe_ >= static_cast<std::uint64_t>(params_.min_frames)) {
    const bool known = revisit(map, reference, timestamp_s, centre_w);
    return inliers < (known ? params_.revisit_ratio : params_.ref_ratio) * ref_tracked;
  }
  return inliers < params_.urgent_ratio * ref_tracked;
}

}  // namespace ale::slam
