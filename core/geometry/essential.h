// The calibrated five-point essential matrix (Stewenius, Engels and Nister 2006: the Groebner
// basis / action matrix form of Nister's 2004 solver) and its RANSAC for two-view
// initialisation.
//
// Why: the 8-point F has 7 degrees of freedom for a 5-dof relative pose; on the largely planar
// EuRoC keyframe pairs (100-250 matches) it overfits the noise and its pose errs by up to
// 3 deg. The five-point samples only ever propose true essential matrices.
//
// Method: the 5 epipolar rows leave a 4-dimensional null space E = x X + y Y + z Z + W (the
// scale fixed by W's coefficient 1). det(E) = 0 and 2 E E^T E - tr(E E^T) E = 0 give 10 cubics
// in the 20 monomials of degree <= 3 in (x, y, z); Gauss-Jordan elimination of the 10 cubic
// monomials leaves the multiplication-by-x action matrix on the quotient basis {x^2, xy, xz,
// y^2, yz, z^2, x, y, z, 1}, whose real eigenvectors give the (up to 10) solutions.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/geometry/two_view.h"

namespace ale::geometry {

constexpr int kEssentialSampleSize = 5;
constexpr int kEssentialMaxSolutions = 10;

// Essential matrices E_21 (q2^T E_21 q1 = 0, unit Frobenius norm, sign arbitrary) from five
// correspondences in normalised image-plane coordinates (K^-1 x). Returns how many (<= 10);
// 0 when a coordinate is not finite or the five do not give a 4-dimensional null space or an
// invertible elimination (e.g. repeated points).
int essential_5point(const Vec2* q1, const Vec2* q2, std::array<Mat3, kEssentialMaxSolutions>* E_21);

// The RANSAC of reconstruct_two_view's general model: five-point samples on K^-1 x, each
// solution scored as the fundamental matrix F_21 = K^-T E K^-1 by score_fundamental (so the
// H/F selection compares like with like), every sample up to the iteration cap, then local
// refits on the essential manifold (Gauss-Newton on the Sampson error of (R, t) over the
// matches within loosening gates, kept while the score improves). *F_21 is in pixels, unit
// Frobenius norm. Errors as estimate_fundamental.
Status estimate_essential(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const TwoViewParams& params,
                          Mat3* F_21, std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch);

// Distance between the essential matrices of two pixel F's of camera K: min |Ea -+ Eb|_F over
// unit-norm Ea, Eb. For small differences it is about the rotation angle and the change of the
// translation direction in radians, each weighted by about 1/sqrt(2).
double essential_distance(const Mat3& F_a, const Mat3& F_b, const Mat3& K);

// Several distinct answers of the five-point RANSAC, for a caller that can verify each one
// against more evidence than the matches (e.g. guided matching along each one's epipolar lines:
// repeated structure, matched to the wrong copy without a motion prior, can give a wrong
// essential matrix a higher score than the true one, which is then only the second or third
// best). The samples are the same as estimate_essential's (same seed, every sample up to the
// cap); of the models within min_separation (essential_distance) of each other the best-scoring
// one is kept, max_hypotheses * candidates_per_hypothesis of them, each is locally refined as in
// estimate_essential, and the best max_hypotheses that are min_separation apart after the
// refinement are returned, best score first (estimate_essential's answer is among the refined
// models, so the first scores at least as well; another raw model can refine to a better one). Errors as estimate_essential; kInvalidArgument for parameters out of range.
struct EssentialHypothesesParams {
  int max_hypotheses = 6;
  double min_separation = 0.035;  // about 3 deg of rotation or translation direction
  int candidates_per_hypothesis = 4;
  // With a rescore: only models whose own score is at least this share of the best own score
  // are rescored (the rescore is the expensive part; the true model's own score is lowered by
  // the wrong matches, not by much: 3 % below the wrong one on EuRoC V1_01 57-58).
  double rescore_min_share = 0.8;
};
// `rescore`, when given, replaces score_fundamental as the score of every model (higher is
// better; e.g. the number of matches a guided search finds along its epipolar lines over all
// keypoints, which the matches the samples come from cannot bias); the pool is then chosen by
// it and not locally refined (the refinement climbs score_fundamental), and `score` holds it.
Status estimate_essential_hypotheses(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const TwoViewParams& params,
                                     const EssentialHypothesesParams& hypotheses, std::vector<EssentialHypothesis>* out,
                                     TwoViewScratch& scratch,
                                     const std::function<double(const Mat3& F_21)>& rescore = nullptr);

}  // namespace ale::geometry
