// The trajectory as ORB-SLAM saves it at the end of a run: each frame's pose is kept relative to
// its reference keyframe and composed, when asked for, with that keyframe's pose as the map holds
// it then, after every later bundle adjustment moved it. A keyframe culled in between is
// replaced by its spanning-tree parent through the relative pose between the two at culling
// time. The online pose (what tracking gave the frame, what the robot received) is not changed;
// this is the offline estimate a replay writes (`ale-slamd --trajectory`, docs/slam.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/geometry/lie.h"
#include "core/map/map_store.h"

namespace ale::slam {

struct TrajectoryPose {
  double timestamp_s = 0.0;
  std::uint64_t sequence = 0;
  std::uint32_t map_id = 0;
  geometry::SE3 T_cw;
  bool refined = false;  // composed with its keyframe's final pose (false: the online pose)
};

class RefinedTrajectory {
 public:
  // A frame with a pose: T_cw from tracking, ref its reference keyframe (alive in `map`).
  void add(double timestamp_s, std::uint64_t sequence, map::KeyframeId ref, const geometry::SE3& T_cw,
           const map::MapStore& map);
  // Keyframes the map erased since the last call (MapStore::take_erased).
  void keyframes_erased(const std::vector<map::ErasedKeyframe>& erased);
  // Composes every frame added since the last call with its keyframe's pose in `map` now; call
  // before the map is reset and at the end. Frames whose keyframe chain is broken keep their
  // online pose. resolve_map(): only the frames of one map (before it is erased), the others
  // stay relative to their keyframes.
  void resolve(const map::MapStore& map);
  void resolve_map(const map::MapStore& map, map::MapId only);
  const std::vector<TrajectoryPose>& poses() const { return poses_; }
  // The current map of `map` was scaled by `factor`: the poses relative to its keyframes (not yet
  // resolved) too; other maps' frames keep theirs.
  void rescale(double factor, const map::MapStore& map);
  // A loop closure scaled the map by another factor around each keyframe: factor_of(kf) is what
  // lengths relative to kf become. The poses relative to keyframes follow (online poses stay).
  template <class F>
  void rescale_relative(F&& factor_of) {
    for (Pending& p : pending_) p.T_cr = p.T_cr.scaled(factor_of(p.ref));
    for (auto& e : erased_) e.second.T_cp = e.second.T_cp.scaled(factor_of(e.second.parent));
  }
  void clear();

 private:
  struct Pending {
    std::size_t index = 0;
    map::KeyframeId ref;
    geometry::SE3 T_cr;
  };
  struct Erased {
    map::KeyframeId parent;
    geometry::SE3 T_cp;
  };
  // The keyframe kf is, or the live one its chain of erased keyframes ends in (nullptr when the
  // chain is broken); T, when given, is multiplied by each erased link's T_cp on the way.
  const map::Keyframe* live_keyframe(map::KeyframeId kf, const map::MapStore& map, geometry::SE3* T) const;
  // The map of keyframe kf, through the chain of erased keyframes when it is gone (~0 when broken).
  std::uint32_t map_of(map::KeyframeId kf, const map::MapStore& map) const;
  // Composes the pending frame p (a broken keyframe chain leaves its online pose).
  void compose(const Pending& p, const map::MapStore& map);
  std::vector<TrajectoryPose> poses_;
  std::vector<Pending> pending_;
  std::unordered_map<std::uint32_t, Erased> erased_;  // by KeyframeId::value (ids are unique across maps)
};

}  // namespace ale::slam
