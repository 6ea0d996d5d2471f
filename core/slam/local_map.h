// The local map a frame is tracked against (ORB-SLAM's UpdateLocalKeyFrames and
// UpdateLocalPoints): the keyframes that observe the frame's matched landmarks, their strongest
// covisible neighbours and their spanning-tree parents, and every landmark those keyframes see.
// The tracker builds it for each frame; a relocaliser builds it around a candidate pose.
#pragma once

#include <vector>

#include "core/map/map_store.h"

namespace ale::slam {

// Median depth of a keyframe's landmarks in its camera (map units); 0 when it has none or is
// stale. scratch and z are the caller's buffers.
double keyframe_median_depth(const map::MapStore& map, map::KeyframeId id, std::vector<map::LandmarkId>& scratch,
                             std::vector<double>& z);

// The landmarks a keyframe and its `neighbours` strongest covisible keyframes see, sorted by id,
// each once, into out (replaced): a place's neighbourhood for a search by projection.
void neighbourhood_landmarks(const map::MapStore& map, map::KeyframeId id, int neighbours,
                             std::vector<map::LandmarkId>& out);

struct LocalMapParams {
  int keyframes_max = 80;           // neighbours are added while the list is shorter than this
  int covisible_per_keyframe = 10;  // strongest neighbours taken from each observing keyframe
};

class LocalMap {
 public:
  // Selects around `matched` (per keypoint; invalid where none). Returns the keyframe that sees
  // the most of them (invalid when none does). Deterministic: keyframes in slot order, then
  // neighbours in covisibility order; landmarks sorted by id, each once.
  map::KeyframeId select(const std::vector<map::LandmarkId>& matched, const map::MapStore& map,
                         const LocalMapParams& params);
  const std::vector<map::KeyframeId>& keyframes() const { return keyframes_; }
  const std::vector<map::LandmarkId>& landmarks() const { return landmarks_; }

 private:
  std::vector<map::KeyframeId> keyframes_;
  std::vector<map::LandmarkId> landmarks_;
  std::vector<int> counts_by_slot_;  // matched landmarks each keyframe sees
  std::vector<map::KeyframeId> ids_by_slot_;
};

}  // namespace ale::slam
