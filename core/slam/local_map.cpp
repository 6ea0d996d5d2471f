#include "core/slam/local_map.h"

#include <algorithm>

#include "core/base/median.h"

namespace ale::slam {

void neighbourhood_landmarks(const map::MapStore& map, map::KeyframeId id, int neighbours,
                             std::vector<map::LandmarkId>& out) {
  out.clear();
  map.landmarks_of(id, out);
  int taken = 0;
  for (const map::Covisible& c : map.covisible_of(id)) {
    if (taken++ >= neighbours) break;
    map.landmarks_of(c.keyframe, out);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

double keyframe_median_depth(const map::MapStore& map, map::KeyframeId id, std::vector<map::LandmarkId>& scratch,
                             std::vector<double>& z) {
  const map::Keyframe* kf = map.keyframe(id);
  scratch.clear();
  z.clear();
  if (!kf) return 0.0;
  map.landmarks_of(id, scratch);
  for (map::LandmarkId l : scratch) z.push_back((kf->T_cw * map.landmark(l)->p_w).z());
  return median_in_place(z);
}

map::KeyframeId LocalMap::select(const std::vector<map::LandmarkId>& matched, const map::MapStore& map,
                                 const LocalMapParams& params) {
  const map::MapStats st = map.stats();
  counts_by_slot_.assign(st.keyframe_capacity, 0);
  ids_by_slot_.resize(st.keyframe_capacity);
  for (map::LandmarkId id : matched) {
    for (const map::Observation& o : map.observations_of(id)) {
      const map::KeyframeId kf = o.keyframe;
      if (!map.keyframe(kf)) continue;
      ++counts_by_slot_[kf.slot()];
      ids_by_slot_[kf.slot()] = kf;
    }
  }
  keyframes_.clear();
  int best = 0;
  map::KeyframeId best_kf;
  for (std::uint32_t s = 0; s < counts_by_slot_.size(); ++s) {
    if (counts_by_slot_[s] == 0) continue;
    const map::KeyframeId id = ids_by_slot_[s];
    if (counts_by_slot_[s] > best) {
      best = counts_by_slot_[s];
      best_kf = id;
    }
    keyframes_.push_back(id);
  }
  // their strongest neighbours and their parents
  const std::size_t direct = keyframes_.size();
  for (std::size_t i = 0; i < direct && static_cast<int>(keyframes_.size()) < params.keyframes_max; ++i) {
    const map::Keyframe* kf = map.keyframe(keyframes_[i]);
    for (const map::Covisible& c : map.covisible_of(keyframes_[i]).first(params.covisible_per_keyframe)) {
      if (std::find(keyframes_.begin(), keyframes_.end(), c.keyframe) == keyframes_.end()) keyframes_.push_back(c.keyframe);
    }
    if (kf->parent.valid() && std::find(keyframes_.begin(), keyframes_.end(), kf->parent) == keyframes_.end()) {
      keyframes_.push_back(kf->parent);
    }
  }
  landmarks_.clear();
  for (map::KeyframeId kf : keyframes_) map.landmarks_of(kf, landmarks_);
  std::sort(landmarks_.begin(), landmarks_.end());
  landmarks_.erase(std::unique(landmarks_.begin(), landmarks_.end()), landmarks_.end());
  return best_kf;
}

}  // namespace ale::slam
