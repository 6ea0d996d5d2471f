#include "core/slam/refined_trajectory.h"

namespace ale::slam {

void RefinedTrajectory::add(double timestamp_s, std::uint64_t sequence, map::KeyframeId ref,
                            const geometry::SE3& T_cw, const map::MapStore& map) {
  TrajectoryPose p;
  p.timestamp_s = timestamp_s;
  p.sequence = sequence;
  p.map_id = map.stats().map_id;
  p.T_cw = T_cw;
  poses_.push_back(p);
  if (const map::Keyframe* kf = map.keyframe(ref)) {
    pending_.push_back(Pending{poses_.size() - 1, ref, T_cw * kf->T_cw.inverse()});
  }
}

void RefinedTrajectory::keyframes_erased(const std::vector<map::ErasedKeyframe>& erased) {
  for (const map::ErasedKeyframe& e : erased) {
    if (e.parent.valid()) erased_[e.id.value] = Erased{e.parent, e.T_cp};
  }
}

const map::Keyframe* RefinedTrajectory::live_keyframe(map::KeyframeId kf, const map::MapStore& map,
                                                      geometry::SE3* T) const {
  // a chain of culled keyframes is at most as long as the keyframes ever erased
  for (std::size_t hops = 0; hops <= erased_.size(); ++hops) {
    if (const map::Keyframe* k = map.keyframe(kf)) return k;
    auto it = erased_.find(kf.value);
    if (it == erased_.end()) return nullptr;
    if (T) *T = *T * it->second.T_cp;
    kf = it->second.parent;
  }
  return nullptr;
}

void RefinedTrajectory::compose(const Pending& p, const map::MapStore& map) {
  geometry::SE3 T = p.T_cr;
  const map::Keyframe* k = live_keyframe(p.ref, map, &T);
  if (!k) return;
  poses_[p.index].T_cw = T * k->T_cw;
  poses_[p.index].map_id = k->map_id.value;  // a merged map's frames: the map they joined
  poses_[p.index].refined = true;
}

void RefinedTrajectory::resolve(const map::MapStore& map) {
  for (const Pending& p : pending_) compose(p, map);
  pending_.clear();
  erased_.clear();
}

void RefinedTrajectory::resolve_map(const map::MapStore& map, map::MapId only) {
  std::size_t kept = 0;
  for (const Pending& p : pending_) {
    if (map_of(p.ref, map) == only.value) {
      compose(p, map);
    } else {
      pending_[kept++] = p;
    }
  }
  pending_.resize(kept);
}

std::uint32_t RefinedTrajectory::map_of(map::KeyframeId kf, const map::MapStore& map) const {
  const map::Keyframe* k = live_keyframe(kf, map, nullptr);
  return k ? k->map_id.value : ~0u;
}

void RefinedTrajectory::rescale(double factor, const map::MapStore& map) {
  // a frame whose keyframe chain is broken is taken for the current map's (as when there was one)
  const std::uint32_t current = map.current_map().value;
  auto other = [&](map::KeyframeId kf) {
    const std::uint32_t m = map_of(kf, map);
    return m != current && m != ~0u;
  };
  for (Pending& p : pending_) {
    if (other(p.ref)) continue;
    p.T_cr = p.T_cr.scaled(factor);
    poses_[p.index].T_cw = poses_[p.index].T_cw.scaled(factor);
  }
  for (auto& e : erased_) {
    if (!other(e.second.parent)) e.second.T_cp = e.second.T_cp.scaled(factor);
  }
}

void RefinedTrajectory::clear() {
  poses_.clear();
  pending_.clear();
  erased_.clear();
}

}  // namespace ale::slam
