#include "core/slam/relocaliser.h"

#include <algorithm>

#include "core/features/brief.h"
#include "core/slam/local_map.h"
#include "core/slam/match/bow.h"
#include "core/slam/match/projection.h"

namespace ale::slam {

Relocaliser::Relocaliser(const RelocaliserParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
                         const MatcherParams& matcher, const PoseRefinerParams& refiner)
    : params_(params), matcher_(matcher), pinhole_(pinhole), pyramid_(pyramid), refiner_(refiner, pinhole) {}

// Each landmark of the keyframe to the frame keypoint nearest its descriptor (Hamming <= th_low,
// ratio to the second nearest), one landmark per keypoint (the nearest wins), then the rotation
// check between the keyframe's and the frame's keypoints. Fills matched_; returns the count.
int Relocaliser::match_keyframe(const Frame& frame, const map::MapStore& map, map::KeyframeId kf) {
  const map::Keyframe* k = map.keyframe(kf);
  const int n = frame.size();
  matched_.assign(static_cast<std::size_t>(n), map::LandmarkId{});
  best_dist_.assign(static_cast<std::size_t>(n), matcher_.th_low + 1);
  if (!k) return 0;
  const map::KeyframeFeature* kf_features = map.features(kf);
  const map::LandmarkId* kf_landmarks = map.keypoint_landmarks(kf);
  matches12_.assign(static_cast<std::size_t>(k->num_features), kNoMatch);
  std::vector<int>& owner = scratch_.owner;  // frame keypoint -> keyframe keypoint
  owner.assign(static_cast<std::size_t>(n), kNoMatch);
  for (int i = 0; i < k->num_features; ++i) {
    if (!map.landmark(kf_landmarks[i])) continue;
    Best2 b;
    for (int j = 0; j < n; ++j) b.offer(features::hamming_distance(kf_features[i].descriptor, frame.features[j].descriptor), j, 0);
    if (b.index == kNoMatch || b.dist > matcher_.th_low) continue;
    if (static_cast<float>(b.dist) >= params_.match_ratio * static_cast<float>(b.dist2)) continue;
    const std::size_t j = static_cast<std::size_t>(b.index);
    if (b.dist >= best_dist_[j]) continue;
    if (owner[j] != kNoMatch) matches12_[static_cast<std::size_t>(owner[j])] = kNoMatch;
    owner[j] = i;
    best_dist_[j] = b.dist;
    matches12_[static_cast<std::size_t>(i)] = b.index;
  }
  if (matcher_.rotation.enabled) {
    const FrameFeatures first{kf_features, k->num_features, nullptr};
    drop_inconsistent_rotations(first, frame.view(), matcher_.rotation.bins, matches12_, rotation_bins_);
  }
  int count = 0;
  for (int i = 0; i < k->num_features; ++i) {
    const int j = matches12_[static_cast<std::size_t>(i)];
    if (j == kNoMatch) continue;
    matched_[static_cast<std::size_t>(j)] = kf_landmarks[i];
    ++count;
  }
  return count;
}

int Relocaliser::try_candidate(Frame& frame, const map::MapStore& map, map::KeyframeId kf,
                                const place::KeyframeDatabase* places, const place::FeatureVector* frame_fv,
                                RelocaliseReport& report) {
  const place::FeatureVector* kf_fv = places && frame_fv ? places->feature_vector(kf) : nullptr;
  int matches = 0;
  if (kf_fv) {
    matched_.assign(static_cast<std::size_t>(frame.size()), map::LandmarkId{});
    matches = search_by_bow(match_context(), {frame.view(), *frame_fv, matched_}, map, kf, *kf_fv);
  } else {
    matches = match_keyframe(frame, map, kf);
  }
  report.matches = std::max(report.matches, matches);
  if (matches < params_.min_matches) return 0;
  ++report.tried;

  points_.clear();
  pixels_.clear();
  sigmas_.clear();
  keypoints_.clear();
  for (int j = 0; j < frame.size(); ++j) {
    const map::Landmark* lm = map.landmark(matched_[static_cast<std::size_t>(j)]);
    if (!lm) continue;
    const map::KeyframeFeature& f = frame.features[static_cast<std::size_t>(j)];
    points_.push_back(lm->p_w);
    pixels_.emplace_back(f.u, f.v);
    sigmas_.push_back(pyramid_.scale[std::clamp<int>(f.level, 0, pyramid_.levels - 1)]);
    keypoints_.push_back(j);
  }
  geometry::PnpParams pnp;
  pnp.ransac.seed = params_.seed;
  pnp.min_inliers = params_.pnp_min_inliers;
  const geometry::PnpInput input{points_.data(), pixels_.data(), sigmas_.data(), static_cast<int>(points_.size())};
  const Status s = geometry::solve_pnp_ransac(pinhole_, input, pnp, &pnp_, pnp_scratch_);
  if (!s.ok() && pnp_.failure != geometry::PnpFailure::kNotConverged) return 0;
  if (pnp_.inlier_count < params_.pnp_min_inliers) return 0;

  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  std::fill(frame.outlier.begin(), frame.outlier.end(), std::uint8_t{0});
  for (std::size_t m = 0; m < keypoints_.size(); ++m) {
    if (pnp_.inliers[m]) frame.landmarks[static_cast<std::size_t>(keypoints_[m])] = matched_[static_cast<std::size_t>(keypoints_[m])];
  }
  frame.T_cw = pnp_.T_cw;
  int inliers = 0;
  if (!refiner_.refine(frame, map, &inliers)) return 0;
  if (inliers < params_.min_inliers) {
    // the candidate's neighbourhood, searched at the refined pose
    neighbourhood_landmarks(map, kf, params_.covisible_per_keyframe, local_);
    search_by_projection(match_context(), {frame.view(), frame.T_cw, frame.landmarks}, map, local_,
                         params_.projection_radius_px);
    if (!refiner_.refine(frame, map, &inliers)) inliers = 0;
  }
  report.inliers = std::max(report.inliers, inliers);
  return inliers;
}

void Relocaliser::Kept::keep(const Frame& frame, map::KeyframeId kf, int n) {
  inliers = n;
  keyframe = kf;
  T_cw = frame.T_cw;
  landmarks.assign(frame.landmarks.begin(), frame.landmarks.end());
  outlier.assign(frame.outlier.begin(), frame.outlier.end());
}

void Relocaliser::Kept::restore(Frame& frame) const {
  frame.T_cw = T_cw;
  std::copy(landmarks.begin(), landmarks.end(), frame.landmarks.begin());
  std::copy(outlier.begin(), outlier.end(), frame.outlier.begin());
  frame.has_pose = true;
}

RelocaliseReport Relocaliser::relocalise(Frame& frame, const map::MapStore& map,
                                         const std::vector<map::KeyframeId>& candidates,
                                         const place::KeyframeDatabase* places, const place::FeatureVector* frame_fv,
                                         const Continuity* continuity) {
  RelocaliseReport report;
  report.candidates = static_cast<int>(candidates.size());
  frame.has_pose = false;
  near_.inliers = 0;
  far_.inliers = 0;
  for (map::KeyframeId kf : candidates) {
    const int inliers = try_candidate(frame, map, kf, places, frame_fv, report);
    if (inliers == 0) continue;
    if (continuity == nullptr) {
      if (inliers < params_.min_inliers) continue;
      report.ok = true;
      report.keyframe = kf;
      frame.has_pose = true;
      return report;
    }
    if (continuity->near(frame.T_cw)) {
      report.near_evidence = report.near_evidence || inliers >= params_.pnp_min_inliers;
      if (inliers >= params_.near_min_inliers && inliers > near_.inliers) near_.keep(frame, kf, inliers);
    } else if (inliers >= params_.min_inliers && inliers > far_.inliers) {
      far_.keep(frame, kf, inliers);
    }
  }
  const Kept* taken = near_.inliers > 0 ? &near_ : far_.inliers > 0 ? &far_ : nullptr;
  if (taken) {
    taken->restore(frame);
    report.ok = true;
    report.far = taken == &far_;
    report.keyframe = taken->keyframe;
    return report;
  }
  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  report.message = "relocalisation: " + std::to_string(report.candidates) + " candidates, " + std::to_string(report.tried) +
                   " with " + std::to_string(params_.min_matches) + " matches, best " + std::to_string(report.inliers) +
                   " inliers of " + std::to_string(continuity ? params_.near_min_inliers : params_.min_inliers);
  return report;
}

namespace {
constexpr ConfigField kRelocaliserFields[] = {
    number<&RelocaliserParams::max_candidates>("max_candidates", 1, 1000, "place-recognition keyframes tried per lost frame"),
    number<&RelocaliserParams::min_matches>("min_matches", 4, 100000, "descriptor matches a candidate needs"),
    number<&RelocaliserParams::min_inliers>("min_inliers", 10, 100000, "inliers of a relocalised frame"),
    number<&RelocaliserParams::near_candidates>("near_candidates", 0, 1000,
                                                "the reference keyframe and its neighbours tried first when lost"),
    number<&RelocaliserParams::near_min_inliers>("near_min_inliers", 10, 100000,
                                                 "inliers of a pose within reach of the last tracked one"),
    number<&RelocaliserParams::reach_margin>("reach_margin", 0, 1000,
                                             "reach: margin x speed before the loss x time since (map units)"),
    number<&RelocaliserParams::reach_floor_depths>("reach_floor_depths", 0, 1000,
                                                   "reach at least this x the reference's median scene depth"),
    number<&RelocaliserParams::far_confirm_s>("far_confirm_s", 0, 1000,
                                              "a pose beyond the reach is taken after this long consistent (s)"),
};
}  // namespace

extern constexpr ConfigTable kRelocaliserConfig = table_of<RelocaliserParams>(kRelocaliserFields);

}  // namespace ale::slam
