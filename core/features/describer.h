// The orientation-and-description stage of the frame path: for the kept corners of a level, the
// intensity-centroid angle on the plain level and the 256-bit rotated BRIEF on the level smoothed
// around them (ORB-SLAM: 7x7 Gaussian, sigma 2; blur.h). Owns the smoothing buffer and the
// rotated sampling pattern (built once per stride).
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/features/blur.h"
#include "core/features/brief.h"
#include "core/features/fast.h"
#include "core/features/frame_pyramid.h"
#include "core/features/orb.h"

namespace ale::features {

class Describer {
 public:
  Describer();
  // Sizes the smoothing buffer and the rotated pattern for `pyramid`'s planned frame size.
  void plan(const FramePyramid& pyramid);
  // Appends one keypoint and its descriptor per corner of `level` (in order).
  void describe_level(const FramePyramid& pyramid, int level, const std::vector<FastCorner>& corners,
                      std::vector<Keypoint>& keypoints, std::vector<Descriptor>& descriptors);

 private:
  int width_ = 0;  // the planned frame size
  int height_ = 0;
  std::vector<std::uint8_t> blurred_;
  BlurScratch blur_scratch_;
  BriefPattern pattern_;
  RotatedPattern rotated_;
};

}  // namespace ale::features
