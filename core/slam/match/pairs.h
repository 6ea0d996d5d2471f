// Matching two frames without a pose (ORB-SLAM's SearchForInitialization, and the prior-free
// matching of two-view reconstruction, pair_reconstruction.h): within a window around predicted
// positions, between all keypoints, or along the epipolar lines of a candidate geometry.
#pragma once

#include <utility>
#include <vector>

#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"
#include "core/slam/match/base.h"

namespace ale::slam {

// Matches keypoints of f1 (up to initialization_max_level) to keypoints of f2 within `window_px` of predicted[i] (the
// position of f1's keypoint i in f2, e.g. its last match), best distance <= th_low, ratio
// ratio_initialization, one-to-one (a better match takes over a taken f2 keypoint).
// matches12[i] = index in f2 or -1. Returns the number of matches. predicted.size() == f1.count.
int search_for_initialization(const MatchContext& ctx, const FrameFeatures& f1, const FrameFeatures& f2,
                              const std::vector<std::pair<float, float>>& predicted, float window_px,
                              std::vector<int>& matches12);

// Matching two frames without a pose: for two-view reconstruction (no motion prior) and for
// verifying a candidate epipolar geometry. Keypoint i of f1 and j of f2 are candidates of each
// other when both positions are finite and the search's own rule admits them; among its
// candidates, i takes its nearest descriptor when that is within max_distance and below ratio
// times the second nearest (an equal second fails), and, when mutual, is itself the nearest of
// j's candidates in f1; then the rotation check. Ties go to the lower index. pairs receives
// (index in f1, index in f2) in f1 order; returns their number. Cost: one Hamming distance per
// candidate pair.
struct PairSearchParams {
  int max_distance = 64;  // of 256 bits (between ORB-SLAM's th_low 50 and th_high 100)
  double ratio = 0.75;
  bool mutual = true;
  RotationCheck rotation;  // the matcher's own (MatcherParams::rotation), not a copy of its fields
};

// Every keypoint of f2 is a candidate of every keypoint of f1 (brute force). Without a motion
// prior this is where repeated structure (a radiator's fins, tiles) matches the wrong copy: the
// ratio and mutual tests and the rotation check remove only part of it.
int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairSearchParams& params,
                    std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch);

// The keypoint pairs with finite positions and Hamming distance <= max_distance / ratio, in
// (i1, i2) order: the only ones that can change a pair search's result (a farther second
// nearest cannot fail the ratio test of a match within max_distance, nor be anyone's nearest
// within it). The searches below given this list return what they return without it and cost
// one visit per listed pair instead of one Hamming distance per keypoint pair, which lets a
// caller score many epipolar geometries (a few thousand pairs of 1000 x 1000 keypoints).
void near_descriptor_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairSearchParams& params,
                           std::vector<DescriptorPair>& near_pairs);
int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<DescriptorPair>& near_pairs,
                    const PairSearchParams& params, std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch);

// Candidates lie in the band of an epipolar geometry F_21 (x2^T F_21 x1 = 0, undistorted
// pixels): the squared distance of j to i's epipolar line in f2 within chi2 sigma^2, sigma the
// level-0 noise times the scale of the coarser of the two levels, and levels at most
// max_level_diff apart (ORB-SLAM's search for triangulation without the epipole exclusion).
// The ratio test runs among the band's candidates: a keypoint whose band crosses several
// copies of a repeated pattern is dropped, and a wrong copy outside the band neither matches
// nor competes.
struct EpipolarBandParams {
  PairSearchParams match;
  double sigma_px = 1.0;
  double chi2 = geometry::kChi2OneDof95;
  int max_level_diff = 1;
  float scale_factor = 1.2f;
};
int match_along_epipolar_lines(const FrameFeatures& f1, const FrameFeatures& f2, const geometry::Mat3& F_21,
                               const EpipolarBandParams& params, std::vector<std::pair<int, int>>& pairs,
                               MatcherScratch& scratch);
int match_along_epipolar_lines(const FrameFeatures& f1, const FrameFeatures& f2,
                               const std::vector<DescriptorPair>& near_pairs, const geometry::Mat3& F_21,
                               const EpipolarBandParams& params, std::vector<std::pair<int, int>>& pairs,
                               MatcherScratch& scratch);

}  // namespace ale::slam
