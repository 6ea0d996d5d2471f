#include "core/slam/system.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>

namespace ale::slam {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

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

}  // namespace

Status validate(const SlamParams& p) {
  auto bad = [](const char* key, const std::string& why) { return invalid_argument(std::string("slam.") + key + ": " + why); };
  if (p.capacity.max_keyframes < 2) return bad("max_keyframes", "at least 2");
  if (p.capacity.max_landmarks < 100) return bad("max_landmarks", "at least 100");
  if (p.capacity.max_keypoints_per_keyframe < 100) return bad("max_keypoints_per_keyframe", "at least 100");
  if (!(p.lost_timeout_s >= 0.0)) return bad("lost_timeout_s", "must be >= 0");
  if (p.keyframe_min_frames < 0) return bad("keyframe_min_frames", "must be >= 0");
  if (!(p.keyframe_ref_ratio > 0.0 && p.keyframe_ref_ratio <= 1.0)) return bad("keyframe_ref_ratio", "in (0, 1]");
  if (p.initializer.min_matches < 8) return bad("initializer.min_matches", "at least 8");
  return geometry::validate(p.initializer.two_view);
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

void SlamSystem::reset() {
  map_->reset();
  initializer_.reset();
  mapper_.reset();
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

void SlamSystem::insert_keyframe(SlamReport& report) {
  Result<map::KeyframeId> kf =
      map_->add_keyframe(current_.timestamp_s, current_.sequence, current_.T_cw, current_.features.data(), current_.size());
  if (!kf.ok()) {
    report.message = "keyframe not inserted: " + kf.status().message();
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  report.mapping = mapper_.process(*kf, current_, *map_);
  report.mapping_ms = ms_since(t0);
  report.keyframe_inserted = true;
  reference_ = *kf;
  frames_since_keyframe_ = 0;
  last_keyframe_sequence_ = current_.sequence;
  // the frame's matches now follow the map (fused or culled landmarks)
  const map::LandmarkId* ids = map_->keypoint_landmarks(*kf);
  for (int i = 0; i < current_.size(); ++i) current_.landmarks[static_cast<std::size_t>(i)] = ids[i];
}

Result<SlamReport> SlamSystem::process(double timestamp_s, std::uint64_t sequence,
                                       const std::vector<map::KeyframeFeature>& features) {
  if (!std::isfinite(timestamp_s) || timestamp_s <= last_timestamp_s_) {
    return invalid_argument("slam: frame " + std::to_string(sequence) + " has timestamp " + std::to_string(timestamp_s) +
                            " s, not after the previous " + std::to_string(last_timestamp_s_) + " s");
  }
  last_timestamp_s_ = timestamp_s;
  SlamReport report;
  const auto t0 = std::chrono::steady_clock::now();

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
      if (need_keyframe(tr)) insert_keyframe(report);
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
  report.tracking_ms = ms_since(t0) - report.mapping_ms;
  report.state = state_;
  report.has_pose = current_.has_pose && (state_ == TrackingState::kTracking);
  if (report.has_pose) {
    report.T_cw = current_.T_cw;
    std::swap(current_, last_);
  }
  const map::MapStats ms = map_->stats();
  report.map_id = ms.map_id;
  report.resets = resets_;
  report.keyframes = ms.keyframes;
  report.landmarks = ms.landmarks;
  return report;
}

}  // namespace ale::slam
