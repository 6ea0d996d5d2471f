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

// Mean distance of the frame's matched landmarks from `centre`; 0 when it has none.
double mean_landmark_distance(const Frame& frame, const geometry::Vec3& centre, const map::MapStore& map) {
  double sum = 0.0;
  int n = 0;
  for (map::LandmarkId id : frame.landmarks) {
    if (const map::Landmark* lm = map.landmark(id)) {
      sum += (lm->p_w - centre).norm();
      ++n;
    }
  }
  return n > 0 ? sum / n : 0.0;
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

bool Tracker::track_reference(Frame& frame, const geometry::SE3& start_cw, map::KeyframeId reference, map::MapStore& map,
                              TrackReport& report) {
  if (!map.keyframe(reference)) {
    report.message = "reference keyframe: none";
    return false;
  }
  frame.T_cw = start_cw;
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

void Tracker::search_local_map(Frame& frame, const std::vector<map::LandmarkId>& seeds, map::MapStore& map,
                               map::KeyframeId* reference, TrackReport& report) {
  const map::KeyframeId best_kf =
      local_map_.select(seeds, map, {params_.local_keyframes_max, params_.covisible_per_keyframe});
  if (best_kf.valid()) *reference = best_kf;
  report.local_keyframes = static_cast<int>(local_map_.keyframes().size());
  report.local_landmarks = static_cast<int>(local_map_.landmarks().size());
  search_by_projection(match_context(), {frame.view(), frame.T_cw, frame.landmarks}, map, local_map_.landmarks(),
                       params_.local_map_radius_px, &in_view_);
  for (map::LandmarkId id : in_view_) ++map.landmark(id)->visible;
  // the landmarks matched before this search were in view too
}

void Tracker::count_found(const Frame& frame, map::MapStore& map) {
  for (map::LandmarkId id : frame.landmarks) {
    if (map::Landmark* lm = map.landmark(id)) ++lm->found;
  }
}

bool Tracker::track_local_map(Frame& frame, map::MapStore& map, map::KeyframeId* reference, TrackReport& report) {
  search_local_map(frame, frame.landmarks, map, reference, report);
  int inliers = 0;
  refiner_.refine(frame, map, &inliers);
  report.inliers = inliers;
  count_found(frame, map);
  if (inliers < params_.local_map_min_inliers) {
    report.message = "local map: " + std::to_string(inliers) + " inliers, " +
                     std::to_string(params_.local_map_min_inliers) + " needed";
    return false;
  }
  return true;
}

// Points along the rays of the last frame's keypoints in bearing_pairs_, `depth` from its centre.
void Tracker::ray_points(const Frame& last, double depth) {
  const geometry::CameraIntrinsics& k = pinhole_.intrinsics();
  const geometry::SE3 T_wc = last.T_cw.inverse();
  const geometry::Mat3 R_wc = T_wc.rotation();
  bearing_points_.clear();
  bearing_keypoints_.clear();
  for (const auto& [il, i] : bearing_pairs_) {
    const map::KeyframeFeature& f = last.features[static_cast<std::size_t>(il)];
    const geometry::Vec3 ray((f.u - k.cx) / k.fx, (f.v - k.cy) / k.fy, 1.0);
    bearing_points_.push_back(T_wc.translation() + depth * (R_wc * ray.normalized()));
    bearing_keypoints_.push_back(i);
  }
}

bool Tracker::track_turn(Frame& frame, const Frame& last, const geometry::SE3& velocity, map::MapStore& map,
                         map::KeyframeId* reference, TrackReport& report) {
  if (turn_from(frame, last, velocity * last.T_cw, map, reference, report)) return true;
  // the turn may have ended: from the last pose
  return turn_from(frame, last, last.T_cw, map, reference, report);
}

bool Tracker::turn_from(Frame& frame, const Frame& last, const geometry::SE3& start_cw, map::MapStore& map,
                        map::KeyframeId* reference, TrackReport& report) {
  frame.T_cw = start_cw;
  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  const MatchContext ctx = match_context();
  const ProjectionTarget target{frame.view(), frame.T_cw, frame.landmarks};
  // the landmarks still in view, then the rest of the last frame's keypoints as bearings
  search_last_frame(ctx, target, last.view(), last.landmarks, map, params_.motion_radius_px);
  const int n = search_bearings(ctx, target, last.view(), last.landmarks, last.T_cw, params_.motion_radius_px,
                                bearing_pairs_);
  report.matches = n;
  if (n < params_.turn_min_bearings) {
    report.message += "; turn: " + std::to_string(n) + " bearings, " + std::to_string(params_.turn_min_bearings) + " needed";
    return false;
  }
  // The bearings as points at the scene's mean depth (that of the last frame's landmarks): their
  // depths are unknown, and the camera moves between frames (on the turning arm, or driving on
  // after the turn), so points at infinity would turn that step into rotation (measured on a
  // synthetic turn and slide: 3.9 degrees of heading error over the run, 1.7 at the mean depth).
  // The centre where the motion model puts it, within the predicted step or 1 % of that depth.
  const geometry::Vec3 last_centre = last.T_cw.inverse().translation();
  optim::CentrePrior prior;
  prior.centre_w = frame.T_cw.inverse().translation();
  double depth = mean_landmark_distance(last, last_centre, map);
  // no landmark left: the last depth measured (the map starts at median depth 1)
  if (depth > 0.0) scene_depth_ = depth; else depth = scene_depth_;
  prior.sigma = std::max((prior.centre_w - last_centre).norm(), 0.01 * depth);
  refiner_.set_centre_prior(odometry_prior_.sigma > 0.0 ? odometry_prior_ : prior);
  ray_points(last, depth);
  int map_inliers = 0, bearing_inliers = 0;
  bool ok = refiner_.refine_with_bearings(frame, map, bearing_points_, bearing_keypoints_, &map_inliers, &bearing_inliers);
  if (ok) {
    // the local map at the refined pose (around the last frame's landmarks when none is left),
    // then both again
    search_local_map(frame, map_inliers > 0 ? frame.landmarks : last.landmarks, map, reference, report);
    ok = refiner_.refine_with_bearings(frame, map, bearing_points_, bearing_keypoints_, &map_inliers, &bearing_inliers);
    count_found(frame, map);
  }
  refiner_.set_centre_prior({});
  report.inliers = map_inliers;
  report.bearings = bearing_inliers;
  if (!ok || bearing_inliers < params_.turn_min_bearings) {
    report.message += "; turn: " + std::to_string(bearing_inliers) + " bearing inliers, " +
                      std::to_string(params_.turn_min_bearings) + " needed";
    return false;
  }
  report.turn = true;
  return true;
}

optim::CentrePrior Tracker::centre_prior(const Frame& last, const geometry::SE3& predicted_cw,
                                         const map::MapStore& map) const {
  optim::CentrePrior prior;
  if (params_.centre_prior_step <= 0.0 && params_.centre_prior_depth <= 0.0) return prior;
  const geometry::Vec3 last_centre = last.T_cw.inverse().translation();
  prior.centre_w = predicted_cw.inverse().translation();
  const double step = (prior.centre_w - last_centre).norm();
  const double depth = mean_landmark_distance(last, last_centre, map);
  prior.sigma = std::max(params_.centre_prior_step * step, params_.centre_prior_depth * depth);
  if (!(prior.sigma > 0.0) || !std::isfinite(prior.sigma)) prior.sigma = 0.0;
  return prior;
}

TrackReport Tracker::track(Frame& frame, const Frame& last, const geometry::SE3& velocity, bool has_velocity,
                           map::MapStore& map, map::KeyframeId* reference, double odometry_sigma) {
  TrackReport report;
  bool ok = false;
  odometry_prior_ = {};
  if (has_velocity && odometry_sigma > 0.0) {
    odometry_prior_.centre_w = (velocity * last.T_cw).inverse().translation();
    odometry_prior_.sigma = odometry_sigma;
    // Quadratic: where the two disagree within a frame it is more often the vision (a turn's
    // yaw against a sideways step) than the wheels; a Huber kernel here cost 0.5-1.2 cm on
    // three of six odometry-bench routes. The local BA's priors have one (map_ba.cpp).
  }
  const bool odometry = odometry_prior_.sigma > 0.0;
  refiner_.set_centre_prior(odometry      ? odometry_prior_
                            : has_velocity ? centre_prior(last, velocity * last.T_cw, map)
                                           : optim::CentrePrior{});
  if (has_velocity) {
    ok = track_motion_model(frame, last, velocity, map, report);
    report.used_motion_model = ok;
  }
  if (!ok) {
    // the odometry's centre holds for every step; the constant-velocity one only for the first
    if (!odometry) refiner_.set_centre_prior({});
    // from the constant-velocity prediction when there is one: in a turn the last pose is a
    // whole turn step behind
    ok = track_reference(frame, has_velocity ? velocity * last.T_cw : last.T_cw, *reference, map, report);
  }
  if (ok) ok = track_local_map(frame, map, reference, report);
  refiner_.set_centre_prior({});
  if (ok) {
    turn_frames_ = 0;
  } else if (has_velocity && params_.turn_min_bearings > 0 && turn_frames_ < params_.turn_max_frames) {
    ok = track_turn(frame, last, velocity, map, reference, report);
    if (ok) ++turn_frames_;
  }
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
    number<&TrackerParams::pose_min_confirmed>("pose_min_confirmed", 0, 100000,
                                               "... when at least this many matches are seen that often"),
    number<&TrackerParams::centre_prior_step>("centre_prior_step", 0, 1000,
                                              "centre prior sigma: x the predicted step (0 and 0: none)"),
    number<&TrackerParams::centre_prior_depth>("centre_prior_depth", 0, 1000, "... at least x the landmarks' mean depth"),
    number<&TrackerParams::turn_min_bearings>("turn_min_bearings", 0, 100000,
                                              "bearing inliers of the turn step (0: no turn step)"),
    number<&TrackerParams::turn_max_frames>("turn_max_frames", 0, 100000, "frames in a row the turn step may track"),
};
}  // namespace

extern constexpr ConfigTable kTrackerConfig = table_of<TrackerParams>(kTrackerFields);

}  // namespace ale::slam
