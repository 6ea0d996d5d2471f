// Two-view geometry from pixel matches: the normalised 8-point fundamental matrix, the
// normalised DLT homography, ORB-SLAM's truncated chi-square scoring, model selection, and the
// decomposition of either model into a relative pose with triangulated points.
//
// Conventions: match i is x1[i] in image 1 and x2[i] in image 2, undistorted pixels of one ideal
// pinhole camera K. F_21 satisfies x2^T F_21 x1 = 0 and H_21 maps x1 to x2 (x2 ~ H_21 x1). The
// pose R_21, t_21 maps camera-1 coordinates to camera 2 (p_2 = R_21 p_1 + t_21, T_21 in lie.h's
// convention); t_21 has unit norm (monocular: the scale is unknown) and the triangulated points
// are in camera 1 at that scale.
//
// Scoring (ORB-SLAM's Initializer, Mur-Artal et al. 2015), sigma the keypoint noise in pixels:
// - F: the squared distance of x2 to the epipolar line F_21 x1 over sigma^2, and of x1 to
//   F_21^T x2; each side within the 1-dof 95 % gate 3.841 adds (5.991 - chi2) to the score (the
//   2-dof gate as the score's cap, so that F and H scores compare); a match is an inlier when
//   both sides pass.
// - H: the squared transfer errors |x2 - H_21 x1|^2 and |x1 - H_12 x2|^2 over sigma^2, each side
//   within the 2-dof 95 % gate 5.991 adds (5.991 - chi2); inlier when both sides pass.
// The general model's RANSAC draws five-point samples (essential.h: calibrated essential
// matrices, each scored as F_21 = K^-T E K^-1) and refines on the essential manifold;
// estimate_fundamental (the 8-point F) stays available on its own. The homography and the
// 8-point F run in the tree's one RANSAC (ransac.h) with 8-point samples and the same seed,
// so they see the same sequence of samples (the homography is the least-squares DLT of the 8);
// each winner is then refitted on all its inliers, again while the score improves (at most 5
// times: one refit can admit inliers that improve the next).
//
// Model selection: RH = SH / (SH + SF); RH > h_ratio_threshold picks the homography (planar
// scenes, low parallax), otherwise the fundamental matrix. The threshold is 0.40, ORB-SLAM2's
// code (its paper says 0.45, ORB-SLAM3 uses 0.50): on an exactly planar scene with Gaussian
// noise sigma in each image, the expected per-side scores are about 2.9 for H (2-dof error,
// mean 2 sigma^2) and 4.0 for F (1-dof), so RH is about 0.42 at best. Above 0.45 planes would be
// handed to the degenerate fundamental matrix (measured on the synthetic planar scene of
// two_view_test.cpp: RH 0.41 with 1 px noise).
//
// Decomposition and acceptance (rules of this implementation, modelled on ORB-SLAM2):
// - F (from the essential RANSAC): E_21 = K^T F_21 K gives four (R, t); H: A = K^-1 H_21 K gives up to eight (R, t, n) by
//   Faugeras' SVD method (1988). Each candidate triangulates every inlier of the chosen model.
// - A point is good for a candidate when its triangulation is finite, it reprojects within the
//   2-dof gate (5.991 sigma^2) in both images and it lies in front of both cameras. A point whose
//   rays meet at less than kPointMinParallaxDeg has an undetermined depth sign: it is good
//   without the depth test (it cannot tell candidates apart) but never valid (not triangulated).
// - The candidate with most good points wins when: its median parallax over its valid points is
//   at least min_parallax_deg (else kLowParallax); no other candidate has more than
//   clear_winner_ratio_f (0.7) times its good count for F, clear_winner_ratio_h (0.75) for H
//   (ORB-SLAM2's values; a plane's decomposition has a second solution with most points in
//   front more often) (else kAmbiguous); its good points are at least
//   min_good_ratio (0.9) of the model's inliers and its valid points at least min_triangulated
//   (50) (else kTooFewTriangulated).
// - F path, after acceptance: the winner's pose is refined by Gauss-Newton on the Sampson error
//   of E = hat(t) R over its valid points, re-triangulated, and kept when no good point is lost.
// Failures return a non-ok Status whose message gives the figure against its threshold, and
// result->failure says which rule failed.
//
// Allocation: TwoViewScratch and the result's vectors keep their capacity; once a call with at
// least as many matches has run, a call allocates nothing on success (a failure's Status message
// is a string).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"
#include "core/geometry/ransac.h"

namespace ale::geometry {

constexpr int kTwoViewSampleSize = 8;
// Parallax below which a triangulated point's depth (and its sign) is noise: ORB-SLAM's
// cos(parallax) < 0.99998.
constexpr double kPointMinParallaxDeg = 0.3624;

// Hartley's normalisation: the similarity T (x_n = T x in homogeneous coordinates) that moves
// the centroid of pts[0..n) to the origin and their mean distance to it to sqrt(2). false when
// n < 1, a point is not finite or all points coincide.
bool hartley_normalisation(const Vec2* pts, int n, Mat3* T);

// F_21 from n >= 8 matches: Hartley-normalised linear least squares (the null vector of the
// 9x9 normal matrix), rank 2 enforced by zeroing the smallest singular value, unit Frobenius
// norm. false when n < 8, a point is not finite, or the points do not fix a unique solution.
bool fundamental_8point(const Vec2* x1, const Vec2* x2, int n, Mat3* F_21);
// H_21 from n >= 4 matches: Hartley-normalised DLT, unit Frobenius norm. false as above (n < 4,
// or the points do not fix a unique homography, e.g. three of four collinear).
bool homography_dlt(const Vec2* x1, const Vec2* x2, int n, Mat3* H_21);

// ORB-SLAM scores (top of file); mask (n entries) gets 1 for inliers, *inliers their count.
// With beat > 0, score_fundamental may stop as soon as the remaining matches cannot lift the
// score above beat: it then returns a value below beat (an upper bound of the score, under it)
// and the mask and count are partial. A score above beat is always the whole, exact score.
double score_fundamental(const Mat3& F_21, const Vec2* x1, const Vec2* x2, int n, double sigma_px,
                         std::uint8_t* mask, int* inliers, double beat = 0.0);
double score_homography(const Mat3& H_21, const Mat3& H_12, const Vec2* x1, const Vec2* x2, int n,
                        double sigma_px, std::uint8_t* mask, int* inliers);

// F_21 = K^-T hat(t_21) R_21 K^-1 of a pose for the pixels of the ideal pinhole `pinhole`
// (distortion ignored), unit Frobenius norm; zero when t_21 is zero.
Mat3 fundamental_from_pose(const CameraIntrinsics& pinhole, const Mat3& R_21, const Vec3& t_21);

// The four (R_21, t_21) of an essential matrix, t unit: (Ra, t), (Ra, -t), (Rb, t), (Rb, -t).
void decompose_essential(const Mat3& E_21, std::array<Mat3, 4>* R_21, std::array<Vec3, 4>* t_21);

// The solutions of a calibrated homography A_21 = K^-1 H_21 K (any scale) by Faugeras' method:
// for each, A_21 is proportional to R_21 + t_21 n^T, with n the plane's unit normal in camera 1
// and t_21 scaled by the inverse plane distance (n^T p_1 = d for the plane's points). The eight
// come in pairs (R, t, n), (R, -t, -n) that give the same homography; cheirality decides between
// them. Returns the count (8), or 0 when two singular values of A_21 coincide to 1e-5 (pure
// rotation or a degenerate homography: the decomposition is not unique).
int decompose_homography(const Mat3& A_21, std::array<Mat3, 8>* R_21, std::array<Vec3, 8>* t_21,
                         std::array<Vec3, 8>* n_1);

enum class TwoViewModel { kNone, kHomography, kFundamental };
const char* to_string(TwoViewModel m);

enum class TwoViewFailure {
  kNone,
  kInvalidInput,        // sizes differ, a coordinate is not finite, bad intrinsics or parameters
  kTooFewMatches,       // fewer than 8 matches
  kDegenerate,          // neither RANSAC found a model with enough inliers, or no decomposition
  kLowParallax,         // the winning candidate's parallax is below min_parallax_deg
  kAmbiguous,           // a second candidate is nearly as good as the best
  kTooFewTriangulated,  // the best candidate explains too few of the model's inliers
};
const char* to_string(TwoViewFailure f);

struct TwoViewParams {
  double sigma_px = 1.0;  // keypoint noise (level 0 of the pyramid)
  // Seed, confidence, iteration cap (both models). The cap is 500, not ORB-SLAM's 200: with
  // 1 px noise the gates accept about 80 % of the true matches, so 30 % outliers leave an
  // observed inlier ratio near 0.57, for which 99 % confidence needs 416 samples of 8 (and on
  // the synthetic scenes 200 left one seed in three with a coarse model). The adaptive count
  // stops earlier on cleaner data.
  RansacParams ransac = {0, 0.99, 500, 1};
  double h_ratio_threshold = 0.40;
  double min_parallax_deg = 1.0;
  int min_triangulated = 50;
  double min_good_ratio = 0.9;
  double clear_winner_ratio_f = 0.7;
  double clear_winner_ratio_h = 0.75;
  bool refine_on_inliers = true;  // refit each RANSAC winner on all its inliers
  // F path: Gauss-Newton on the Sampson error over the winner's valid points (kept when it
  // keeps at least as many good points).
  bool refine_pose = true;
};

// kInvalidArgument naming the first field out of range.
Status validate(const TwoViewParams& p);

struct TwoViewResult {
  TwoViewModel model = TwoViewModel::kNone;
  TwoViewFailure failure = TwoViewFailure::kNone;
  Mat3 R_21 = Mat3::Identity();
  Vec3 t_21 = Vec3::Zero();          // unit
  Mat3 F_21 = Mat3::Zero();          // best fundamental matrix (when its RANSAC succeeded)
  Mat3 H_21 = Mat3::Zero();          // best homography (when its RANSAC succeeded)
  double score_f = 0.0, score_h = 0.0;
  double ratio_h = 0.0;              // SH / (SH + SF)
  int inliers_f = 0, inliers_h = 0;
  RansacStats ransac_f, ransac_h;
  std::vector<std::uint8_t> inlier_mask;  // per match: inlier of the chosen model
  // Candidates of the chosen model's decomposition: good-point counts, in decomposition order.
  int candidates = 0;
  std::array<int, 8> candidate_good{};
  int best_candidate = -1;
  double parallax_deg = 0.0;         // median parallax of the winner's valid points
  // Per match (size of the input): triangulated in camera 1 at the scale of the unit t_21,
  // meaningful where valid[i] is 1 (good and parallax >= kPointMinParallaxDeg).
  std::vector<Vec3> points_1;
  std::vector<std::uint8_t> valid;
  int num_valid = 0;
};

// One answer of estimate_essential_hypotheses (essential.h).
struct EssentialHypothesis {
  Mat3 F_21 = Mat3::Zero();  // pixels, unit Frobenius norm
  double score = 0.0;        // score_fundamental at params.sigma_px
  int inliers = 0;
};

// Buffers reused between calls (see the top of the file).
struct TwoViewScratch {
  RansacScratch ransac;
  std::vector<Vec2> n1, n2;               // Hartley-normalised pixels
  std::vector<Vec2> r1, r2;               // normalised image-plane coordinates (K^-1 x)
  std::vector<std::uint8_t> mask_f, mask_h, mask_tmp;
  std::vector<Vec3> points_tmp;
  std::vector<std::uint8_t> valid_tmp;
  std::vector<double> parallax_tmp, parallax_best;
  std::vector<EssentialHypothesis> hypotheses_tmp;  // estimate_essential_hypotheses
};

// The RANSAC estimations alone (what reconstruct_two_view runs). x1 and x2 have n entries;
// kInvalidArgument for n < 8 or non-finite input, kNotFound when no model reaches 8 inliers.
Status estimate_fundamental(const Vec2* x1, const Vec2* x2, int n, const TwoViewParams& params, Mat3* F_21,
                            std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch);
Status estimate_homography(const Vec2* x1, const Vec2* x2, int n, const TwoViewParams& params, Mat3* H_21,
                           std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch);

// Estimates both models, picks one, decomposes it and checks the candidates (top of file).
// `pinhole` is the ideal camera of the undistorted pixels: its distortion must be all zero.
Status reconstruct_two_view(const std::vector<Vec2>& x1_px, const std::vector<Vec2>& x2_px,
                            const CameraIntrinsics& pinhole, const TwoViewParams& params, TwoViewResult* result,
                            TwoViewScratch& scratch);

// The same decomposition and acceptance rules for a fundamental matrix the caller already has
// (e.g. a hypothesis being verified on its guided matches): F_21 is scored on the matches for
// its inliers, no RANSAC runs and no homography is considered. kInvalidArgument for a zero or
// non-finite F_21; otherwise as reconstruct_two_view.
Status reconstruct_two_view_from(const Mat3& F_21, const std::vector<Vec2>& x1_px, const std::vector<Vec2>& x2_px,
                                 const CameraIntrinsics& pinhole, const TwoViewParams& params, TwoViewResult* result,
                                 TwoViewScratch& scratch);

}  // namespace ale::geometry
