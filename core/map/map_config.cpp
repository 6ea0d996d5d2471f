#include "core/map/map_config.h"

namespace ale::map {

namespace {
constexpr ConfigField kCapacityFields[] = {
    number<&MapCapacity::max_keyframes>("max_keyframes", 2, 100000, "keyframes the map store holds (fixed arena)"),
    number<&MapCapacity::max_landmarks>("max_landmarks", 100, 10000000, "landmarks the map store holds"),
    number<&MapCapacity::max_keypoints_per_keyframe>("max_keypoints_per_keyframe", 100, 100000,
                                                           "keypoints kept per frame (the strongest; features.num_features is the front end's)"),
};
}  // namespace

extern constexpr ConfigTable kMapCapacityConfig = table_of<MapCapacity>(kCapacityFields);

}  // namespace ale::map
