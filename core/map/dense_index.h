// Dense numbers for one map's keyframes and landmarks: what a map file stores instead of ids,
// which are a slot and a generation and depend on the store's history. Keyframes are numbered
// 0..n-1 in the order of their frame sequence numbers (ties, which a replay does not make, by
// slot), landmarks 0..m-1 in slot order: a store that loads a file by adding its objects in
// that order gives them slots in that order, so saving it again gives the same numbers.
// Memory is reserved for the store's capacity at construction; build() does not allocate.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/map/map_store.h"

namespace ale::map {

class DenseIndex {
 public:
  explicit DenseIndex(const MapStore& store);

  // Numbers the live keyframes and landmarks of `map` in `store` (the store given to the
  // constructor or one of the same capacity); the previous numbering is dropped.
  void build(const MapStore& store, MapId map);

  int num_keyframes() const { return static_cast<int>(keyframes_.size()); }
  int num_landmarks() const { return static_cast<int>(landmarks_.size()); }
  // The dense index of an id, -1 when it was not live in the map at build().
  int index_of(KeyframeId id) const { return lookup(keyframe_index_, keyframes_, id); }
  int index_of(LandmarkId id) const { return lookup(landmark_index_, landmarks_, id); }
  // The id of a dense index; invalid when out of range.
  KeyframeId keyframe_at(int i) const { return at(keyframes_, i); }
  LandmarkId landmark_at(int i) const { return at(landmarks_, i); }

 private:
  template <class IdT>
  static int lookup(const std::vector<std::int32_t>& index, const std::vector<IdT>& ids, IdT id) {
    if (!id.valid() || id.slot() >= index.size()) return -1;
    const std::int32_t i = index[id.slot()];
    // the slot's current occupant may be a later object than the one numbered
    return i >= 0 && ids[static_cast<std::size_t>(i)] == id ? i : -1;
  }
  template <class IdT>
  static IdT at(const std::vector<IdT>& ids, int i) {
    return i >= 0 && static_cast<std::size_t>(i) < ids.size() ? ids[static_cast<std::size_t>(i)] : IdT{};
  }

  std::vector<KeyframeId> keyframes_;          // dense index -> id
  std::vector<LandmarkId> landmarks_;
  std::vector<std::int32_t> keyframe_index_;   // slot -> dense index or -1
  std::vector<std::int32_t> landmark_index_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order_;  // (frame_seq, slot), scratch of build()
};

}  // namespace ale::map
