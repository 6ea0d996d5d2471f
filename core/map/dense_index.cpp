#include "core/map/dense_index.h"

#include <algorithm>

namespace ale::map {

DenseIndex::DenseIndex(const MapStore& store) {
  const MapStats s = store.stats();
  keyframes_.reserve(s.keyframe_capacity);
  landmarks_.reserve(s.landmark_capacity);
  keyframe_index_.assign(s.keyframe_capacity, -1);
  landmark_index_.assign(s.landmark_capacity, -1);
  order_.reserve(s.keyframe_capacity);
}

void DenseIndex::build(const MapStore& store, MapId map) {
  keyframes_.clear();
  landmarks_.clear();
  std::fill(keyframe_index_.begin(), keyframe_index_.end(), -1);
  std::fill(landmark_index_.begin(), landmark_index_.end(), -1);
  order_.clear();
  store.for_each_keyframe([&](KeyframeId id, const Keyframe& kf) {
    if (kf.map_id == map && id.slot() < keyframe_index_.size()) order_.emplace_back(kf.frame_seq, id.value);
  });
  std::sort(order_.begin(), order_.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : KeyframeId{a.second}.slot() < KeyframeId{b.second}.slot();
  });
  for (const auto& o : order_) {
    const KeyframeId id{o.second};
    keyframe_index_[id.slot()] = static_cast<std::int32_t>(keyframes_.size());
    keyframes_.push_back(id);
  }
  store.for_each_landmark([&](LandmarkId id, const Landmark& lm) {
    if (lm.map_id != map || id.slot() >= landmark_index_.size()) return;
    landmark_index_[id.slot()] = static_cast<std::int32_t>(landmarks_.size());
    landmarks_.push_back(id);
  });
}

}  // namespace ale::map
