// Descriptor matching for the SLAM core (spec section 7; ORB-SLAM's ORBmatcher without
// bag-of-words): the windowed search that initialisation uses, search by projection of
// landmarks (local map) and of the last frame's matched landmarks, and the epipolar-constrained
// search between two keyframes for triangulation. Every search applies the Hamming gates, the
// ratio test where ORB-SLAM does and, optionally, the rotation-consistency check (a histogram of
// orientation differences; matches outside its three strongest bins are dropped). Results
// depend only on the inputs (ties go to the lower index), so replays are deterministic.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/slam/feature_grid.h"

namespace ale::slam {

struct MatcherParams {
  int th_high = 100;             // Hamming gate for projection searches
  int th_low = 50;               // Hamming gate for initialisation and triangulation
  float ratio_initialization = 0.9f;
  float ratio_projection = 0.8f;
  // Triangulation search: the best candidate along the epipolar line must beat, by this ratio,
  // every candidate farther than ratio_separation x its level's scale from it (another place on
  // the line, so another depth; nearer ones are the same corner on a neighbouring level).
  // ORB-SLAM has no ratio test here because bag-of-words already narrows the candidates; along
  // the whole line repeated texture (floor planks, stripes) otherwise gives wrong depths: on the
  // rendered loops a quarter of new floor points were more than 30 % off. 1 disables it.
  float ratio_triangulation = 0.8f;
  float ratio_separation = 3.0f;
  // Keypoints of the reference frame up to this level take part in the initialisation search
  // (ORB-SLAM: level 0 only; all levels here: on the 20 TUM fr2_desk frames level 0 alone gives
  // 70-110 matches between frames and never initialises, all levels 390-460); candidates are on
  // the keypoint's level +-1.
  int initialization_max_level = 15;
  bool check_orientation = true;
  int orientation_bins = 30;
};

// A frame's features (undistorted pixels) and their grid; `landmarks` (count entries, invalid
// where none) are the landmarks matched to each keypoint.
struct FrameFeatures {
  const map::KeyframeFeature* features = nullptr;
  int count = 0;
  const FeatureGrid* grid = nullptr;
};

// The nearest and second-nearest Hamming distance seen for one keypoint, and the nearest's index.
struct Nearest2 {
  int index = -1;
  int best = 1 << 30;
  int second = 1 << 30;
};

// A keypoint pair (f1, f2) whose descriptors are close enough to matter to a pair search.
struct DescriptorPair {
  int i1 = 0;
  int i2 = 0;
  int distance = 0;
};

// Reused buffers of the searches (no allocation once warm).
struct MatcherScratch {
  std::vector<DescriptorPair> near_pairs;
  std::vector<Nearest2> nearest12, nearest21;
  std::vector<float> line_sigma;
  std::vector<geometry::Vec3> lines;
  std::vector<int> candidates;
  std::vector<int> best_dist;
  std::vector<int> owner;
  std::vector<std::vector<int>> bins;
  std::vector<int> matched;
  std::vector<std::uint32_t> seen;
  std::vector<std::pair<int, int>> scored;  // (keypoint, Hamming distance) along one epipolar line
};

// Matches keypoints of f1 (up to initialization_max_level) to keypoints of f2 within `window_px` of predicted[i] (the
// position of f1's keypoint i in f2, e.g. its last match), best distance <= th_low, ratio
// ratio_initialization, one-to-one (a better match takes over a taken f2 keypoint).
// matches12[i] = index in f2 or -1. Returns the number of matches. predicted.size() == f1.count.
int search_for_initialization(const FrameFeatures& f1, const FrameFeatures& f2,
                              const std::vector<std::pair<float, float>>& predicted, float window_px,
                              const MatcherParams& params, std::vector<int>& matches12, MatcherScratch& scratch);

// Projects the candidate landmarks into a frame at pose T_cw through `pinhole` (the camera of
// the undistorted keypoints) and matches each, where it is in the image, inside its
// scale-invariance distance range and seen within 60 deg of its mean viewing direction, to the
// best free keypoint within radius_factor * scale(predicted level) (x2.5, or x4 at oblique views)
// on the predicted level or the one below, Hamming <= th_high, ratio ratio_projection when the
// two best are on one level. frame_landmarks (frame.count entries) receives the landmark of each
// newly matched keypoint; keypoints that already have one are not searched. Candidates already
// matched in frame_landmarks are skipped. in_view, when given, receives every candidate that
// passed the view checks (matched or not: the landmarks' "visible" counters). Returns the number
// of new matches.
int search_by_projection(const FrameFeatures& frame, const geometry::SE3& T_cw, const geometry::Camera& pinhole,
                         const map::MapStore& map, const std::vector<map::LandmarkId>& candidates,
                         const ScalePyramid& pyramid, float radius_factor, const MatcherParams& params,
                         std::vector<map::LandmarkId>& frame_landmarks, MatcherScratch& scratch,
                         std::vector<map::LandmarkId>* in_view = nullptr);

// Projects the landmarks matched in the last frame (last_landmarks, last.count entries) into
// the current frame at T_cw and matches each to a free keypoint within radius_px *
// scale(last level), on that level +-1, Hamming <= th_high, with the rotation check.
// current_landmarks (current.count entries) receives the matches. Returns their number.
int search_by_projection(const FrameFeatures& current, const geometry::SE3& T_cw, const FrameFeatures& last,
                         const std::vector<map::LandmarkId>& last_landmarks, const map::MapStore& map,
                         const geometry::Camera& pinhole, const ScalePyramid& pyramid, float radius_px,
                         const MatcherParams& params, std::vector<map::LandmarkId>& current_landmarks,
                         MatcherScratch& scratch);

// Pairs of keypoints of two keyframes that have no landmark yet (kf_landmarks* entries invalid)
// and satisfy the epipolar constraint of their poses (squared distance to the epipolar line
// below 3.84 sigma^2 of the second keypoint's level), away from the epipole (100 px scaled by
// level), Hamming <= th_low, clearly better than any candidate elsewhere on the line
// (ratio_triangulation, including keypoints that have a landmark), one-to-one, rotation check.
// The candidates in kf2 are taken from its
// grid cells along the epipolar line, only along the part a point in front of both cameras can
// project to: from the epipole (depth 0 in kf1) to the ray's projection at `max_depth` (depth in
// kf1's camera; 0 or less: to the ray's vanishing point). pairs receives (index in kf1, index in
// kf2) in kf1 order.
int search_for_triangulation(const FrameFeatures& kf1, const geometry::SE3& T1w, const map::LandmarkId* kf1_landmarks,
                             const FrameFeatures& kf2, const geometry::SE3& T2w, const map::LandmarkId* kf2_landmarks,
                             const geometry::Camera& pinhole, const ScalePyramid& pyramid, const MatcherParams& params,
                             std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch, double max_depth = 0.0);

// Matching two frames without a pose: for two-view reconstruction (no motion prior) and for
// verifying a candidate epipolar geometry. Keypoint i of f1 and j of f2 are candidates of each
// other when both positions are finite and the search's own rule admits them; among its
// candidates, i takes its nearest descriptor when that is within max_distance and below ratio
// times the second nearest (an equal second fails), and, when mutual, is itself the nearest of
// j's candidates in f1; then the rotation check. Ties go to the lower index. pairs receives
// (index in f1, index in f2) in f1 order; returns their number. Cost: one Hamming distance per
// candidate pair.
struct PairMatchParams {
  int max_distance = 64;  // of 256 bits (between ORB-SLAM's th_low 50 and th_high 100)
  double ratio = 0.75;
  bool mutual = true;
  bool check_orientation = true;
  int orientation_bins = 30;
};

// Every keypoint of f2 is a candidate of every keypoint of f1 (brute force). Without a motion
// prior this is where repeated structure (a radiator's fins, tiles) matches the wrong copy: the
// ratio and mutual tests and the rotation check remove only part of it.
int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairMatchParams& params,
                    std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch);

// The keypoint pairs with finite positions and Hamming distance <= max_distance / ratio, in
// (i1, i2) order: the only ones that can change a pair search's result (a farther second
// nearest cannot fail the ratio test of a match within max_distance, nor be anyone's nearest
// within it). The searches below given this list return what they return without it and cost
// one visit per listed pair instead of one Hamming distance per keypoint pair, which lets a
// caller score many epipolar geometries (a few thousand pairs of 1000 x 1000 keypoints).
void near_descriptor_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairMatchParams& params,
                           std::vector<DescriptorPair>& near_pairs);
int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<DescriptorPair>& near_pairs,
                    const PairMatchParams& params, std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch);

// Candidates lie in the band of an epipolar geometry F_21 (x2^T F_21 x1 = 0, undistorted
// pixels): the squared distance of j to i's epipolar line in f2 within chi2 sigma^2, sigma the
// level-0 noise times the scale of the coarser of the two levels, and levels at most
// max_level_diff apart (ORB-SLAM's search for triangulation without the epipole exclusion).
// The ratio test runs among the band's candidates: a keypoint whose band crosses several
// copies of a repeated pattern is dropped, and a wrong copy outside the band neither matches
// nor competes.
struct EpipolarBandParams {
  PairMatchParams match;
  double sigma_px = 1.0;
  double chi2 = 3.841;  // 1-dof 95 %
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
