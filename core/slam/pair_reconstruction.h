// Two-view reconstruction of two frames that have no motion prior (keyframes far apart, a
// relocalised frame, a map-merging check): prior-free matches, several distinct essential
// hypotheses from them, each verified by guided matching along its own epipolar lines, and the
// hypothesis the most matches support wins.
//
// Why: brute-force matches over repeated structure (a radiator's fins, tiled panels,
// checkerboards) pair the wrong copies of a pattern consistently enough that a wrong essential
// matrix whose epipolar lines run along the pattern outscores the true one on those matches
// (EuRoC V1_01 keyframes 57-58: 16 such matches share one vertical shift). The true pose is
// still among the five-point RANSAC's good distinct answers. Guided matching over all
// keypoints tells them apart: along the true lines each pattern copy has one match in the band;
// along lines that run with the pattern the band holds several copies, the ratio test inside
// the band drops them, and the wrong hypothesis keeps fewer matches.
//
// Steps:
// 1. match_all_pairs (match/pairs.h): mutual nearest neighbours, ratio, rotation check.
// 2. estimate_essential_hypotheses (essential.h) on them, every model (whose own score is
//    near the best) rescored by its match count along its epipolar lines over all keypoints:
//    up to `hypotheses.max_hypotheses` distinct ones.
// 3. Each hypothesis, `guided_rounds` times: match_along_epipolar_lines under its current F
//    (the first round's band first_band_scale wider), reconstruct_two_view_from on those
//    matches (decomposition, cheirality, Sampson refinement of that F, no RANSAC), its pose's F
//    for the next round. Its support is the last round's good-point count (matches triangulated
//    in front of both cameras within the reprojection gate, two_view.h).
// 4. The hypothesis with most support wins. A second verified pose at least ambiguity_separation
//    away makes the pair ambiguous (kNotFound) unless McNemar's test on the keypoints of f1 that
//    support only one of the two says the winner's lead is significant (ambiguity_chi2).
// 5. (final_estimate) The winner's band matches, taken without the rotation check, are
//    reconstructed afresh by reconstruct_two_view (RANSAC, model selection, refinement), as the
//    matches of a known geometry would be; its status is the pair's. Band matching with the
//    rotation check keeps the matches whose orientation agrees with a slightly wrong pose and
//    can hold the pose there; without it the re-estimate stays within a fraction of a degree of
//    the truth when started from the truth (docs/geometry.md).
//
// Status (docs/geometry.md): on the 68 EuRoC V1_01 keyframe pairs 48 are used, none outside
// 1 deg / 5 deg (rotation median / p90 / max 0.18 / 0.46 / 0.56 deg, translation direction
// 0.90 / 2.09 / 3.85 deg); the other 20 decline, most as ambiguous: no support measure tried
// ranks the true pose above the pattern-aligned ones on those pairs.
#pragma once

#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/essential.h"
#include "core/geometry/two_view.h"
#include "core/slam/match/pairs.h"

namespace ale::slam {

struct PairReconstructionParams {
  PairSearchParams match;           // step 1
  EpipolarBandParams band;          // step 3 (its sigma_px should be two_view.sigma_px)
  geometry::TwoViewParams two_view;
  geometry::EssentialHypothesesParams hypotheses;
  int guided_rounds = 3;
  // The first round's band is this many times wider (in sigma): a hypothesis from the
  // prior-free matches can be a few degrees off, and a band at the final width would keep only
  // the matches that agree with its error.
  double first_band_scale = 1.0;
  // Ambiguity (step 4) considers only verified poses at least ambiguity_separation
  // (essential_distance, about 8 deg) from the winner: closer poses are one answer within its
  // noise, not an alternative. With ambiguity_chi2 > 0 the test is McNemar's: with b keypoints
  // of f1 supporting only the winner and c only the other pose, the pair is ambiguous when
  // b <= c or (b - c)^2 / (b + c) < ambiguity_chi2 (3.841: 95 %, 1 dof). With ambiguity_chi2 <= 0
  // it is ambiguous when the other pose has more than clear_winner_ratio of the winner's support.
  double clear_winner_ratio = 0.95;
  double ambiguity_separation = 0.1;
  double ambiguity_chi2 = geometry::kChi2OneDof95;
  bool verify_check_orientation = true;  // the rotation check in step 3's bands
  bool final_estimate = true;            // step 5; false returns step 3's reconstruction
  bool final_check_orientation = false;  // the rotation check in step 5's band
};

// kInvalidArgument naming the first field out of range.
Status validate(const PairReconstructionParams& p);

struct PairHypothesisFigures {
  double ransac_score = 0.0;  // of the prior-free matches (score_fundamental)
  int guided_matches = 0;     // of the last round
  int support = 0;            // 0 when its reconstruction declined
  geometry::TwoViewFailure failure = geometry::TwoViewFailure::kNone;
  geometry::Mat3 R_21 = geometry::Mat3::Identity();  // the verified pose (when support > 0)
  geometry::Vec3 t_21 = geometry::Vec3::Zero();
};

struct PairReconstruction {
  int prior_free_matches = 0;
  std::vector<PairHypothesisFigures> hypotheses;  // in RANSAC score order
  int chosen = -1;
  int support = 0;
  int runner_up_support = 0;  // best support of a verified pose min_separation from the chosen one
  geometry::TwoViewResult two_view;           // the chosen hypothesis's last reconstruction
  std::vector<std::pair<int, int>> matches;   // its input, (index in f1, index in f2)
};

struct PairScratch {
  MatcherScratch matcher;
  geometry::TwoViewScratch two_view;
  std::vector<geometry::EssentialHypothesis> hypotheses;
  std::vector<DescriptorPair> near_pairs;
  std::vector<std::pair<int, int>> pairs, band_pairs;
  std::vector<geometry::Vec2> x1, x2;
  geometry::TwoViewResult trial;
  std::vector<geometry::Mat3> verified_F;
  std::vector<std::vector<int>> supporters;  // per hypothesis: f1 keypoints of its inliers, sorted
};

// f1, f2: undistorted keypoints in the pixels of the ideal pinhole `pinhole` (positions that are
// not finite never match). On success result->two_view holds the pose (R_21, t_21 unit) and the
// points of result->matches. kInvalidArgument for bad parameters or intrinsics; kNotFound (with
// the figures) when there are too few prior-free matches, no hypothesis reconstructs, or the
// pair is ambiguous.
Status reconstruct_pair(const FrameFeatures& f1, const FrameFeatures& f2, const geometry::CameraIntrinsics& pinhole,
                        const PairReconstructionParams& params, PairReconstruction* result, PairScratch& scratch);

}  // namespace ale::slam
