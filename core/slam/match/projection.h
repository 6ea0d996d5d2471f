// Search by projection (ORB-SLAM's SearchByProjection): landmarks projected into a frame at a
// predicted pose and matched to the keypoints near where they land. Two kinds: a list of
// landmarks (the local map, a reference keyframe's), and the landmarks matched in the last frame
// (the constant-velocity step, which also knows each landmark's level there).
#pragma once

#include <utility>
#include <vector>

#include "core/geometry/lie.h"
#include "core/map/map_store.h"
#include "core/slam/match/base.h"

namespace ale::slam {

// The frame a projection search matches into: its features, the pose it is searched at, and
// the landmark of each keypoint (frame.count entries, invalid where none), which receives the
// new matches. Keypoints that already have a landmark are not searched.
struct ProjectionTarget {
  FrameFeatures frame;
  geometry::SE3 T_cw;
  std::vector<map::LandmarkId>& landmarks;
};

// Matches each candidate landmark that is in view (landmark_in_view, base.h) and not already
// matched in the target to the best free keypoint within radius_px * scale(predicted level) of
// its projection (radius_px at views within 3.6 deg of the landmark's mean viewing direction,
// 1.6 times it at more oblique ones: ORB-SLAM's 2.5 and 4), on the predicted level or the one
// below, Hamming <= th_high, ratio ratio_projection when the two best are on one level.
// in_view, when given, receives every candidate that passed the view test (matched or not: the
// landmarks' "visible" counters). Returns the number of new matches.
int search_by_projection(const MatchContext& ctx, const ProjectionTarget& target, const map::MapStore& map,
                         const std::vector<map::LandmarkId>& candidates, float radius_px,
                         std::vector<map::LandmarkId>* in_view = nullptr);

// Projects the landmarks matched in the last frame (last_landmarks, last.count entries) into
// the target and matches each to a free keypoint within radius_px * scale(its level in the last
// frame), on that level +-1, Hamming <= th_high, then the rotation check (when
// rotation.enabled) between the two frames. Returns the number of matches.
int search_last_frame(const MatchContext& ctx, const ProjectionTarget& target, const FrameFeatures& last,
                      const std::vector<map::LandmarkId>& last_landmarks, const map::MapStore& map, float radius_px);

// The last frame's keypoints as bearings (rays without depth) for a turn on the spot, where the
// map has no landmarks in the new view yet: each keypoint of `last` (posed at last_T_cw) that
// has no landmark there is rotated into the target by the two poses' rotations alone (where a
// far point lands: the camera's step matters little against the rotation) and matched to the
// best free target keypoint within radius_px * scale(its level), on that level +-1, Hamming <=
// th_low, ratio ratio_projection when the two best are on one level; then the rotation check.
// pairs receives (last keypoint, target keypoint). Returns the number of pairs.
int search_bearings(const MatchContext& ctx, const ProjectionTarget& target, const FrameFeatures& last,
                    const std::vector<map::LandmarkId>& last_landmarks, const geometry::SE3& last_T_cw, float radius_px,
                    std::vector<std::pair<int, int>>& pairs);

}  // namespace ale::slam
