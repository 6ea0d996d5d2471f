#include "core/slam/system.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>
#include <utility>

namespace ale::slam {
namespace {

// The undistorted image's extent: the border's pixels, undistorted (ORB-SLAM uses the corners;
// the edges' midpoints matter under strong barrel distortion).
ImageBounds undistorted_bounds(const geometry::Camera& camera) {
  const geometry::CameraIntrinsics& k = camera.intrinsics();
  const double w = k.width, h = k.height;
  ImageBounds b{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h)};
  if (!camera.has_distortion()) return b;
  float min_u = 1e30f, min_v = 1e30f, max_u = -1e30f, max_v = -1e30f;
  const int steps = 16;
  for (int i = 0; i <= steps; ++i) {
    const double s = static_cast<double>(i) / steps;
    const geometry::Vec2 border[4] = {{s * w, 0.0}, {s * w, h}, {0.0, s * h}, {w, s * h}};
    for (const geometry::Vec2& p : border) {
      geometry::Vec2 q;
      if (!camera.undistort_pixel(p, &q)) continue;
      min_u = std::min(min_u, static_cast<float>(q.x()));
      max_u = std::max(max_u, static_cast<float>(q.x()));
      min_v = std::min(min_v, static_cast<float>(q.y()));
      max_v = std::max(max_v, static_cast<float>(q.y()));
    }
  }
  if (min_u < max_u && min_v < max_v) b = ImageBounds{min_u, min_v, max_u, max_v};
  return b;
}

constexpr ConfigField kCapacityFields[] = {
    number<&map::MapCapacity::max_keyframes>("max_keyframes", 2, 100000, "keyframes the map store holds (fixed arena)"),
    number<&map::MapCapacity::max_landmarks>("max_landmarks", 100, 10000000, "landmarks the map store holds"),
    number<&map::MapCapacity::max_keypoints_per_keyframe>("max_keypoints_per_keyframe", 100, 100000,
                                                           "keypoints kept per frame (the strongest; features.num_features is the front end's)"),
};
constexpr ConfigTable kCapacityTable = table_of<map::MapCapacity>(kCapacityFields);

constexpr ConfigField kInitializerFields[] = {
    number<&InitializerParams::min_features>("min_features", 8, 100000, "keypoints a reference frame needs"),
    number<&InitializerParams::min_matches>("min_matches", 8, 100000, "matches to the reference to try a reconstruction"),
    number<&InitializerParams::min_map_points>("min_map_points", 8, 100000, "landmarks the first map needs after BA"),
    number<&InitializerParams::ba_iterations>("ba_iterations", 0, 1000, "iterations of the two-keyframe BA"),
    number<&InitializerParams::max_reference_age_s>("max_reference_age_s", 0.01, 1000,
                                                     "a reference frame older than this is replaced"),
    number<&InitializerParams::probe_samples>("probe_samples", 0, 100000,
                                               "RANSAC samples of a quick look before each full try (0: none)"),
    number<&InitializerParams::probe_parallax_share>("probe_parallax_share", 0, 1,
                                                      "the full try is skipped below this share of the minimum parallax"),
};
constexpr ConfigTable kInitializerTable = table_of<InitializerParams>(kInitializerFields);

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
constexpr ConfigTable kTrackerTable = table_of<TrackerParams>(kTrackerFields);

constexpr ConfigField kMappingFields[] = {
    number<&LocalMapperParams::triangulation_neighbours>("triangulation_neighbours", 1, 1000,
                                                          "covisible keyframes new points are triangulated with"),
    number<&LocalMapperParams::fuse_neighbours>("fuse_neighbours", 0, 1000, "keyframes searched for duplicates"),
    number<&LocalMapperParams::ba_iterations>("ba_iterations", 0, 1000, "local BA iterations per pass"),
    number<&LocalMapperParams::ba_first_pass_iterations>("ba_first_pass_iterations", 1, 1000,
                                                         "at most, of the local BA's first pass (outlier separation)"),
    number<&LocalMapperParams::ba_function_tolerance>("ba_function_tolerance", 0.0, 1.0,
                                                      "relative cost change that ends a local BA pass"),
    number<&LocalMapperParams::ba_first_pass_function_tolerance>(
        "ba_first_pass_function_tolerance", 0.0, 1.0, "... that ends the first pass (the larger of the two)"),
    number<&LocalMapperParams::ba_max_keyframes>("ba_max_keyframes", 1, 1000,
                                                  "free keyframes of the local BA (the new one, its most covisible)"),
    number<&LocalMapperParams::min_found_ratio>("min_found_ratio", 0, 1, "recent points found less often are culled"),
    flag<&LocalMapperParams::cull_keyframes>("cull_keyframes", "drop keyframes whose points others see"),
    flag<&LocalMapperParams::defer_ba>("defer_ba", "run a keyframe's local BA and culling on the next frame"),
};
constexpr ConfigTable kMappingTable = table_of<LocalMapperParams>(kMappingFields);

constexpr ConfigField kSlamFields[] = {
    number<&SlamParams::lost_timeout_s>("lost_timeout_s", 0, 1e6, "keep re-tracking this long when lost, then a new map"),
    number<&SlamParams::reset_below_keyframes>("reset_below_keyframes", 0, 100000,
                                               "a map this small is reset at once when lost"),
    number<&SlamParams::keyframe_min_frames>("keyframe_min_frames", 0, 100000, "frames between keyframes at least"),
    number<&SlamParams::keyframe_ref_ratio>("keyframe_ref_ratio", 0.01, 1,
                                            "a keyframe when inliers < ratio x the reference's tracked points"),
    number<&SlamParams::keyframe_min_inliers>("keyframe_min_inliers", 0, 100000, "and more inliers than this"),
    number<&SlamParams::process_fps>("process_fps", 0, 120,
                                     "frames processed per second, evenly spaced; the rest skipped (0: all)"),
    nested<&SlamParams::capacity>("capacity", kCapacityTable),
    nested<&SlamParams::initializer>("initializer", kInitializerTable),
    nested<&SlamParams::tracker>("tracker", kTrackerTable),
    nested<&SlamParams::mapping>("mapping", kMappingTable),
};
constexpr ConfigTable kSlamTable = table_of<SlamParams>(kSlamFields);

}  // namespace

const ConfigTable& slam_config_table() { return kSlamTable; }

Status validate(const SlamParams& p) {
  ALE_RETURN_IF_ERROR(check_ranges(kSlamTable, &p, "slam."));
  if (Status s = geometry::validate(p.initializer.two_view); !s.ok())
    return invalid_argument("slam.initializer.two_view: " + s.message());
  return {};
}

Result<std::unique_ptr<SlamSystem>> SlamSystem::create(const SlamParams& params, const geometry::Camera& camera, int levels,
                                      float scale_factor) {
  ALE_RETURN_IF_ERROR(validate(params));
  const geometry::CameraIntrinsics& k = camera.intrinsics();
  if (k.width <= 0 || k.height <= 0) return invalid_argument("slam: the camera has no image size");
  if (levels < 1 || levels > ScalePyramid::kMaxLevels || !(scale_factor > 1.0f)) {
    return invalid_argument("slam: pyramid of " + std::to_string(levels) + " levels, scale " + std::to_string(scale_factor));
  }
  return std::unique_ptr<SlamSystem>(
      new SlamSystem(params, camera, ScalePyramid::make(levels, scale_factor), undistorted_bounds(camera)));
}

SlamSystem::SlamSystem(const SlamParams& params, const geometry::Camera& camera, const ScalePyramid& pyramid,
                       const ImageBounds& bounds)
    : params_(params),
      camera_(camera),
      pinhole_(camera.undistorted()),
      pyramid_(pyramid),
      bounds_(bounds),
      map_(std::make_unique<map::MapStore>(params.capacity)),
      initializer_(params.initializer, pinhole_, pyramid),
      tracker_(params.tracker, pinhole_, pyramid),
      mapper_(params.mapping, pinhole_, pyramid, bounds) {}

void SlamSystem::take_erased() {
  erased_.clear();
  map_->keyframe_events().read(erased_cursor_, [&](const map::KeyframeEvent& e) {
    if (e.kind == map::MapEventKind::kKeyframeErased) erased_.push_back(e.keyframe);
  });
  if (record_trajectory_) trajectory_.keyframes_erased(erased_);
}

void SlamSystem::resolve_trajectory() {
  take_erased();
  trajectory_.resolve(*map_);
}

void SlamSystem::reset() {
  resolve_trajectory();
  map_->reset();
  initializer_.reset();
  mapper_.reset();
  deferred_ = MappingReport{};
  state_ = TrackingState::kNotInitialized;
  has_velocity_ = false;
  reference_ = map::KeyframeId{};
}

void SlamSystem::start_new_map(SlamReport& report) {
  reset();
  ++resets_;
  report.map_reset = true;
}

bool SlamSystem::need_keyframe(const TrackReport& t) const {
  if (frames_since_keyframe_ < static_cast<std::uint64_t>(params_.keyframe_min_frames)) return false;
  const map::Keyframe* ref = map_->keyframe(reference_);
  if (!ref) return true;
  // landmarks of the reference keyframe with enough observations to be trusted
  const int min_obs = map_->stats().keyframes <= 2 ? 2 : 3;
  const map::LandmarkId* ids = map_->keypoint_landmarks(reference_);
  int ref_tracked = 0;
  for (int i = 0; i < ref->num_features; ++i) {
    const map::Landmark* lm = map_->landmark(ids[i]);
    if (lm && lm->num_observations >= min_obs) ++ref_tracked;
  }
  // Inline mapping is always idle, so ORB-SLAM's "enough frames or mapper idle" condition always
  // holds and the view change alone decides.
  const bool view_changed = t.inliers < params_.keyframe_ref_ratio * ref_tracked;
  return view_changed && t.inliers > params_.keyframe_min_inliers;
}

// The map's memory is fixed: when the keyframe or landmark arena is nearly full, the oldest
// keyframes outside the reference keyframe's covisible neighbourhood go (with the landmarks no
// other keyframe observes), so that a robot running for hours keeps mapping where it is. Without
// loop closing the map forgets the places it left longest ago; the poses stay continuous.
void SlamSystem::make_room(SlamReport& report) {
  const map::MapStats before = map_->stats();
  // room for this keyframe and the landmarks one keyframe can create
  const std::size_t landmark_margin = static_cast<std::size_t>(params_.capacity.max_keypoints_per_keyframe);
  auto full = [&](const map::MapStats& s) {
    return s.keyframes + 1 >= s.keyframe_capacity || s.landmarks + landmark_margin >= s.landmark_capacity;
  };
  if (!full(before)) return;
  const map::Keyframe* ref = map_->keyframe(reference_);
  auto near_reference = [&](map::KeyframeId id) {
    if (!ref) return false;
    for (int n = 0; n < ref->num_covisible; ++n)
      if (ref->covisible[static_cast<std::size_t>(n)].keyframe == id) return true;
    return false;
  };
  // oldest first, those outside the neighbourhood before those in it (a small map may have no
  // other); a few at a time so eviction is not needed on every keyframe
  std::vector<std::tuple<bool, std::uint64_t, map::KeyframeId>> candidates;
  map_->for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& kf) {
    if (id != reference_) candidates.emplace_back(near_reference(id), kf.frame_seq, id);
  });
  std::sort(candidates.begin(), candidates.end());
  const std::size_t batch = std::max<std::size_t>(1, before.keyframe_capacity / 20);
  std::vector<map::LandmarkId> seen;
  for (std::size_t i = 0; i < candidates.size() && i < batch; ++i) {
    seen.clear();
    const map::KeyframeId id = std::get<2>(candidates[i]);
    map_->landmarks_of(id, seen);
    map_->erase_keyframe(id);
    ++report.mapping.keyframes_evicted;
    for (map::LandmarkId l : seen) {
      const map::Landmark* lm = map_->landmark(l);
      if (lm && lm->num_observations < 2) {
        map_->erase_landmark(l);
        ++report.mapping.landmarks_evicted;
      }
    }
  }
}

void SlamSystem::insert_keyframe(SlamReport& report) {
  make_room(report);
  Result<map::KeyframeId> kf =
      map_->add_keyframe(current_.timestamp_s, current_.sequence, current_.T_cw, current_.features.data(), current_.size());
  if (!kf.ok()) {
    report.message = "keyframe not inserted: " + kf.status().message();
    return;
  }
  report.mapping += mapper_.process(*kf, current_, *map_);  // after make_room's evictions
  report.keyframe_inserted = true;
  reference_ = *kf;
  frames_since_keyframe_ = 0;
  last_keyframe_sequence_ = current_.sequence;
  // the frame's matches now follow the map (fused or culled landmarks)
  const map::LandmarkId* ids = map_->keypoint_landmarks(*kf);
  for (int i = 0; i < current_.size(); ++i) current_.landmarks[static_cast<std::size_t>(i)] = ids[i];
}

void SlamSystem::finish_mapping() {
  if (!mapper_.has_pending()) return;
  const map::KeyframeId kf = mapper_.pending();
  deferred_ += mapper_.finish_pending(*map_);
  take_erased();
  // The keyframe's frame is the last one now: its matches follow the map after the BA's outlier
  // removal, as they did when the BA ran inside insert_keyframe().
  const map::Keyframe* k = map_->keyframe(kf);
  if (!k || k->frame_seq != last_.sequence || k->num_features != last_.size()) return;
  const map::LandmarkId* ids = map_->keypoint_landmarks(kf);
  for (int i = 0; i < last_.size(); ++i) last_.landmarks[static_cast<std::size_t>(i)] = ids[i];
}

Result<SlamReport> SlamSystem::process(double timestamp_s, std::uint64_t sequence,
                                       const std::vector<map::KeyframeFeature>& features) {
  finish_mapping();
  ALE_RETURN_IF_ERROR(track_frame(timestamp_s, sequence, features));
  map_frame();
  return report_;
}

Status SlamSystem::track_frame(double timestamp_s, std::uint64_t sequence, const std::vector<map::KeyframeFeature>& features) {
  tracked_ = false;
  if (!std::isfinite(timestamp_s) || timestamp_s <= last_timestamp_s_) {
    return invalid_argument("slam: frame " + std::to_string(sequence) + " has timestamp " + std::to_string(timestamp_s) +
                            " s, not after the previous " + std::to_string(last_timestamp_s_) + " s");
  }
  last_timestamp_s_ = timestamp_s;
  report_ = SlamReport{};
  SlamReport& report = report_;
  report.mapping = deferred_;  // the last keyframe's local BA, run by finish_mapping() before this frame
  deferred_ = MappingReport{};
  keyframe_pending_ = false;

  current_.timestamp_s = timestamp_s;
  current_.sequence = sequence;
  current_.features.clear();
  const int cap = params_.capacity.max_keypoints_per_keyframe;
  for (const map::KeyframeFeature& f : features) {
    if (static_cast<int>(current_.features.size()) >= cap) break;
    geometry::Vec2 ideal;
    if (!camera_.undistort_pixel(geometry::Vec2(f.u, f.v), &ideal)) continue;
    map::KeyframeFeature g = f;
    g.u = static_cast<float>(ideal.x());
    g.v = static_cast<float>(ideal.y());
    current_.features.push_back(g);
  }
  current_.index(bounds_);
  report.features = current_.size();
  ++frames_since_keyframe_;

  if (state_ == TrackingState::kNotInitialized || state_ == TrackingState::kInitializing) {
    map::KeyframeId k1, k2;
    const InitReport ir = initializer_.add_frame(current_, *map_, &k1, &k2);
    report.matches = ir.matches;
    if (ir.state == InitState::kInitialized) {
      state_ = TrackingState::kTracking;
      reference_ = k2;
      frames_since_keyframe_ = 0;
      has_velocity_ = false;
      std::vector<map::LandmarkId> lms;
      map_->landmarks_of(k2, lms);
      for (map::LandmarkId l : lms) mapper_.add_recent(l, k1);
      report.inliers = current_.matched();
    } else {
      state_ = ir.state == InitState::kWaiting ? TrackingState::kInitializing : TrackingState::kNotInitialized;
      report.message = ir.message;
    }
  } else {
    const TrackReport tr = tracker_.track(current_, last_, velocity_, has_velocity_ && state_ == TrackingState::kTracking,
                                          *map_, &reference_);
    report.matches = tr.matches;
    report.inliers = tr.inliers;
    if (tr.ok) {
      velocity_ = current_.T_cw * last_.T_cw.inverse();
      has_velocity_ = true;
      state_ = TrackingState::kTracking;
      keyframe_pending_ = need_keyframe(tr);
    } else {
      report.message = tr.message;
      if (state_ == TrackingState::kTracking) {
        state_ = TrackingState::kLost;
        lost_since_s_ = timestamp_s;
        has_velocity_ = false;
      }
      if (static_cast<int>(map_->stats().keyframes) < params_.reset_below_keyframes ||
          timestamp_s - lost_since_s_ > params_.lost_timeout_s) {
        start_new_map(report);
        report.message += "; a new map starts";
      }
      // otherwise the last frame with a pose stays the one to re-track from
    }
  }
  report.state = state_;
  tracked_ = true;
  return {};
}

void SlamSystem::map_frame() {
  if (!tracked_) return;
  tracked_ = false;
  SlamReport& report = report_;
  if (keyframe_pending_) insert_keyframe(report);
  keyframe_pending_ = false;
  report.has_pose = current_.has_pose && (state_ == TrackingState::kTracking);
  take_erased();
  if (report.has_pose) {
    if (record_trajectory_) trajectory_.add(current_.timestamp_s, current_.sequence, reference_, current_.T_cw, *map_);
    report.T_cw = current_.T_cw;
    std::swap(current_, last_);
  }
  const map::MapStats ms = map_->stats();
  report.map_id = ms.map_id;
  report.resets = resets_;
  report.keyframes = ms.keyframes;
  report.landmarks = ms.landmarks;
}

}  // namespace ale::slam
