#include "core/slam/map_budget.h"

#include <algorithm>

namespace ale::slam {

void MapBudget::make_room(map::MapStore& map, map::KeyframeId reference, MappingReport& report) {
  const map::MapStats before = map.stats();
  const std::size_t landmark_margin = static_cast<std::size_t>(capacity_.max_keypoints_per_keyframe);
  const bool full = before.keyframes + 1 >= before.keyframe_capacity ||
                    before.landmarks + landmark_margin >= before.landmark_capacity;
  if (!full) return;
  const map::Keyframe* ref = map.keyframe(reference);
  auto near_reference = [&](map::KeyframeId id) {
    if (!ref) return false;
    for (int n = 0; n < ref->num_covisible; ++n)
      if (ref->covisible[static_cast<std::size_t>(n)].keyframe == id) return true;
    return false;
  };
  // oldest first, those outside the neighbourhood before those in it (a small map may have no other)
  candidates_.clear();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& kf) {
    if (id != reference) candidates_.emplace_back(near_reference(id), kf.timestamp_s, id);
  });
  std::sort(candidates_.begin(), candidates_.end());
  const std::size_t batch = std::max<std::size_t>(1, before.keyframe_capacity / 20);
  for (std::size_t i = 0; i < candidates_.size() && i < batch; ++i) {
    seen_.clear();
    const map::KeyframeId id = std::get<2>(candidates_[i]);
    map.landmarks_of(id, seen_);
    map.erase_keyframe(id);
    ++report.keyframes_evicted;
    for (map::LandmarkId l : seen_) {
      const map::Landmark* lm = map.landmark(l);
      if (lm && lm->num_observations < 2) {
        map.erase_landmark(l);
        ++report.landmarks_evicted;
      }
    }
  }
}

}  // namespace ale::slam
