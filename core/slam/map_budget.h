// The map's fixed memory (MapCapacity): before a keyframe is inserted into a nearly full map,
// the oldest keyframes outside the reference keyframe's covisible neighbourhood go, with the
// landmarks no other keyframe observes, so that a robot running for hours keeps mapping where it
// is. Without loop closing the map forgets the places it left longest ago; the poses stay
// continuous. A few keyframes go at a time (a twentieth of the capacity), so that eviction is
// not needed at every keyframe.
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "core/map/map_store.h"
#include "core/slam/local_mapper.h"

namespace ale::slam {

class MapBudget {
 public:
  explicit MapBudget(const map::MapCapacity& capacity) : capacity_(capacity) {}

  // Makes room for one keyframe and the landmarks it can create, when the map lacks it; counts
  // the evictions into report.keyframes_evicted and report.landmarks_evicted.
  void make_room(map::MapStore& map, map::KeyframeId reference, MappingReport& report);

 private:
  map::MapCapacity capacity_;
  // (in the reference's neighbourhood, keyframe time, id): oldest outside it first
  std::vector<std::tuple<bool, double, map::KeyframeId>> candidates_;
  std::vector<map::LandmarkId> seen_;
};

}  // namespace ale::slam
