#include "core/slam/map_ba.h"

#include "core/geometry/chi_square.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {

void MapBundleAdjustment::reset(const map::MapStore& map) {
  map_ = &map;
  ba_.reset(pinhole_);
  for (map::KeyframeId k : keyframes_) pose_index_[k.slot()] = -1;
  const std::size_t keyframes = map.stats().keyframe_capacity;
  if (pose_index_.size() < keyframes) {  // the map's capacity bounds the poses: room for all of them
    pose_index_.resize(keyframes, -1);
    keyframes_.reserve(keyframes);
    ba_.reserve(static_cast<int>(keyframes), 0, 0);
  }
  keyframes_.clear();
  landmarks_.clear();
  observations_.clear();
  observation_landmarks_.clear();
}

bool MapBundleAdjustment::add_keyframe(map::KeyframeId kf, bool fixed) {
  const map::Keyframe* k = map_->keyframe(kf);
  if (!k || pose_index_[kf.slot()] >= 0) return false;
  pose_index_[kf.slot()] = ba_.add_pose(k->T_cw, fixed);
  keyframes_.push_back(kf);
  return true;
}

void MapBundleAdjustment::add_landmark(map::LandmarkId id) {
  const map::Landmark* lm = map_->landmark(id);
  if (!lm) return;
  static const optim::RobustKernel kHuber = optim::RobustKernel::huber(std::sqrt(geometry::kChi2TwoDof95));
  const int p = ba_.add_point(lm->p_w);
  landmarks_.push_back(id);
  for (int i = 0; i < lm->num_observations; ++i) {
    const map::Observation& o = lm->observations[static_cast<std::size_t>(i)];
    const int pose = pose_index_[o.keyframe.slot()];
    if (pose < 0 || !map_->keyframe(o.keyframe)) continue;
    const map::KeyframeFeature& f = map_->features(o.keyframe)[o.keypoint];
    const int level = std::clamp<int>(f.level, 0, pyramid_.levels - 1);
    ba_.add_observation(pose, p, geometry::Vec2(f.u, f.v), pyramid_.inv_sigma2[level], kHuber);
    observations_.emplace_back(o.keyframe, static_cast<int>(o.keypoint));
    observation_landmarks_.push_back(id);
  }
}

int MapBundleAdjustment::add_odometry_priors(const OdometryParams& odometry, double gyro_bias_rps) {
  int added = 0;
  for (map::KeyframeId id : keyframes_) {
    const map::Keyframe* k = map_->keyframe(id);
    if (!k->has_odometry) continue;
    const map::Keyframe* before = nullptr;
    for (map::KeyframeId other : keyframes_) {
      const map::Keyframe* o = map_->keyframe(other);
      if (o->has_odometry && o->timestamp_s < k->timestamp_s && (!before || o->timestamp_s > before->timestamp_s)) before = o;
    }
    if (!before || k->timestamp_s - before->timestamp_s > odometry.keyframe_prior_max_span_s) continue;
    // the keyframe's camera centre in the earlier one's camera frame, then in the world
    const BasePose2 a = keyframe_odometry(*before), b = keyframe_odometry(*k);
    const geometry::SE3 between = camera_between(odometry.T_bc, a, b);
    const geometry::Vec3 step = between.translation();
    const geometry::SE3 T_wc = before->T_cw.inverse();
    const double sigma = odometry.prior_sigma(step.norm());
    // Huber: a wheel that spun or slipped pulls no harder than a few sigmas
    static const optim::RobustKernel kHuber = optim::RobustKernel::huber(std::sqrt(geometry::kChi2ThreeDof95));
    const int pose = pose_index_[id.slot()];
    ba_.add_centre_prior(pose, T_wc * step, sigma, kHuber);
    if (odometry.rotation_prior_sigma_deg > 0.0) {
      // the heading the gyro and wheels turned through (and, the floor being flat, no roll or pitch)
      BasePose2 turned = b;
      turned.theta_rad -= gyro_bias_rps * (k->timestamp_s - before->timestamp_s);
      const geometry::SE3 rotated = gyro_bias_rps == 0.0 ? between : camera_between(odometry.T_bc, a, turned);
      const geometry::Mat3 R_cw = rotated.rotation().transpose() * before->T_cw.rotation();
      ba_.add_rotation_prior(pose, R_cw, odometry.rotation_prior_sigma(a, b), kHuber);
    }
    ++added;
  }
  return added;
}

int MapBundleAdjustment::add_floor_observations(const FloorParams& params, const FloorGeometry& floor) {
  static const optim::RobustKernel kHuber = optim::RobustKernel::huber(std::sqrt(geometry::kChi2OneDof95));
  const double information = 1.0 / (params.sigma_m * params.sigma_m);
  int added = 0;
  for (std::size_t j = 0; j < landmarks_.size(); ++j) {
    const map::Landmark* lm = map_->landmark(landmarks_[j]);
    for (int i = 0; i < lm->num_observations; ++i) {
      const map::KeyframeId kf = lm->observations[static_cast<std::size_t>(i)].keyframe;
      const int pose = pose_index_[kf.slot()];
      const map::Keyframe* k = pose < 0 ? nullptr : map_->keyframe(kf);
      if (!k) continue;
      const geometry::Vec3 p_c = k->T_cw * lm->p_w;
      if (p_c.z() > 0.0 && std::abs(floor.up_c.dot(p_c) + floor.camera_height_m) <= params.max_height_m) {
        ba_.add_plane_observation(pose, static_cast<int>(j), floor.up_c, floor.camera_height_m, information, kHuber);
        ++added;
      }
      break;
    }
  }
  return added;
}

void MapBundleAdjustment::write_back(map::MapStore& map) const {
  for (std::size_t i = 0; i < keyframes_.size(); ++i) {
    const geometry::SE3& T = ba_.pose(static_cast<int>(i));
    if (T.translation().allFinite()) map.keyframe(keyframes_[i])->T_cw = T;
  }
  for (std::size_t j = 0; j < landmarks_.size(); ++j) {
    const geometry::Vec3& p = ba_.point(static_cast<int>(j));
    if (p.allFinite()) map.landmark(landmarks_[j])->p_w = p;
  }
}

}  // namespace ale::slam
