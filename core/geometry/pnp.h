// Camera pose from 3-D points and their pixels: a minimal P3P solver (three bearings, up to
// four poses) inside the tree's seeded RANSAC, then Levenberg-Marquardt on the inliers'
// reprojection error (SE(3) left perturbation, analytic Jacobian) with inlier reclassification.
//
// The P3P solver follows the idea of Lambda Twist (Persson & Nordberg, ECCV 2018): the three
// distance equations lambda_i^2 + lambda_j^2 - 2 b_ij lambda_i lambda_j = a_ij give two
// homogeneous conics in (lambda_1, lambda_2, lambda_3); a singular member of their pencil (a
// root of a cubic) is a pair of planes, each of which meets a conic in at most two rays.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"
#include "core/geometry/ransac.h"

namespace ale::geometry {

// Poses T_cw with R x_i + t = lambda_i y_i (lambda_i > 0) for three world points x_i and
// bearings y_i (any length > 0). Returns how many (0..4) were written to poses_cw; 0 when the
// points are collinear or coincide, or an input is not finite.
int solve_p3p(const Vec3 bearings[3], const Vec3 points_w[3], SE3 poses_cw[4]);

// Whitened reprojection residual of one observation, r = (project(T_cw p_w) - uv) / sigma_px,
// and its Jacobian with respect to the left perturbation of T_cw (lie.h). false (outputs
// untouched) when the point does not project (behind the camera).
bool pnp_residual(const Camera& camera, const SE3& T_cw, const Vec3& p_w, const Vec2& uv, double sigma_px, Vec2* r,
                  Mat26* d_r_d_xi = nullptr);

enum class PnpFailure {
  kNone = 0,
  kTooFewPoints,  // fewer than 4 correspondences
  kInvalidInput,  // a point, pixel or sigma is not finite (or sigma <= 0), or a pixel cannot
                  // be unprojected by the camera model
  kDegenerate,    // the points are collinear (or coincide): no minimal sample gives a pose
  kNoConsensus,   // no pose has min_inliers inliers (before or after refinement)
  kNotConverged,  // refinement did not converge; the pose is RANSAC's (finite)
};

const char* to_string(PnpFailure failure);

struct PnpParams {
  RansacParams ransac{0, 0.99, 300, 1};
  // Gate on (squared pixel error) / sigma^2: chi-square, 2 dof, 95 %.
  double chi2 = kChi2TwoDof95;
  // Consensus needed (RANSAC and after refinement); at least 4 is used (3 fit any P3P pose).
  int min_inliers = 10;
  // Refinement: rounds of (Levenberg-Marquardt on the inliers, reclassification of all points),
  // stopping early when the inlier set no longer changes.
  int refine_rounds = 3;
  int max_refine_iterations = 20;
};

// Correspondences, n of each (non-owning): 3-D points in the world, their pixels in `camera`'s
// image (for a camera with distortion, the distorted pixels; for undistorted pixels pass an
// ideal pinhole) and the pixel sigma of each observation (e.g. 1.2^level); sigma_px may be
// nullptr for 1 px everywhere.
struct PnpInput {
  const Vec3* points_w = nullptr;
  const Vec2* pixels = nullptr;
  const double* sigma_px = nullptr;
  int size = 0;
};

struct PnpResult {
  // Identity when RANSAC found no pose; else the refined pose (kNotConverged: RANSAC's pose).
  // Never NaN.
  SE3 T_cw;
  std::vector<std::uint8_t> inliers;  // 1 per inlier, size entries (the final classification)
  int inlier_count = 0;
  int ransac_iterations = 0;
  int refine_iterations = 0;  // LM iterations over all rounds
  double rms_px = 0.0;        // RMS pixel error over the final inliers
  PnpFailure failure = PnpFailure::kNone;
};

// Buffers reused between calls: with the same scratch (and result), a call with no more points
// than an earlier one does not allocate.
struct PnpScratch {
  std::vector<Vec3> bearings;
  std::vector<std::uint8_t> mask;
  RansacScratch ransac;
};

// RANSAC over P3P samples (seeded, adaptive iteration count, hard cap), scored by ORB-SLAM's
// truncated chi-square, then refinement and reclassification. ok, or a status whose message
// gives the reason, with result->failure saying which.
Status solve_pnp_ransac(const Camera& camera, const PnpInput& input, const PnpParams& params, PnpResult* result,
                        PnpScratch& scratch);

// Levenberg-Marquardt on the reprojection errors of the points with mask[i] != 0, from *T_cw
// (updated in place). Returns true when it converged (relative cost decrease or step below
// 1e-10) within max_iterations; *iterations receives the iterations run.
bool refine_pnp(const Camera& camera, const PnpInput& input, const std::uint8_t* mask, int max_iterations, SE3* T_cw,
                int* iterations);

}  // namespace ale::geometry
