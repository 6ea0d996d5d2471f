#include "core/slam/pose_refiner.h"

namespace ale::slam {

void PoseRefiner::gather(const Frame& frame, const map::MapStore& map) {
  obs_.clear();
  obs_keypoint_.clear();
  int confirmed = 0;
  for (map::LandmarkId id : frame.landmarks) {
    const map::Landmark* lm = map.landmark(id);
    if (lm && lm->num_observations >= params_.min_observations) ++confirmed;
  }
  const int needed = confirmed >= params_.min_confirmed ? params_.min_observations : 0;
  for (int i = 0; i < frame.size(); ++i) {
    const map::Landmark* lm = map.landmark(frame.landmarks[static_cast<std::size_t>(i)]);
    if (!lm || lm->num_observations < needed) continue;
    const map::KeyframeFeature& f = frame.features[static_cast<std::size_t>(i)];
    optim::PoseObservation o;
    o.p_w = lm->p_w;
    o.uv_px = geometry::Vec2(f.u, f.v);
    o.level = f.level;
    obs_.push_back(o);
    obs_keypoint_.push_back(i);
  }
}

bool PoseRefiner::refine(Frame& frame, const map::MapStore& map, int* inliers) {
  gather(frame, map);
  *inliers = 0;
  if (obs_.empty()) return false;
  inlier_.assign(obs_.size(), 0);
  const optim::MotionOnlyResult r = optim::optimize_pose(pinhole_, frame.T_cw, obs_.data(), static_cast<int>(obs_.size()),
                                                         params_.motion_only, inlier_.data(), prior_);
  if (!r.status.ok() || !r.T_cw.translation().allFinite()) return false;
  frame.T_cw = r.T_cw;
  for (std::size_t k = 0; k < obs_.size(); ++k) {
    if (!inlier_[k]) frame.landmarks[static_cast<std::size_t>(obs_keypoint_[k])] = map::LandmarkId{};
  }
  *inliers = r.inliers;
  return r.inliers >= params_.min_inliers;
}

}  // namespace ale::slam
