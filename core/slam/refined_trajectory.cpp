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

void RefinedTrajectory::resolve(const map::MapStore& map) {
  for (const Pending& p : pending_) {
    geometry::SE3 T = p.T_cr;
    map::KeyframeId kf = p.ref;
    // a chain of culled keyframes is at most as long as the keyframes ever erased
    for (std::size_t hops = 0; hops <= erased_.size(); ++hops) {
      if (const map::Keyframe* k = map.keyframe(kf)) {
        poses_[p.index].T_cw = T * k->T_cw;
        poses_[p.index].refined = true;
        break;
      }
      auto it = erased_.find(kf.value);
      if (it == erased_.end()) break;
      T = T * it->second.T_cp;
      kf = it->second.parent;
    }
  }
  pending_.clear();
  erased_.clear();
}

void RefinedTrajectory::rescale(double factor) {
  for (Pending& p : pending_) {
    p.T_cr = p.T_cr.scaled(factor);
    poses_[p.index].T_cw = poses_[p.index].T_cw.scaled(factor);
  }
  for (auto& e : erased_) e.second.T_cp = e.second.T_cp.scaled(factor);
}

void RefinedTrajectory::clear() {
  poses_.clear();
  pending_.clear();
  erased_.clear();
}

}  // namespace ale::slam
