// The front end's keypoints are in distorted pixels; the SLAM core's solvers work on the
// undistorted pinhole. Each keypoint is undistorted once, as the frame enters the core.
#pragma once

#include <vector>

#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/frame.h"

namespace ale::slam {

class KeypointUndistorter {
 public:
  explicit KeypointUndistorter(const geometry::Camera& camera);

  // The pinhole of the undistorted keypoints, and the extent of the undistorted image (the
  // border's pixels undistorted: ORB-SLAM uses the corners; the edges' midpoints matter under
  // strong barrel distortion).
  const geometry::Camera& pinhole() const { return pinhole_; }
  const ImageBounds& bounds() const { return bounds_; }
  // frame.features becomes the first `max_keypoints` of `features` that can be undistorted (the
  // others are dropped), and the frame is indexed on them.
  void apply(const std::vector<map::KeyframeFeature>& features, int max_keypoints, Frame& frame) const;

 private:
  geometry::Camera camera_, pinhole_;
  ImageBounds bounds_;
};

}  // namespace ale::slam
