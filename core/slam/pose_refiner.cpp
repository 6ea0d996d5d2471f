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

bool PoseRefiner::refine_with_bearings(Frame& frame, const map::MapStore& map, std::vector<geometry::Vec3>& bearings,
                                       std::vector<int>& bearing_keypoints, int* map_inliers, int* bearing_inliers) {
  gather(frame, map);
  *map_inliers = 0;
  *bearing_inliers = 0;
  const std::size_t landmarks = obs_.size();
  for (std::size_t k = 0; k < bearings.size(); ++k) {
    const map::KeyframeFeature& f = frame.features[static_cast<std::size_t>(bearing_keypoints[k])];
    optim::PoseObservation o;
    o.p_w = bearings[k];
    o.uv_px = geometry::Vec2(f.u, f.v);
    o.level = f.level;
    obs_.push_back(o);
  }
  if (obs_.size() < 3) return false;
  inlier_.assign(obs_.size(), 0);
  const optim::MotionOnlyResult r = optim::optimize_pose(pinhole_, frame.T_cw, obs_.data(), static_cast<int>(obs_.size()),
                                                         params_.motion_only, inlier_.data(), prior_);
  if (!(r.status.ok() || r.status.code() == StatusCode::kNotFound) || !r.T_cw.translation().allFinite()) return false;
  frame.T_cw = r.T_cw;
  for (std::size_t k = 0; k < landmarks; ++k) {
    if (!inlier_[k]) {
      frame.landmarks[static_cast<std::size_t>(obs_keypoint_[k])] = map::LandmarkId{};
    } else {
      ++*map_inliers;
    }
  }
  std::size_t kept = 0;
  for (std::size_t k = 0; k < bearings.size(); ++k) {
    if (!inlier_[landmarks + k]) continue;
    bearings[kept] = bearings[k];
    bearing_keypoints[kept] = bearing_keypoints[k];
    ++kept;
  }
  bearings.resize(kept);
  bearing_keypoints.resize(kept);
  *bearing_inliers = static_cast<int>(kept);
  return true;
}

}  // namespace ale::slam
