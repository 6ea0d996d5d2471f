// Search for triangulation (ORB-SLAM's SearchForTriangulation without bag-of-words): keypoints
// of two keyframes that have no landmark yet, paired along the epipolar lines of the keyframes'
// poses, for the local mapper to triangulate.
#pragma once

#include <utility>
#include <vector>

#include "core/geometry/lie.h"
#include "core/map/map_store.h"
#include "core/slam/match/base.h"

namespace ale::slam {

// A keyframe as the search sees it: its features and grid, its pose, and the landmark of each
// keypoint (frame.count entries; nullptr: none has one).
struct PosedKeyframe {
  FrameFeatures frame;
  geometry::SE3 T_cw;
  const map::LandmarkId* landmarks = nullptr;
};

// Pairs of keypoints of kf1 and kf2 that have no landmark yet and satisfy the epipolar
// constraint of their poses (squared distance to the epipolar line below 3.84 sigma^2 of the
// second keypoint's level, geometry::kChi2OneDof95TwoDigits), away from the epipole (100 px
// scaled by level), Hamming <= th_low, clearly better than any candidate elsewhere on the line
// (ratio_triangulation, including keypoints that have a landmark), one-to-one, rotation check.
// The candidates in kf2 are taken from its grid cells along the epipolar line, only along the
// part a point in front of both cameras can project to: from the epipole (depth 0 in kf1) to
// the ray's projection at `max_depth` (depth in kf1's camera; 0 or less: to the ray's vanishing
// point). pairs receives (index in kf1, index in kf2) in kf1 order; returns their number.
int search_for_triangulation(const MatchContext& ctx, const PosedKeyframe& kf1, const PosedKeyframe& kf2,
                             double max_depth, std::vector<std::pair<int, int>>& pairs);

}  // namespace ale::slam
