// Frame-to-frame matching figures for the front end (ale-features --match, the light-level
// report): how many of two frames' keypoints match and how many of those matches one rigid
// scene explains. Not on the SLAM path (the tracker matches by projection); it measures what the
// front end hands to it.
//
//   matches: mutual nearest neighbours in Hamming distance, within `max_hamming`, each passing
//            the ratio test (best < ratio * second best) on both sides;
//   inliers: of those, the largest set one fundamental matrix explains to `epipolar_px` (the
//            distance of each point to the other's epipolar line, in both images), by the tree's
//            seeded RANSAC (core/geometry/ransac.h) over the normalised 8-point F
//            (core/geometry/two_view.h), then refitted on its inliers while their count grows.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/features/brief.h"
#include "core/features/orb.h"
#include "core/geometry/lie.h"
#include "core/geometry/ransac.h"

namespace ale::features {

struct PairMatchParams {
  int max_hamming = 64;       // of 256 bits (ORB-SLAM's TH_LOW is 50, TH_HIGH 100)
  double ratio = 0.8;         // Lowe's ratio on the two nearest distances
  double epipolar_px = 1.0;   // inlier gate of the fundamental matrix
  std::uint64_t seed = 1;     // RANSAC
  int max_iterations = 2000;
  double confidence = 0.999;
};

struct PairMatchFigures {
  int keypoints_a = 0;
  int keypoints_b = 0;
  int matches = 0;
  int inliers = 0;  // 0 when fewer than 8 matches or no model
};

// Scratch kept between calls so that repeated matching reuses its buffers.
struct PairMatchScratch {
  std::vector<int> nearest_in_b, best_a, second_a;  // per keypoint of a
  std::vector<int> nearest_in_a, best_b, second_b;  // per keypoint of b
  std::vector<std::pair<int, int>> matches;         // (index in a, index in b)
  std::vector<geometry::Vec2> x1, x2, in1, in2;     // matched points; the inliers' for the refit
  std::vector<std::uint8_t> mask, refit_mask;
  geometry::RansacScratch ransac;
};

// The mutual ratio-tested matches of a to b into scratch.matches (by index in a).
void match_descriptors(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                       const PairMatchParams& params, PairMatchScratch& scratch);

// Matches and their fundamental-matrix inliers. kInvalidArgument when a keypoint list and its
// descriptors differ in length or a parameter is out of range.
Result<PairMatchFigures> match_pair(const std::vector<Keypoint>& kps_a, const std::vector<Descriptor>& desc_a,
                                    const std::vector<Keypoint>& kps_b, const std::vector<Descriptor>& desc_b,
                                    const PairMatchParams& params, PairMatchScratch& scratch);

}  // namespace ale::features
