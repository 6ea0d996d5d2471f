// Motion-only pose optimisation: refine one camera pose T_cw against fixed 3-D points, with
// ORB-SLAM's outlier rounds (Optimizer::PoseOptimization): `rounds` (4) runs of at most
// `iterations` (10) Levenberg-Marquardt steps; after each run every observation, including the
// ones rejected before, is reclassified by its chi-square information * |r|^2 against 5.991;
// the Huber kernel (delta sqrt(5.991)) is on for the first `robust_rounds` (2) runs only;
// information = 1 / scale_factor^(2 level). Nothing is allocated.
//
// Status: kInvalidArgument for bad input (invalid camera, non-finite pose or observations, fewer
// than 3 observations); kNotFound when fewer than min_inliers observations are inliers at the
// end (the pose is then the last estimate, finite, but should not be trusted); kInternal when
// the cost is not finite at the start. T_cw is always finite.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"
#include "core/optim/lm.h"

namespace ale::optim {

struct PoseObservation {
  geometry::Vec3 p_w = geometry::Vec3::Zero();
  geometry::Vec2 uv_px = geometry::Vec2::Zero();
  int level = 0;  // pyramid level of the keypoint (0..31)
};

struct MotionOnlyOptions {
  int rounds = 4;
  int iterations = 10;
  int robust_rounds = 2;
  double chi2_gate = geometry::kChi2TwoDof95;
  double huber_delta = geometry::kHuberDeltaTwoDof95;
  double scale_factor = 1.2;
  int min_inliers = 10;
  LmOptions lm;  // max_iterations is replaced by `iterations`
};

// A soft prior on the camera centre (T_cw.inverse().translation()): the cost gains
// 0.5 |c - centre_w|^2 / sigma^2, no kernel, no outlier test. sigma <= 0: no prior. The
// tracker predicts the centre from the wheel odometry or the constant-velocity model: a ground
// robot's camera centre moves smoothly while its heading can turn fast, and against points at
// one depth a yaw error looks like a sideways step (the two are told apart only by depth
// differences).
struct CentrePrior {
  geometry::Vec3 centre_w = geometry::Vec3::Zero();
  double sigma = 0.0;
};

struct MotionOnlyResult {
  Status status;
  geometry::SE3 T_cw;
  int inliers = 0;
  int iterations = 0;        // LM iterations over all rounds
  double final_cost = 0.0;   // 0.5 * sum of chi-squares over the final inliers
};

// inlier[k] receives 1 for inliers, 0 for outliers (n entries).
MotionOnlyResult optimize_pose(const geometry::Camera& camera, const geometry::SE3& T_cw_init,
                               const PoseObservation* observations, int n,
                               const MotionOnlyOptions& options, std::uint8_t* inlier,
                               const CentrePrior& prior = CentrePrior{});

}  // namespace ale::optim
