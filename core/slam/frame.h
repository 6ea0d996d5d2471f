// A frame as the SLAM core sees it: its undistorted keypoints with descriptors (the front end's
// output, undistorted once), their grid, the landmark matched to each keypoint, and the pose
// when tracking found one. Buffers are reused from frame to frame.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/lie.h"
#include "core/map/map_store.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/match/base.h"

namespace ale::slam {

struct Frame {
  double timestamp_s = 0.0;
  std::uint64_t sequence = 0;
  std::vector<map::KeyframeFeature> features;
  FeatureGrid grid;
  std::vector<map::LandmarkId> landmarks;  // per keypoint; invalid where none
  std::vector<std::uint8_t> outlier;       // per keypoint: rejected by the last pose optimisation
  geometry::SE3 T_cw;
  bool has_pose = false;

  int size() const { return static_cast<int>(features.size()); }
  // Rebuilds the grid and clears the matches after `features` was filled.
  void index(const ImageBounds& bounds) {
    grid.build(features.data(), size(), bounds);
    landmarks.assign(features.size(), map::LandmarkId{});
    outlier.assign(features.size(), 0);
    has_pose = false;
  }
  FrameFeatures view() const { return {features.data(), size(), &grid}; }
  int matched() const {
    int n = 0;
    for (std::size_t i = 0; i < landmarks.size(); ++i) n += landmarks[i].valid() && !outlier[i];
    return n;
  }
};

}  // namespace ale::slam
