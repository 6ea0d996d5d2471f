// The map-to-BA builder: the one place that turns keyframes, landmarks and their observations
// into a bundle-adjustment problem, and the one rule for whether a solve's result may reach the
// map. The initialiser's two-keyframe BA and the local mapper's local BA both build through it.
//
// The rule: a solve that converged (ok) or stopped at its iteration limit (kNotConverged) leaves
// the best state it reached, which never costs more than the start, so its poses and points are
// used; any other status (bad input, numerical failure) leaves the map as it was.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/optim/bundle_adjuster.h"
#include "core/slam/floor.h"
#include "core/slam/odometry.h"
#include "core/slam/match/feature_grid.h"

namespace ale::slam {

class MapBundleAdjustment {
 public:
  MapBundleAdjustment(const geometry::Camera& pinhole, const ScalePyramid& pyramid)
      : pinhole_(pinhole), pyramid_(pyramid) {}

  // Starts a problem over `map` (every buffer keeps its capacity).
  void reset(const map::MapStore& map);
  // Adds a keyframe's pose; false (nothing added) for a stale id or one already in the problem.
  bool add_keyframe(map::KeyframeId kf, bool fixed);
  // Adds a landmark with every observation of it by a keyframe in the problem (in the landmark's
  // observation order), Huber-weighted at the 95 % chi-square of 2 degrees of freedom.
  void add_landmark(map::LandmarkId lm);

  // Wheel odometry between keyframes (in a metric map): each free keyframe of the problem with an
  // odometry pose gets a prior on its camera centre where the odometry puts it from the latest
  // earlier keyframe of the problem (at that keyframe's pose now), within keyframe_prior_max_span_s, with sigma
  // prior_sigma_m + prior_sigma_fraction x the distance. It keeps a window whose views cannot fix
  // the scale (the walls a turn on the spot brings into view) from shrinking its baselines.
  // Returns the priors added.
  // gyro_bias_rps (GyroBias::rate_rps) is taken off the odometry's heading change of the
  // rotation priors.
  int add_odometry_priors(const OdometryParams& odometry, double gyro_bias_rps = 0.0);

  // The floor (in a metric map): each landmark of the problem that lies within
  // params.max_height_m of the floor under the first keyframe of the problem that sees it (by that
  // keyframe's pose now) is held on that floor with sigma params.sigma_m (Huber at the 95 %
  // chi-square of 1 degree of freedom): the scale the camera's height gives, window after window.
  // Call after every add_landmark (these observations come after the reprojections'). Returns
  // how many were added.
  int add_floor_observations(const FloorParams& params, const FloorGeometry& floor);

  optim::BaSummary solve(const optim::BaOptions& options) { return ba_.solve(options); }
  static bool usable(const optim::BaSummary& summary) {
    return summary.status.ok() || summary.status.code() == StatusCode::kNotConverged;
  }
  // The solved poses and points (the finite ones) into the map.
  void write_back(map::MapStore& map) const;

  int num_keyframes() const { return static_cast<int>(keyframes_.size()); }
  int num_landmarks() const { return static_cast<int>(landmarks_.size()); }
  int num_observations() const { return static_cast<int>(observations_.size()); }
  map::LandmarkId landmark(int j) const { return landmarks_[static_cast<std::size_t>(j)]; }
  const geometry::SE3& pose(int i) const { return ba_.pose(i); }
  const geometry::Vec3& point(int j) const { return ba_.point(j); }
  // The k-th reprojection (k < num_observations(); the floor's come after them): its keyframe and
  // keypoint, and whether the solve kept it.
  const std::pair<map::KeyframeId, int>& observation(int k) const { return observations_[static_cast<std::size_t>(k)]; }
  map::LandmarkId observation_landmark(int k) const { return observation_landmarks_[static_cast<std::size_t>(k)]; }
  bool is_inlier(int k) const { return ba_.is_inlier(k); }

 private:
  geometry::Camera pinhole_;
  ScalePyramid pyramid_;
  const map::MapStore* map_ = nullptr;
  optim::BundleAdjuster ba_;
  std::vector<int> pose_index_;  // by keyframe slot, -1 outside the problem
  std::vector<map::KeyframeId> keyframes_;
  std::vector<map::LandmarkId> landmarks_;
  std::vector<std::pair<map::KeyframeId, int>> observations_;
  std::vector<map::LandmarkId> observation_landmarks_;
};

}  // namespace ale::slam
