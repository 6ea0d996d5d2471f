#include "core/slam/tracker.h"

#include <algorithm>

namespace ale::slam {

Tracker::Tracker(const TrackerParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
                 const MatcherParams& matcher)
    : params_(params), matcher_(matcher), pinhole_(pinhole), pyramid_(pyramid) {
  params_.motion_only.scale_factor = pyramid.scale_factor;
}

// Motion-only optimisation of frame.T_cw over its matched landmarks; outliers are unmatched.
bool Tracker::optimise(Frame& frame, int* inliers) {
  // the frame's landmarks are read from the map through the caller's last search; positions
  // are gathered here
  *inliers = 0;
  if (obs_.empty()) return false;
  inlier_.assign(obs_.size(), 0);
  const optim::MotionOnlyResult r =
      optim::optimize_pose(pinhole_, frame.T_cw, obs_.data(), static_cast<int>(obs_.size()), params_.motion_only, inlier_.data());
  if (!r.status.ok() || !r.T_cw.translation().allFinite()) return false;
  frame.T_cw = r.T_cw;
  for (std::size_t k = 0; k < obs_.size(); ++k) {
    if (!inlier_[k]) frame.landmarks[static_cast<std::size_t>(obs_keypoint_[k])] = map::LandmarkId{};
  }
  *inliers = r.inliers;
  return r.inliers >= params_.min_inliers;
}

namespace {
// The matched landmarks of a frame as motion-only observations: those seen by at least
// min_observations keyframes when at least min_confirmed are, else all.
void gather(const Frame& frame, const map::MapStore& map, int min_observations, int min_confirmed,
            std::vector<optim::PoseObservation>& obs, std::vector<int>& keypoint) {
  obs.clear();
  keypoint.clear();
  int confirmed = 0;
  for (map::LandmarkId id : frame.landmarks) {
    const map::Landmark* lm = map.landmark(id);
    if (lm && lm->num_observations >= min_observations) ++confirmed;
  }
  const int needed = confirmed >= min_confirmed ? min_observations : 0;
  for (int i = 0; i < frame.size(); ++i) {
    const map::Landmark* lm = map.landmark(frame.landmarks[static_cast<std::size_t>(i)]);
    if (!lm || lm->num_observations < needed) continue;
    const map::KeyframeFeature& f = frame.features[static_cast<std::size_t>(i)];
    optim::PoseObservation o;
    o.p_w = lm->p_w;
    o.uv_px = geometry::Vec2(f.u, f.v);
    o.level = f.level;
    obs.push_back(o);
    keypoint.push_back(i);
  }
}
}  // namespace

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
  gather(frame, map, params_.pose_min_observations, params_.pose_min_confirmed, obs_, obs_keypoint_);
  int inliers = 0;
  if (!optimise(frame, &inliers)) {
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
  gather(frame, map, params_.pose_min_observations, params_.pose_min_confirmed, obs_, obs_keypoint_);
  int inliers = 0;
  if (!optimise(frame, &inliers)) {
    report.message = "reference keyframe: " + std::to_string(inliers) + " inliers";
    return false;
  }
  return true;
}

bool Tracker::track_local_map(Frame& frame, map::MapStore& map, map::KeyframeId* reference, TrackReport& report) {
  // keyframes that see the frame's landmarks, by how many
  const map::MapStats st = map.stats();
  counts_by_slot_.assign(st.keyframe_capacity, 0);
  ids_by_slot_.resize(st.keyframe_capacity);
  for (map::LandmarkId id : frame.landmarks) {
    for (const map::Observation& o : map.observations_of(id)) {
      const map::KeyframeId kf = o.keyframe;
      if (!map.keyframe(kf)) continue;
      ++counts_by_slot_[kf.slot()];
      ids_by_slot_[kf.slot()] = kf;
    }
  }
  local_keyframes_.clear();
  int best = 0;
  map::KeyframeId best_kf;
  for (std::uint32_t s = 0; s < counts_by_slot_.size(); ++s) {
    if (counts_by_slot_[s] == 0) continue;
    const map::KeyframeId id = ids_by_slot_[s];
    if (counts_by_slot_[s] > best) {
      best = counts_by_slot_[s];
      best_kf = id;
    }
    local_keyframes_.push_back(id);
  }
  // their strongest neighbours, parents and children
  const std::size_t direct = local_keyframes_.size();
  for (std::size_t i = 0; i < direct && static_cast<int>(local_keyframes_.size()) < params_.local_keyframes_max; ++i) {
    const map::Keyframe* kf = map.keyframe(local_keyframes_[i]);
    for (const map::Covisible& c : map.covisible_of(local_keyframes_[i]).first(params_.covisible_per_keyframe)) {
      const map::KeyframeId n = c.keyframe;
      if (std::find(local_keyframes_.begin(), local_keyframes_.end(), n) == local_keyframes_.end()) {
        local_keyframes_.push_back(n);
      }
    }
    if (kf->parent.valid() &&
        std::find(local_keyframes_.begin(), local_keyframes_.end(), kf->parent) == local_keyframes_.end()) {
      local_keyframes_.push_back(kf->parent);
    }
  }
  if (best_kf.valid()) *reference = best_kf;
  local_landmarks_.clear();
  for (map::KeyframeId kf : local_keyframes_) map.landmarks_of(kf, local_landmarks_);
  std::sort(local_landmarks_.begin(), local_landmarks_.end());
  local_landmarks_.erase(std::unique(local_landmarks_.begin(), local_landmarks_.end()), local_landmarks_.end());
  report.local_keyframes = static_cast<int>(local_keyframes_.size());
  report.local_landmarks = static_cast<int>(local_landmarks_.size());

  search_by_projection(match_context(), {frame.view(), frame.T_cw, frame.landmarks}, map, local_landmarks_,
                       params_.local_map_radius_px, &in_view_);
  for (map::LandmarkId id : in_view_) ++map.landmark(id)->visible;
  // the landmarks matched before this search were in view too
  gather(frame, map, params_.pose_min_observations, params_.pose_min_confirmed, obs_, obs_keypoint_);
  int inliers = 0;
  optimise(frame, &inliers);
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

TrackReport Tracker::track(Frame& frame, const Frame& last, const geometry::SE3& velocity, bool has_velocity,
                           map::MapStore& map, map::KeyframeId* reference) {
  TrackReport report;
  bool ok = false;
  if (has_velocity) {
    ok = track_motion_model(frame, last, velocity, map, report);
    report.used_motion_model = ok;
  }
  if (!ok) ok = track_reference(frame, last, *reference, map, report);
  if (ok) ok = track_local_map(frame, map, reference, report);
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
};
}  // namespace

extern constexpr ConfigTable kTrackerConfig = table_of<TrackerParams>(kTrackerFields);

}  // namespace ale::slam
