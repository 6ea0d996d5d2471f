// Pose refinement of a frame against its matched landmarks: motion-only optimisation of
// frame.T_cw; the matches it finds to be outliers are unmatched. The landmarks used are those
// seen by at least min_observations keyframes, when at least min_confirmed matches are seen that
// often (a landmark from two keyframes fits any match that obeys their epipolar geometry, right
// or wrong), else all of them. The tracker refines after each search; a relocaliser refines its
// PnP pose the same way.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/optim/motion_only.h"
#include "core/slam/frame.h"

namespace ale::slam {

struct PoseRefinerParams {
  int min_observations = 3;
  int min_confirmed = 60;
  int min_inliers = 10;
  optim::MotionOnlyOptions motion_only;
};

class PoseRefiner {
 public:
  PoseRefiner(const PoseRefinerParams& params, const geometry::Camera& pinhole) : params_(params), pinhole_(pinhole) {}

  // Refines frame.T_cw from its matches in `map`; *inliers gets the inlier count (0 when the
  // optimisation failed or had nothing to use). True when there are at least min_inliers.
  bool refine(Frame& frame, const map::MapStore& map, int* inliers);
  // The same with far points besides the landmarks: bearings[k] is a point far along the ray of
  // keypoint bearing_keypoints[k] (Tracker's turn step). Bearings found to be outliers are
  // removed from both lists. *map_inliers and *bearing_inliers get the two inlier counts. False
  // when the optimisation failed.
  bool refine_with_bearings(Frame& frame, const map::MapStore& map, std::vector<geometry::Vec3>& bearings,
                            std::vector<int>& bearing_keypoints, int* map_inliers, int* bearing_inliers);
  const PoseRefinerParams& params() const { return params_; }
  // The centre prior of the following refine() calls (core/optim/motion_only.h); sigma 0: none.
  void set_centre_prior(const optim::CentrePrior& prior) { prior_ = prior; }

 private:
  void gather(const Frame& frame, const map::MapStore& map);

  PoseRefinerParams params_;
  optim::CentrePrior prior_;
  geometry::Camera pinhole_;
  std::vector<optim::PoseObservation> obs_;
  std::vector<int> obs_keypoint_;
  std::vector<std::uint8_t> inlier_;
};

}  // namespace ale::slam
