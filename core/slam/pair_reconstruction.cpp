#include "core/slam/pair_reconstruction.h"

#include <algorithm>
#include <string>

namespace ale::slam {
namespace {

using geometry::Mat3;
using geometry::Vec2;

void pixels_of(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<std::pair<int, int>>& pairs,
               std::vector<Vec2>& x1, std::vector<Vec2>& x2) {
  x1.resize(pairs.size());
  x2.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const map::KeyframeFeature& a = f1.features[pairs[k].first];
    const map::KeyframeFeature& b = f2.features[pairs[k].second];
    x1[k] = Vec2(a.u, a.v);
    x2[k] = Vec2(b.u, b.v);
  }
}

int support_of(const geometry::TwoViewResult& r) {
  return r.best_candidate >= 0 ? r.candidate_good[static_cast<std::size_t>(r.best_candidate)] : 0;
}

}  // namespace

Status validate(const PairReconstructionParams& p) {
  ALE_RETURN_IF_ERROR(geometry::validate(p.two_view));
  if (p.guided_rounds < 1) return invalid_argument("pair reconstruction: guided_rounds must be >= 1");
  if (!(p.ambiguity_separation >= 0.0)) return invalid_argument("pair reconstruction: ambiguity_separation must be >= 0");
  if (!(p.first_band_scale >= 1.0)) return invalid_argument("pair reconstruction: first_band_scale must be >= 1");
  if (!(p.clear_winner_ratio > 0.0 && p.clear_winner_ratio <= 1.0))
    return invalid_argument("pair reconstruction: clear_winner_ratio must be in (0, 1]");
  if (!(p.band.sigma_px > 0.0) || !(p.band.chi2 > 0.0) || p.band.max_level_diff < 0 || !(p.band.scale_factor >= 1.0f))
    return invalid_argument("pair reconstruction: band sigma_px and chi2 must be > 0, max_level_diff >= 0, "
                            "scale_factor >= 1");
  if (p.hypotheses.max_hypotheses < 1 || p.hypotheses.candidates_per_hypothesis < 1 ||
      !(p.hypotheses.min_separation >= 0.0))
    return invalid_argument("pair reconstruction: hypotheses need max_hypotheses and candidates_per_hypothesis >= 1, "
                            "min_separation >= 0");
  return Status::ok_status();
}

Status reconstruct_pair(const FrameFeatures& f1, const FrameFeatures& f2, const geometry::CameraIntrinsics& pinhole,
                        const PairReconstructionParams& params, PairReconstruction* result, PairScratch& scratch) {
  PairReconstruction& r = *result;
  r.prior_free_matches = 0;
  r.hypotheses.clear();
  r.chosen = -1;
  r.support = r.runner_up_support = 0;
  r.matches.clear();
  ALE_RETURN_IF_ERROR(validate(params));
  Mat3 K = Mat3::Identity();
  K(0, 0) = pinhole.fx;
  K(1, 1) = pinhole.fy;
  K(0, 2) = pinhole.cx;
  K(1, 2) = pinhole.cy;

  // One list of the descriptor pairs that matter, for both searches (match/pairs.h).
  PairSearchParams widest = params.match;
  if (params.band.match.max_distance / params.band.match.ratio > widest.max_distance / widest.ratio) widest = params.band.match;
  near_descriptor_pairs(f1, f2, widest, scratch.near_pairs);
  r.prior_free_matches = match_all_pairs(f1, f2, scratch.near_pairs, params.match, scratch.pairs, scratch.matcher);
  pixels_of(f1, f2, scratch.pairs, scratch.x1, scratch.x2);
  // Every sampled model is scored by the matches along its own epipolar lines.
  const auto band_count = [&](const Mat3& F) {
    return static_cast<double>(
        match_along_epipolar_lines(f1, f2, scratch.near_pairs, F, params.band, scratch.band_pairs, scratch.matcher));
  };
  const Status hs = geometry::estimate_essential_hypotheses(
      scratch.x1.data(), scratch.x2.data(), static_cast<int>(scratch.x1.size()), K, params.two_view, params.hypotheses,
      &scratch.hypotheses, scratch.two_view, band_count);
  if (!hs.ok())
    return Status(hs.code() == StatusCode::kInvalidArgument && scratch.x1.size() >= geometry::kTwoViewSampleSize
                      ? hs.code()
                      : StatusCode::kNotFound,
                  std::to_string(r.prior_free_matches) + " prior-free matches: " + hs.message());

  scratch.verified_F.clear();
  for (const geometry::EssentialHypothesis& h : scratch.hypotheses) {
    PairHypothesisFigures fig;
    fig.ransac_score = h.score;
    Mat3 F = h.F_21;
    bool reconstructed = false;
    for (int round = 0; round < params.guided_rounds; ++round) {
      EpipolarBandParams band = params.band;
      band.match.rotation.enabled = params.verify_check_orientation;
      if (round == 0) band.sigma_px *= params.first_band_scale;
      match_along_epipolar_lines(f1, f2, scratch.near_pairs, F, band, scratch.pairs, scratch.matcher);
      pixels_of(f1, f2, scratch.pairs, scratch.x1, scratch.x2);
      const Status s = geometry::reconstruct_two_view_from(F, scratch.x1, scratch.x2, pinhole, params.two_view,
                                                           &scratch.trial, scratch.two_view);
      fig.guided_matches = static_cast<int>(scratch.pairs.size());
      fig.failure = scratch.trial.failure;
      if (!s.ok()) {
        if (s.code() == StatusCode::kInvalidArgument && scratch.trial.failure == geometry::TwoViewFailure::kInvalidInput)
          return s;
        reconstructed = false;
        break;
      }
      reconstructed = true;
      F = geometry::fundamental_from_pose(pinhole, scratch.trial.R_21, scratch.trial.t_21);
    }
    if (reconstructed) {
      fig.support = support_of(scratch.trial);
      fig.R_21 = scratch.trial.R_21;
      fig.t_21 = scratch.trial.t_21;
    }
    const int index = static_cast<int>(r.hypotheses.size());
    if (scratch.supporters.size() <= static_cast<std::size_t>(index)) scratch.supporters.resize(static_cast<std::size_t>(index) + 1);
    std::vector<int>& sup = scratch.supporters[static_cast<std::size_t>(index)];
    sup.clear();
    if (reconstructed)
      for (std::size_t k = 0; k < scratch.pairs.size(); ++k)
        if (scratch.trial.inlier_mask[k]) sup.push_back(scratch.pairs[k].first);
    std::sort(sup.begin(), sup.end());
    r.hypotheses.push_back(fig);
    scratch.verified_F.push_back(reconstructed ? F : Mat3::Zero());
    if (reconstructed && fig.support > r.support) {
      r.support = fig.support;
      r.chosen = index;
      std::swap(r.two_view, scratch.trial);
      r.matches.swap(scratch.pairs);
    }
  }
  if (r.chosen < 0)
    return not_found("none of " + std::to_string(scratch.hypotheses.size()) + " hypotheses from " +
                     std::to_string(r.prior_free_matches) + " prior-free matches reconstructs");
  const Mat3& F_chosen = scratch.verified_F[static_cast<std::size_t>(r.chosen)];
  for (std::size_t k = 0; k < r.hypotheses.size(); ++k) {
    if (static_cast<int>(k) == r.chosen || r.hypotheses[k].support == 0) continue;
    if (geometry::essential_distance(scratch.verified_F[k], F_chosen, K) < params.ambiguity_separation) continue;
    r.runner_up_support = std::max(r.runner_up_support, r.hypotheses[k].support);
    if (params.ambiguity_chi2 > 0.0) {
      const std::vector<int>& a = scratch.supporters[static_cast<std::size_t>(r.chosen)];
      const std::vector<int>& b = scratch.supporters[k];
      std::size_t ia = 0, ib = 0;
      int only_a = 0, only_b = 0;
      while (ia < a.size() || ib < b.size()) {
        if (ib == b.size() || (ia < a.size() && a[ia] < b[ib])) ++only_a, ++ia;
        else if (ia == a.size() || b[ib] < a[ia]) ++only_b, ++ib;
        else ++ia, ++ib;
      }
      const double d = only_a - only_b;
      if (only_a + only_b == 0 || d <= 0.0 || d * d < params.ambiguity_chi2 * (only_a + only_b))
        return not_found("ambiguous: a second verified pose: " + std::to_string(only_a) + " keypoints support only the best, " +
                         std::to_string(only_b) + " only it");
    }
  }
  if (params.ambiguity_chi2 <= 0.0 && r.runner_up_support > params.clear_winner_ratio * r.support)
    return not_found("ambiguous: a second verified pose has " + std::to_string(r.runner_up_support) +
                     " supporting matches, the best " + std::to_string(r.support));
  if (params.final_estimate) {
    EpipolarBandParams band = params.band;
    band.match.rotation.enabled = params.final_check_orientation;
    match_along_epipolar_lines(f1, f2, scratch.near_pairs, F_chosen, band, scratch.pairs, scratch.matcher);
    pixels_of(f1, f2, scratch.pairs, scratch.x1, scratch.x2);
    r.matches.swap(scratch.pairs);
    return geometry::reconstruct_two_view(scratch.x1, scratch.x2, pinhole, params.two_view, &r.two_view,
                                          scratch.two_view);
  }
  return Status::ok_status();
}

}  // namespace ale::slam
