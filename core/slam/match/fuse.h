// Search for fusion (ORB-SLAM's Fuse): a landmark projected into a keyframe that does not
// observe it, to find the keypoint it duplicates there. The local mapper then merges the two
// landmarks, or adds the observation when the keypoint has none.
#pragma once

#include "core/geometry/lie.h"
#include "core/map/map_store.h"
#include "core/slam/match/base.h"

namespace ale::slam {

// The keyframe landmarks are fused into: its id, features and grid, and pose.
struct FusionTarget {
  map::KeyframeId keyframe;
  FrameFeatures frame;
  geometry::SE3 T_cw;
  geometry::Vec3 centre_w;  // T_cw.inverse().translation()
};

// The keypoint of the target that `lm` duplicates, or kNoMatch: none when the target observes lm
// already or lm is not in view (landmark_in_view, base.h); else the nearest in descriptor,
// Hamming <= th_low, ties to the lower index, among the keypoints within radius_px *
// scale(predicted level) of its projection, on the predicted level +-1, whose squared distance
// to the projection is within the 2-dof 95 % gate (geometry::kChi2TwoDof95) of their level's
// sigma^2.
int search_for_fusion(const MatchContext& ctx, const FusionTarget& target, const map::Landmark& lm, float radius_px);

}  // namespace ale::slam
