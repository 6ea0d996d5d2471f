// Search by bag of words (ORB-SLAM's SearchByBoW for a keyframe and a frame): a frame without a
// pose matched to a keyframe's landmarks, comparing only features that fall under the same node
// of the vocabulary (their feature vectors, place/vocabulary.h). What relocalisation uses before
// it has a pose to project with.
#pragma once

#include <vector>

#include "core/map/map_store.h"
#include "core/place/vocabulary.h"
#include "core/slam/match/base.h"

namespace ale::slam {

// The frame matched against a keyframe: its features, their feature vector (from the same
// vocabulary and fv_levels_up as the keyframe's) and the landmark of each keypoint (frame.count
// entries, invalid where none), which receives the new matches. Keypoints that already have a
// landmark are not searched.
struct BowTarget {
  FrameFeatures frame;
  const place::FeatureVector& fv;
  std::vector<map::LandmarkId>& landmarks;
};

// For each keypoint of `keyframe` that observes a landmark, the nearest free keypoint of the
// target under the same node (Hamming <= th_low, nearer than ratio_bow x the second nearest
// there; ties to the lower index); a target keypoint is taken once (by the first keyframe
// keypoint, in feature-vector order, that picks it). Then the rotation check (when
// rotation.enabled) between target and keyframe. Writes the keyframe keypoint's landmark into
// target.landmarks; returns the number of matches. Needs no pyramid or camera of ctx; uses
// ctx.scratch (no allocation once warm).
int search_by_bow(const MatchContext& ctx, const BowTarget& target, const map::MapStore& map, map::KeyframeId keyframe,
                  const place::FeatureVector& keyframe_fv);

}  // namespace ale::slam
