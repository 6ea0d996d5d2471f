// Similarity (or rigid motion) between two sets of matched 3-D points: y_i ~ S_yx * x_i with
// S_yx = (s, R, t). The closed form is Umeyama's (1991): centroids, the SVD of the cross
// covariance, a sign flip against reflections, and the scale from the singular values; with
// weights it minimises sum w_i |y_i - S x_i|^2. Inside RANSAC (core/geometry/ransac.h, seeded)
// from minimal samples of three matches, for loop closing and map merging.
//
// Inlier gate: the 3-D residual e_i = |y_i - S x_i| (in y's units) must be below max_error_y,
// and, when max_error_x > 0, e_i / s = |x_i - S^-1 y_i| (in x's units) below max_error_x. The
// second side matters when the two point sets have different scales (two monocular maps): a
// gate in only one frame would favour models that shrink that frame's residuals. (ORB-SLAM's
// Sim3Solver gates reprojection errors in both keyframes instead; a caller with cameras can
// rescore the returned inliers that way.) The score is MSAC's: sum over inliers of
// 1 - (e_i / gate)^2.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/lie.h"
#include "core/geometry/ransac.h"

namespace ale::geometry {

// The S_yx minimising sum w_i |y_i - (s R x_i + t)|^2, s = 1 unless with_scale. `weights` empty
// means all 1. kInvalidArgument when the sizes differ, there are fewer than 3 matches, a value
// is not finite, a weight is negative or all are 0, or the points are degenerate (all x or all y
// on one line or at one point: the rotation about that line is then undetermined).
Result<Sim3> umeyama(const std::vector<Vec3>& x, const std::vector<Vec3>& y, bool with_scale,
                     const std::vector<double>& weights = {});

struct Sim3RansacParams {
  RansacParams ransac;        // seed, confidence, iteration cap
  bool with_scale = true;     // false: a rigid motion (scale fixed to 1)
  double max_error_y = 0.0;   // gate on |y - S x|, y's units; must be > 0
  double max_error_x = 0.0;   // gate on |x - S^-1 y|, x's units; 0: not used
  int min_inliers = 6;        // fewer after refinement: kNotFound
  int refine_rounds = 3;      // closed form on the inliers, reclassify, repeat while it helps
};

struct Sim3RansacResult {
  Sim3 S_yx;
  std::vector<std::uint8_t> inlier_mask;  // one entry per match, 1 for an inlier
  int inliers = 0;
  double rms_error_y = 0.0;  // of the inliers, y's units
  RansacStats stats;         // of the sampling stage
};

// Scratch a caller keeps so that repeated solves do not allocate once warmed up.
struct Sim3Scratch {
  RansacScratch ransac;
  std::vector<std::uint8_t> mask;
  std::vector<Vec3> x_in, y_in;
};

// RANSAC over minimal samples of 3 matches, then refinement on the inliers. kInvalidArgument
// for bad input (sizes, fewer than 3, not finite, no gate, all x or all y collinear); kNotFound
// when no model reaches min_inliers. The same input and seed give the same result everywhere.
Status solve_sim3_ransac(const std::vector<Vec3>& x, const std::vector<Vec3>& y, const Sim3RansacParams& params,
                         Sim3RansacResult* result, Sim3Scratch& scratch);

}  // namespace ale::geometry
