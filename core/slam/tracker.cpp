#include "core/slam/tracker.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {
namespace {
PoseRefinerParams refiner_params(const TrackerParams& p, const ScalePyramid& pyramid) {
  PoseRefinerParams r{p.pose_min_observations, p.pose_min_confirmed, p.min_inliers, p.motion_only};
  r.motion_only.scale_factor = pyramid.scale_factor;
  return r;
}
}  // namespace

Tracker::Tracker(const TrackerParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
                 const MatcherParams& matcher)
    : params_(params),
      matcher_(matcher),
      pinhole_(pinhole),
      pyramid_(pyramid),
      refiner_(refiner_params(params, pyramid), pinhole) {}

bool Tracker::track_motion_model(Frame& frame, const Frame& last, const geometry::SE3& velocity, map::MapStore& map,
                                 TrackReport& report) {
  frame.T_cw = velocity * last.T_cw;
  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  const MatchContext ctx = match_context();
  const ProjectionTarget target{frame.view(), frame.T_cw, frame.landmarks};
  int n = search_last_frame(ctx, target, last.view(), last.landmarks, map, params_.motion_radius_px);
  if (n < params_.motion_min_matches) {
    std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
    n = search_last_frame(ctx, target, last.view(), last.landmarks, map, 2.0f * params_.motion_radius_px);
  }
  report.matches = n;
  if (n < params_.motion_min_matches) {
    report.message = "motion model: " + std::to_string(n) + " matches, " + std::to_string(params_.motion_min_matches) + " needed";
    return false;
  }
  int inliers = 0;
  if (!refiner_.refine(frame, map, &inliers)) {
    report.message = "motion model: " + std::to_string(inliers) + " inliers, " + std::to_string(params_.min_inliers) + " needed";
    return false;
  }
  return true;
}

bool Tracker::track_reference(Frame& frame, const Frame& last, map::KeyframeId reference, map::MapStore& map,
                              TrackReport& report) {
  if (!map.keyframe(reference)) {
    report.message = "reference keyframe: none";
    return false;
  }
  frame.T_cw = last.T_cw;
  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  landmarks_.clear();
  map.landmarks_of(reference, landmarks_);
  // a wide radius around the last pose stands in for ORB-SLAM's bag-of-words search
  const int n = search_by_projection(match_context(), {frame.view(), frame.T_cw, frame.landmarks}, map, landmarks_,
                                     params_.reference_radius_px);
  report.matches = n;
  if (n < params_.reference_min_matches) {
    report.message = "reference keyframe: " + std::to_string(n) + " matches, " +
                     std::to_string(params_.reference_min_matches) + " needed";
    return false;
  }
  int inliers = 0;
  if (!refiner_.refine(frame, map, &inliers)) {
    report.message = "reference keyframe: " + std::to_string(inliers) + " inliers";
    return false;
  }
  return true;
}

bool Tracker::track_local_map(Frame& frame, map::MapStore& map, map::KeyframeId* reference, TrackReport& report) {
  const map::KeyframeId best_kf =
      local_map_.select(frame.landmarks, map, {params_.local_keyframes_max, params_.covisible_per_keyframe});
  if (best_kf.valid()) *reference = best_kf;
  report.local_keyframes = static_cast<int>(local_map_.keyframes().size());
  report.local_landmarks = static_cast<int>(local_map_.landmarks().size());

  search_by_projection(match_context(), {frame.view(), frame.T_cw, frame.landmarks}, map, local_map_.landmarks(),
                       params_.local_map_radius_px, &in_view_);
  for (map::LandmarkId id : in_view_) ++map.landmark(id)->visible;
  // the landmarks matched before this search were in view too
  int inliers = 0;
  refiner_.refine(frame, map, &inliers);
  report.inliers = inliers;
  for (map::LandmarkId id : frame.landmarks) {
    if (map::Landmark* lm = map.landmark(id)) ++lm->found;
  }
  if (inliers < params_.local_map_min_inliers) {
    report.message = "local map: " + std::to_string(inliers) + " inliers, " +
                     std::to_string(params_.local_map_min_inliers) + " needed";
    return false;
  }
  return true;
}

optim::CentrePrior Tracker::centre_prior(const Frame& last, const geometry::SE3& predicted_cw,
                                         const map::MapStore& map) const {
  optim::CentrePrior prior;
  if (params_.centre_prior_step <= 0.0 && params_.centre_prior_depth <= 0.0) return prior;
  const geometry::Vec3 last_centre = last.T_cw.inverse().translation();
  prior.centre_w = predicted_cw.inverse().translation();
  double depth_sum = 0.0;
  int depths = 0;
  for (map::LandmarkId id : last.landmarks) {
    if (const map::Landmark* lm = map.landmark(id)) {
      depth_sum += (lm->p_w - last_centre).norm();
      ++depths;
    }
  }
  const double step = (prior.centre_w - last_centre).norm();
  const double depth = depths > 0 ? depth_sum / depths : 0.0;
  prior.sigma = std::max(params_.centre_prior_step * step, params_.centre_prior_depth * depth);
  if (!(prior.sigma > 0.0) || !std::isfinite(prior.sigma)) prior.sigma = 0.0;
  return prior;
}

TrackReport Tracker::track(Frame& frame, const Frame& last, const geometry::SE3& velocity, bool has_velocity,
                           map::MapStore& map, map::KeyframeId* reference) {
  TrackReport report;
  bool ok = false;
  refiner_.set_centre_prior(has_velocity ? centre_prior(last, velocity * last.T_cw, map) : optim::CentrePrior{});
  if (has_velocity) {
    ok = track_motion_model(frame, last, velocity, map, report);
    report.used_motion_model = ok;
  }
  if (!ok) {
    refiner_.set_centre_prior({});
    ok = track_reference(frame, last, *reference, map, report);
  }
  if (ok) ok = track_local_map(frame, map, reference, report);
  refiner_.set_centre_prior({});
  frame.has_pose = ok;
  report.ok = ok;
  if (!ok) std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  return report;
}

namespace {
constexpr ConfigField kTrackerFields[] = {
    number<&TrackerParams::motion_min_matches>("motion_min_matches", 4, 100000, "matches the motion model needs"),
    number<&TrackerParams::reference_min_matches>("reference_min_matches", 4, 100000, "matches the reference needs"),
    number<&TrackerParams::min_inliers>("min_inliers", 4, 100000, "inliers after each motion-only optimisation"),
    number<&TrackerParams::local_map_min_inliers>("local_map_min_inliers", 4, 100000,
                                                   "inliers after the local map for a tracked frame"),
    number<&TrackerParams::local_keyframes_max>("local_keyframes_max", 1, 10000, "keyframes of the local map"),
    number<&TrackerParams::pose_min_observations>("pose_min_observations", 0, 1000,
                                                  "landmarks seen by fewer keyframes are matched, not used for the pose"),
    number<&TrackerParams::centre_prior_step>("centre_prior_step", 0, 1000,
                                              "centre prior sigma: x the predicted step (0 and 0: none)"),
    number<&TrackerParams::centre_prior_depth>("centre_prior_depth", 0, 1000, "... at least x the landmarks' mean depth"),
    number<&TrackerParams::pose_min_confirmed>("pose_min_confirmed", 0, 100000,
                                               "... when at least this many matches are seen that often"),
};
}  // namespace

extern constexpr ConfigTable kTrackerConfig = table_of<TrackerParams>(kTrackerFields);

}  // namespace ale::slam
