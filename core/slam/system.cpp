#include "core/slam/system.h"

#include "core/geometry/chi_square.h"
#include "core/map/map_config.h"
#include "core/slam/local_map.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

namespace ale::slam {
namespace {

// A frame's time in seconds as the odometry's nanoseconds.
std::int64_t to_ns(double seconds) { return std::llround(seconds * 1e9); }

constexpr ConfigField kSlamFields[] = {
    number<&SlamParams::lost_timeout_s>("lost_timeout_s", 0, 1e6, "relocalise this long when lost, then a new map"),
    number<&SlamParams::reset_below_keyframes>("reset_below_keyframes", 0, 100000,
                                               "a map this small is reset at once when lost"),
    number<&SlamParams::coast_frames>("coast_frames", 0, 1000,
                                      "lost frames still tracked from the constant-velocity model"),
    number<&SlamParams::keyframe_min_frames>("keyframe_min_frames", 0, 100000, "frames between keyframes at least"),
    number<&SlamParams::keyframe_ref_ratio>("keyframe_ref_ratio", 0.01, 1,
                                            "a keyframe when inliers < ratio x the reference's tracked points"),
    number<&SlamParams::keyframe_min_inliers>("keyframe_min_inliers", 0, 100000, "and more inliers than this"),
    number<&SlamParams::keyframe_urgent_min_frames>("keyframe_urgent_min_frames", 0, 100000,
                                                    "frames between keyframes when the view leaves the map fast"),
    number<&SlamParams::keyframe_urgent_ratio>("keyframe_urgent_ratio", 0, 1,
                                               "fast: inliers < ratio x the reference's tracked points (0: never)"),
    number<&SlamParams::keyframe_revisit_age_s>("keyframe_revisit_age_s", 0, 1e6,
                                                "a reference keyframe this old is a known place (0: off)"),
    number<&SlamParams::keyframe_revisit_ratio>("keyframe_revisit_ratio", 0, 1,
                                                "there: a keyframe when inliers < ratio x the reference's tracked points"),
    number<&SlamParams::keyframe_revisit_radius_depths>(
        "keyframe_revisit_radius_depths", 0, 100,
        "... on its line of sight: at most this share of its median depth aside (not the next lane)"),
    number<&SlamParams::process_fps>("process_fps", 0, 120,
                                     "frames processed per second, evenly spaced; the rest skipped (0: all)"),
    nested<&SlamParams::capacity>("capacity", map::kMapCapacityConfig),
    nested<&SlamParams::initializer>("initializer", kInitializerConfig),
    nested<&SlamParams::tracker>("tracker", kTrackerConfig),
    nested<&SlamParams::relocaliser>("relocaliser", kRelocaliserConfig),
    nested<&SlamParams::loop_closing>("loop_closing", kLoopCloserConfig),
    nested<&SlamParams::mapping>("mapping", kLocalMapperConfig),
    nested<&SlamParams::matcher>("matcher", kMatcherConfig),
    nested<&SlamParams::odometry>("odometry", kOdometryConfig),
    nested<&SlamParams::floor>("floor", kFloorConfig),
    flag<&SlamParams::localisation_only>("localisation_only",
                                         "the map is frozen: relocalise and track in the loaded map, add nothing"),
};
constexpr ConfigTable kSlamTable = table_of<SlamParams>(kSlamFields);

}  // namespace

const ConfigTable& slam_config_table() { return kSlamTable; }

Status validate(const SlamParams& p) {
  ALE_RETURN_IF_ERROR(check_ranges(kSlamTable, &p, "slam."));
  if (Status s = geometry::validate(p.initializer.two_view); !s.ok())
    return invalid_argument("slam.initializer.two_view: " + s.message());
  if (Status s = validate(p.odometry); !s.ok()) return invalid_argument("slam." + s.message());
  if (Status s = validate(p.floor); !s.ok()) return invalid_argument("slam." + s.message());
  return {};
}

Result<std::unique_ptr<SlamSystem>> SlamSystem::create(const SlamParams& params, const geometry::Camera& camera, int levels,
                                      float scale_factor, std::shared_ptr<const place::Vocabulary> vocabulary) {
  ALE_RETURN_IF_ERROR(validate(params));
  const geometry::CameraIntrinsics& k = camera.intrinsics();
  if (k.width <= 0 || k.height <= 0) return invalid_argument("slam: the camera has no image size");
  if (levels < 1 || levels > ScalePyramid::kMaxLevels || !(scale_factor > 1.0f)) {
    return invalid_argument("slam: pyramid of " + std::to_string(levels) + " levels, scale " + std::to_string(scale_factor));
  }
  if (vocabulary && vocabulary->empty()) return invalid_argument("slam: the vocabulary is empty");
  return std::unique_ptr<SlamSystem>(
      new SlamSystem(params, camera, ScalePyramid::make(levels, scale_factor), std::move(vocabulary)));
}

SlamSystem::SlamSystem(const SlamParams& params, const geometry::Camera& camera, const ScalePyramid& pyramid,
                       std::shared_ptr<const place::Vocabulary> vocabulary)
    : params_(params),
      map_file_context_{io::MapFileCamera{camera.intrinsics().fx, camera.intrinsics().fy, camera.intrinsics().cx,
                                          camera.intrinsics().cy, camera.intrinsics().width, camera.intrinsics().height,
                                          pyramid.levels, pyramid.scale_factor},
                        vocabulary ? vocabulary->checksum() : 0},
      undistorter_(camera),
      map_(std::make_unique<map::MapStore>(params.capacity)),
      vocabulary_(std::move(vocabulary)),
      places_(vocabulary_ ? std::make_unique<place::KeyframeDatabase>(*vocabulary_, params.capacity) : nullptr),
      initializer_(params.initializer, undistorter_.pinhole(), pyramid, params.matcher),
      tracker_(params.tracker, undistorter_.pinhole(), pyramid, params.matcher),
      relocaliser_(params.relocaliser, undistorter_.pinhole(), pyramid, params.matcher, tracker_.pose_refiner_params()),
      loop_closer_(params.loop_closing, undistorter_.pinhole(), pyramid, undistorter_.bounds(), params.matcher,
                   tracker_.pose_refiner_params(), params.capacity),
      mapper_(params.mapping, undistorter_.pinhole(), pyramid, undistorter_.bounds(), params.matcher),
      keyframe_policy_({params.keyframe_min_frames, params.keyframe_ref_ratio, params.keyframe_min_inliers,
                        params.keyframe_urgent_min_frames, params.keyframe_urgent_ratio,
                        params.loop_closing.enabled ? params.keyframe_revisit_age_s : 0.0,
                        params.keyframe_revisit_ratio, params.keyframe_revisit_radius_depths}),
      map_budget_(params.capacity),
      odometry_(params.odometry),
      floor_(floor_geometry(params.floor, params.odometry.T_bc)),
      gyro_bias_(params.odometry) {
  loop_closer_.set_odometry(&params_.odometry);
  keyframe_policy_.reserve(params.capacity.max_keypoints_per_keyframe);
}

Status SlamSystem::add_odometry(const OdometrySample& sample) { return odometry_.add(sample); }

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
  reset_tracking();
}

// Everything but the map and the trajectory starts over (a new map is being started).
void SlamSystem::reset_tracking() {
  initializer_.reset();
  mapper_.reset();
  loop_closer_.reset();
  loop_keyframe_ = map::KeyframeId{};
  deferred_ = MappingReport{};
  state_ = TrackingState::kNotInitialized;
  motion_.forget();
  lost_frames_ = 0;
  tracker_.forget_turn();
  reference_ = map::KeyframeId{};
  chain_keyframe_ = map::KeyframeId{};
  speed_ = 0.0;
  has_speed_ = false;
  far_chain_ = false;
  anywhere_ = false;
  lost_clock_pending_ = false;
  floor_scaled_ = false;
  floor_candidate_ = 0.0;
  carried_ = false;
  scale_keyframe_ = map::KeyframeId{};
  scale_count_ = 0;
  map_scale_ = 0.0;
}

// The map's two first keyframes: the map (at median depth 1) is put in metres by the floor under
// the second (the camera's height over the floor's distance below it) or, without a floor, by the
// odometry between their frames when it moved the camera far enough. A floor that disagrees with
// the odometry by more than a quarter (a table top taken for the floor) is not used.
void SlamSystem::to_metres(map::KeyframeId k1, map::KeyframeId k2, SlamReport& report) {
  const map::Keyframe* a = map_->keyframe(k1);
  const map::Keyframe* b = map_->keyframe(k2);
  if (!a || !b) return;
  double odometry_factor = 0.0;
  const std::optional<geometry::SE3> motion = odometry_.camera_motion(to_ns(a->timestamp_s), to_ns(b->timestamp_s));
  if (motion) {
    const double metres = motion->translation().norm();
    const double units = (b->T_cw.inverse().translation() - a->T_cw.inverse().translation()).norm();
    if (metres >= params_.odometry.min_init_baseline_m && units > 0.0) {
      odometry_factor = metres / units;
    } else {
      report.message = "odometry baseline " + std::to_string(metres) + " m at initialisation";
    }
  }
  double floor_factor = 0.0;
  if (floor_) {
    if (const std::optional<FloorFit> fit = fit_floor(k2, 0)) {
      floor_factor = floor_->camera_height_m / fit->distance;
      constexpr double kMaxDisagreement = 0.25;
      if (odometry_factor > 0.0 && std::abs(floor_factor / odometry_factor - 1.0) > kMaxDisagreement) {
        report.message = "the floor's scale " + std::to_string(floor_factor) + " disagrees with the odometry's " +
                         std::to_string(odometry_factor) + " at initialisation: the odometry's is used";
        floor_factor = 0.0;
      }
    }
  }
  const double factor = floor_factor > 0.0 ? floor_factor : odometry_factor;
  if (!(factor > 0.0)) {
    if (!report.message.empty()) report.message += ": the map stays unscaled";
    return;
  }
  if (floor_factor > 0.0) report.message.clear();
  floor_scaled_ = floor_factor > 0.0;
  rescale(factor);
  set_metric();
  if (motion) mapper_.set_odometry(&params_.odometry);
  mapper_.set_floor(params_.floor, floor_);
  record_odometry(k1);
  record_odometry(k2);
  check_scale(k1);
  check_scale(k2);
}

// The floor under keyframe `kf` from its landmarks seen by at least `min_observations` keyframes.
std::optional<FloorFit> SlamSystem::fit_floor(map::KeyframeId kf, int min_observations) {
  const map::Keyframe* k = map_->keyframe(kf);
  if (!floor_ || !k) return std::nullopt;
  depth_landmarks_.clear();
  map_->landmarks_of(kf, depth_landmarks_);
  floor_points_.clear();
  for (map::LandmarkId l : depth_landmarks_) {
    const map::Landmark* lm = map_->landmark(l);
    if (lm->num_observations >= min_observations) floor_points_.push_back(k->T_cw * lm->p_w);
  }
  return floor_distance(params_.floor, floor_->up_c, floor_points_, depths_);
}

// The two-view map of initialisation seldom gives the floor (its depths are 20-30 % uncertain),
// so a map still without metres (no odometry) tries again at each keyframe on the last
// keyframe's landmarks seen by at least three keyframes (refined by the local BAs since). Two
// keyframes in a row that agree within 2 % scale the whole map, and every distance the system
// keeps, by their mean; from then on the local BA holds the floor landmarks there. A map the
// odometry put in metres is not rescaled: the floor's landmarks pull it in the local BA.
void SlamSystem::scale_by_floor() {
  if (!floor_ || metric()) return;
  const std::optional<FloorFit> fit = fit_floor(reference_, 3);
  if (!fit) {
    floor_candidate_ = 0.0;
    return;
  }
  const double factor = floor_->camera_height_m / fit->distance;
  constexpr double kAgreement = 0.02;
  const double candidate = floor_candidate_;
  floor_candidate_ = factor;
  if (!(candidate > 0.0) || std::abs(factor / candidate - 1.0) > kAgreement) return;
  rescale(0.5 * (factor + candidate));
  floor_scaled_ = true;
  set_metric();
  mapper_.set_floor(params_.floor, floor_);
}

// Every distance the system keeps, with the map's.
void SlamSystem::rescale(double factor) {
  map_->rescale(factor);
  current_.T_cw = current_.T_cw.scaled(factor);
  last_.T_cw = last_.T_cw.scaled(factor);
  motion_.rescale(factor);
  tracker_.rescale(factor);
  trajectory_.rescale(factor, *map_);
  speed_ *= factor;
  far_centre_ *= factor;
  for (double& r : scale_ratios_) r *= factor;
  map_scale_ *= factor;
}

// Tracking is lost for good (not relocalised) at once in a map this small.
bool SlamSystem::small_map() const {
  return static_cast<int>(map_->stats().map_keyframes) < params_.reset_below_keyframes;
}

// The camera tracked this frame in the map (or relocalised it): the odometry's carrying starts over.
void SlamSystem::seen(double timestamp_s) {
  seen_s_ = timestamp_s;
  coast_m_ = 0.0;
  carried_ = false;
}

// A frame the camera could not track, held by the odometry's motion since the last posed frame
// (report.odometry_prior), within coast_s of the last frame the camera tracked: it may be posed by
// the odometry (coast()), and tracking goes on from it.
bool SlamSystem::can_coast(double timestamp_s, const SlamReport& report) const {
  return report.odometry_prior && state_ == TrackingState::kTracking && params_.odometry.coast_s > 0.0 &&
         timestamp_s - seen_s_ <= params_.odometry.coast_s;
}

// Poses the frame where the odometry's motion since the last posed frame puts it (no
// keyframe_pending_: it has no matches).
void SlamSystem::coast(const geometry::SE3& motion, SlamReport& report) {
  current_.T_cw = motion * last_.T_cw;
  current_.has_pose = true;
  std::fill(current_.landmarks.begin(), current_.landmarks.end(), map::LandmarkId{});
  coast_m_ += motion.translation().norm();
  carried_ = true;
  report.odometry_pose = true;
  report.pose_sigma_m = params_.odometry.prior_sigma(coast_m_);
}

// relocalise() for a frame the turn step tracked from a carried one; its pose and matches are
// kept when that fails.
bool SlamSystem::relocalise_carried(SlamReport& report) {
  if (small_map()) return false;
  const geometry::SE3 T_cw = current_.T_cw;
  carried_landmarks_ = current_.landmarks;
  const std::string message = report.message;
  if (relocalise(report)) {
    seen(current_.timestamp_s);
    motion_.forget();
    tracker_.forget_turn();
    return true;
  }
  current_.T_cw = T_cw;
  current_.landmarks = carried_landmarks_;
  current_.has_pose = true;
  report.message = message;
  return false;
}

// The camera's pose in the frame of the last metric map it was posed in, carried on by the odometry
// from frame to frame while it is not posed (lost, a new map initialising); forgotten without
// odometry between two frames.
void SlamSystem::reckon(bool posed) {
  if (posed) {
    reckoned_ = metric();
    reckoned_T_cw_ = current_.T_cw;
    reckoned_s_ = current_.timestamp_s;
    return;
  }
  if (!reckoned_) return;
  const std::optional<geometry::SE3> T_cw = reckoned_at(current_.timestamp_s);
  reckoned_ = T_cw.has_value();
  if (!T_cw) return;
  reckoned_T_cw_ = *T_cw;
  reckoned_s_ = current_.timestamp_s;
}

// The reckoned pose moved on by the odometry to timestamp_s; nullopt without odometry between.
std::optional<geometry::SE3> SlamSystem::reckoned_at(double timestamp_s) const {
  const std::optional<geometry::SE3> motion = odometry_.camera_motion(to_ns(reckoned_s_), to_ns(timestamp_s));
  if (!motion) return std::nullopt;
  return *motion * reckoned_T_cw_;
}

// A new metric map started after a loss in a metric map, the odometry bridging the two: moved so
// that its keyframe kf (this frame) is where the odometry puts the camera in the old map's frame.
// The poses go on in the frame the robot had (within the odometry's drift over the loss) until a
// merge joins the maps.
void SlamSystem::place_where_reckoned(map::KeyframeId kf, double timestamp_s, SlamReport& report) {
  const map::Keyframe* k = map_->keyframe(kf);
  if (!reckoned_ || !metric() || !k) return;
  const std::optional<geometry::SE3> T_cw = reckoned_at(timestamp_s);
  if (!T_cw) return;
  const geometry::SE3 G = T_cw->inverse() * k->T_cw;
  map_->move(G);
  current_.T_cw = current_.T_cw * G.inverse();
  report.message = "the new map placed where the odometry puts the camera in the last one's frame";
}

// A lost frame in a metric map: where the odometry puts the camera since the last tracked frame.
void SlamSystem::dead_reckon(SlamReport& report) {
  if (!metric() || !last_.has_pose) return;
  const std::optional<geometry::SE3> motion = odometry_.camera_motion(to_ns(last_.timestamp_s), to_ns(current_.timestamp_s));
  if (!motion) return;
  report.odometry_pose = true;
  report.T_cw = *motion * last_.T_cw;
  report.pose_sigma_m = params_.odometry.prior_sigma(motion->translation().norm());
}

void SlamSystem::check_scale(map::KeyframeId kf) {
  const map::Keyframe* b = map_->keyframe(kf);
  if (!b || !b->has_odometry) return;
  const map::Keyframe* a = map_->keyframe(scale_keyframe_);
  if (a && a->has_odometry) {
    const double metres =
        camera_between(params_.odometry.T_bc, keyframe_odometry(*a), keyframe_odometry(*b)).translation().norm();
    constexpr double kMinTravelM = 0.05;
    if (metres < kMinTravelM) return;  // keep the older keyframe as the pair's start
    const double units = (b->T_cw.inverse().translation() - a->T_cw.inverse().translation()).norm();
    scale_ratios_[static_cast<std::size_t>(scale_count_ % static_cast<int>(scale_ratios_.size()))] = units / metres;
    ++scale_count_;
    const std::size_t n = std::min(scale_ratios_.size(), static_cast<std::size_t>(scale_count_));
    std::array<double, 15> sorted = scale_ratios_;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.begin() + static_cast<std::ptrdiff_t>(n));
    map_scale_ = sorted[n / 2];
  }
  scale_keyframe_ = kf;
}

void SlamSystem::record_odometry(map::KeyframeId kf) {
  map::Keyframe* k = map_->keyframe(kf);
  if (!k) return;
  const std::optional<BasePose2> pose = odometry_.at(to_ns(k->timestamp_s));
  k->has_odometry = pose.has_value();
  if (!pose) return;
  k->odometry_x_m = pose->x_m;
  k->odometry_y_m = pose->y_m;
  k->odometry_theta_rad = pose->theta_rad;
}

void SlamSystem::set_metric() { map_->set_metric(map_->current_map(), true); }

bool SlamSystem::metric() const {
  const map::MapInfo* m = map_->map_info(map_->current_map());
  return m && m->metric;
}

// Tracking lost for good: a new map. With map merging the map that ends is kept when it is large
// enough to be recognised (LoopCloserParams::merge), the oldest kept map going beyond max_maps;
// its frames stay relative to its keyframes, resolved at the end.
void SlamSystem::start_new_map(SlamReport& report) {
  const LoopCloserParams& lc = params_.loop_closing;
  const bool merging = places_ && lc.enabled && lc.merge && lc.max_maps > 1;
  const bool keep = merging && static_cast<int>(map_->stats().map_keyframes) >= lc.min_keyframes;
  if (!keep && map_->maps().size() == 1) {
    reset();
  } else {
    // the maps kept before stay; the one that ended goes unless it is kept itself
    const map::MapId ended = map_->current_map();
    take_erased();
    if (!keep) trajectory_.resolve_map(*map_, ended);
    map_->start_map();
    if (!keep) (void)map_->erase_map(ended);
    while (static_cast<int>(map_->maps().size()) > std::max(lc.max_maps, 1)) (void)map_->erase_map(map_->maps()[0].id);
    take_erased();
    reset_tracking();
  }
  ++resets_;
  report.map_reset = true;
}

// The keyframes a lost frame tries, in order: first the reference keyframe and its strongest
// covisible neighbours (the robot is usually near where it was lost), then with a vocabulary the
// keyframe database's candidates for the frame's bag of words, best first; without one a sweep
// over the rest of the map that continues on the next lost frame where this one stopped, so a
// kidnapped robot is tried against every place within a few frames.
void SlamSystem::relocalisation_candidates() {
  candidates_.clear();
  const int near = params_.relocaliser.near_candidates;
  int budget = near;
  auto offer = [&](map::KeyframeId id) {
    if (static_cast<int>(candidates_.size()) >= budget || !map_->keyframe(id)) return;
    if (std::find(candidates_.begin(), candidates_.end(), id) == candidates_.end()) candidates_.push_back(id);
  };
  if (near > 0) offer(reference_);
  if (map_->keyframe(reference_)) {
    for (const map::Covisible& c : map_->covisible_of(reference_)) {
      if (static_cast<int>(candidates_.size()) >= near) break;
      offer(c.keyframe);
    }
  }
  budget = static_cast<int>(candidates_.size()) + params_.relocaliser.max_candidates;
  if (places_) {
    // the places that look like the frame, best first
    places_->sync(*map_);
    descriptors_.clear();
    for (const map::KeyframeFeature& f : current_.features) descriptors_.push_back(f.descriptor);
    vocabulary_->transform(descriptors_.data(), current_.size(), frame_bow_, frame_fv_, places_->params().fv_levels_up);
    places_->relocalisation_candidates(frame_bow_, *map_, place_candidates_);
    for (map::KeyframeId id : place_candidates_) offer(id);
    return;
  }
  keyframe_ids_.clear();
  map_->for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    if (k.map_id == map_->current_map()) keyframe_ids_.push_back(id);
  });
  if (keyframe_ids_.empty()) return;
  for (std::size_t n = 0; n < keyframe_ids_.size() && static_cast<int>(candidates_.size()) < budget; ++n) {
    offer(keyframe_ids_[candidate_cursor_ % keyframe_ids_.size()]);
    ++candidate_cursor_;
  }
}

double SlamSystem::reach(double seconds) {
  const RelocaliserParams& p = params_.relocaliser;
  const double floor = p.reach_floor_depths * keyframe_median_depth(*map_, reference_, depth_landmarks_, depths_);
  return std::max(floor, p.reach_margin * speed_ * seconds);
}

// The odometry's turn against the camera's over this frame (GyroBias), in a metric map; the local
// BA's heading priors follow the estimate.
void SlamSystem::measure_gyro_bias(int inliers) {
  if (!metric() || !last_.has_pose) return;
  const std::optional<BasePose2> a = odometry_.at(to_ns(last_.timestamp_s));
  const std::optional<BasePose2> b = odometry_.at(to_ns(current_.timestamp_s));
  if (!a || !b) return;
  // the camera's rotation from the last frame about the floor's normal (the base's z in the camera)
  const Eigen::AngleAxisd turn(current_.T_cw.rotation() * last_.T_cw.rotation().transpose());
  const double camera_turn = -(turn.angle() * turn.axis()).dot(floor_normal_in_camera(params_.odometry.T_bc));
  const double odometry_turn = angle_difference(b->theta_rad, a->theta_rad);
  gyro_bias_.add(odometry_turn, camera_turn, current_.timestamp_s - last_.timestamp_s, inliers);
  mapper_.set_gyro_bias(gyro_bias_.rate_rps());
}

void SlamSystem::measure_speed() {
  const double dt = current_.timestamp_s - last_.timestamp_s;
  if (!(dt > 0.0)) return;
  const double v = (current_.T_cw.inverse().translation() - last_.T_cw.inverse().translation()).norm() / dt;
  // smoothed over about kSpeedSmoothingS of tracked frames
  constexpr double kSpeedSmoothingS = 0.5;
  speed_ = has_speed_ ? speed_ + dt / (dt + kSpeedSmoothingS) * (v - speed_) : v;
  has_speed_ = true;
}

// A pose beyond the reach is taken once lost frames have put the camera there, each within the
// reach of the one before, for far_confirm_s, and no candidate within the reach showed evidence
// meanwhile (RelocaliserParams::far_confirm_s, core/slam/relocaliser.h).
bool SlamSystem::far_confirmed(const RelocaliseReport& rr, double timestamp_s, SlamReport& report) {
  const double confirm_s = params_.relocaliser.far_confirm_s;
  if (rr.near_evidence) {
    far_chain_ = false;
    report.message += "; relocalised beyond the reach while a pose within it had evidence: refused";
    return false;
  }
  const geometry::Vec3 centre = current_.T_cw.inverse().translation();
  const bool consistent = far_chain_ && (centre - far_centre_).norm() <= reach(timestamp_s - far_last_s_);
  if (!consistent) far_since_s_ = timestamp_s;
  far_chain_ = true;
  far_centre_ = centre;
  far_last_s_ = timestamp_s;
  // timestamps in ns: a frame period's rounding must not cost a frame
  if (timestamp_s - far_since_s_ + 1e-6 >= confirm_s) return true;
  report.message += "; relocalised beyond the reach, confirmed for " + std::to_string(timestamp_s - far_since_s_) +
                    " of " + std::to_string(confirm_s) + " s";
  return false;
}

bool SlamSystem::relocalise(SlamReport& report) {
  const std::int64_t start = clock_();
  relocalisation_candidates();
  report.relocalisation_candidates = static_cast<int>(candidates_.size());
  // where the robot was last tracked, and how far it can have gone since
  const double timestamp_s = current_.timestamp_s;
  Continuity continuity;
  continuity.centre = last_.T_cw.inverse().translation();
  continuity.reach = reach(timestamp_s - last_.timestamp_s);
  const RelocaliseReport rr = relocaliser_.relocalise(current_, *map_, candidates_, places_.get(),
                                                      places_ ? &frame_fv_ : nullptr, anywhere_ ? nullptr : &continuity);
  report.place_ns += clock_() - start;
  if (!rr.ok) {
    if (rr.near_evidence) far_chain_ = false;
    report.message += "; " + rr.message;
    return false;
  }
  if (rr.far && params_.relocaliser.far_confirm_s > 0.0 && !far_confirmed(rr, timestamp_s, report)) {
    current_.has_pose = false;
    std::fill(current_.landmarks.begin(), current_.landmarks.end(), map::LandmarkId{});
    return false;
  }
  map::KeyframeId reference = rr.keyframe;
  TrackReport tr;
  if (!tracker_.track_local_map(current_, *map_, &reference, tr)) {
    current_.has_pose = false;
    std::fill(current_.landmarks.begin(), current_.landmarks.end(), map::LandmarkId{});
    report.message += "; relocalised, then " + tr.message;
    return false;
  }
  current_.has_pose = true;
  reference_ = reference;
  chain_keyframe_ = reference;
  report.inliers = tr.inliers;
  report.relocalised = true;
  report.message.clear();
  anywhere_ = false;
  ++relocalisations_;
  return true;
}

void SlamSystem::insert_keyframe(SlamReport& report) {
  scale_by_floor();
  map_budget_.make_room(*map_, reference_, report.mapping);
  Result<map::KeyframeId> kf =
      map_->add_keyframe(current_.timestamp_s, current_.sequence, current_.T_cw, current_.features.data(), current_.size());
  if (!kf.ok()) {
    report.message = "keyframe not inserted: " + kf.status().message();
    return;
  }
  if (metric()) {
    record_odometry(*kf);
    check_scale(*kf);
  }
  // after make_room's evictions; a keyframe of the turn step may share no landmark with the
  // map: it also triangulates with the keyframe before it
  report.mapping += mapper_.process(*kf, current_, *map_, keyframe_in_turn_ ? reference_ : map::KeyframeId{});
  report.keyframe_inserted = true;
  reference_ = *kf;
  loop_keyframe_ = *kf;
  chain_keyframe_ = *kf;
  keyframe_policy_.keyframe_made();
  // the frame's matches now follow the map (fused or culled landmarks)
  const map::LandmarkId* ids = map_->keypoint_landmarks(*kf);
  for (int i = 0; i < current_.size(); ++i) current_.landmarks[static_cast<std::size_t>(i)] = ids[i];
}

void SlamSystem::finish_mapping() {
  const bool adjusting = mapper_.has_pending();
  if (adjusting) {
    const map::KeyframeId kf = mapper_.pending();
    deferred_ += mapper_.finish_pending(*map_);
    take_erased();
    // The keyframe's frame is the last one now: its matches follow the map after the BA's outlier
    // removal, as they did when the BA ran inside insert_keyframe().
    const map::Keyframe* k = map_->keyframe(kf);
    if (k && k->frame_seq == last_.sequence && k->num_features == last_.size()) {
      const map::LandmarkId* ids = map_->keypoint_landmarks(kf);
      for (int i = 0; i < last_.size(); ++i) last_.landmarks[static_cast<std::size_t>(i)] = ids[i];
    }
  }
  close_loop(adjusting);
}

// The last keyframe looked up for a loop, after its local BA and culling, or the next step of a
// loop's correction (on a frame without a local BA); the system's own poses and lengths follow
// what moved.
void SlamSystem::close_loop(bool adjusted) {
  const map::KeyframeId kf = loop_keyframe_;
  loop_keyframe_ = map::KeyframeId{};
  if (!places_ || !params_.loop_closing.enabled) return;
  if (!loop_closer_.busy() && !map_->keyframe(kf)) return;
  // a frame that paid for a local BA does not also pay for a step of a loop's correction
  if (loop_closer_.busy() && adjusted) return;
  const std::int64_t start = clock_();
  places_->sync(*map_);
  loop_ = loop_closer_.step(kf, *map_, *places_, metric(), mapper_);
  if (loop_closer_.moved()) {
    take_erased();
    follow_loop(loop_.keyframe);
  }
  // the poses go on in the older map's frame and units (metric() is the older map's)
  if (loop_.merged) far_chain_ = false;
  loop_ns_ += clock_() - start;
}

// After a closed loop: the last tracked frame keeps its pose relative to its reference keyframe
// (its length in that keyframe's corrected units), and so do the trajectory's frames; the
// velocity, the turn step's depth and the speed take the reference's new units.
void SlamSystem::follow_loop(map::KeyframeId kf) {
  const map::KeyframeId ref = map_->keyframe(reference_) ? reference_ : kf;
  const double factor = loop_closer_.length_factor(ref);
  if (last_.has_pose && map_->keyframe(ref)) {
    const geometry::SE3 T_lr = (last_.T_cw * loop_closer_.pose_before(ref, *map_).inverse()).scaled(factor);
    last_.T_cw = T_lr * map_->keyframe(ref)->T_cw;
  }
  motion_.rescale(factor);
  tracker_.rescale(factor);
  speed_ *= factor;
  trajectory_.rescale_relative([this](map::KeyframeId k) { return loop_closer_.length_factor(k); });
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
    return frame_rejected("slam: frame " + std::to_string(sequence) + " has timestamp " + std::to_string(timestamp_s) +
                            " s, not after the previous " + std::to_string(last_timestamp_s_) + " s");
  }
  last_timestamp_s_ = timestamp_s;
  report_ = SlamReport{};
  SlamReport& report = report_;
  report.mapping = deferred_;  // the last keyframe's local BA, run by finish_mapping() before this frame
  deferred_ = MappingReport{};
  report.loop = loop_;
  report.loop_ns = loop_ns_;
  loop_ = LoopReport{};
  loop_ns_ = 0;
  keyframe_pending_ = false;

  current_.timestamp_s = timestamp_s;
  current_.sequence = sequence;
  undistorter_.apply(features, params_.capacity.max_keypoints_per_keyframe, current_);
  report.features = current_.size();
  keyframe_policy_.frame_arrived();

  if (params_.localisation_only && map_->stats().map_keyframes == 0) {
    report.message = "localisation only: no map loaded";
  } else if (state_ == TrackingState::kNotInitialized || state_ == TrackingState::kInitializing) {
    map::KeyframeId k1, k2;
    const InitReport ir = initializer_.add_frame(current_, *map_, &k1, &k2);
    report.matches = ir.matches;
    if (ir.state == InitState::kInitialized) {
      state_ = TrackingState::kTracking;
      seen(timestamp_s);
      reference_ = k2;
      chain_keyframe_ = k2;
      keyframe_policy_.keyframe_made();
      motion_.forget();
      to_metres(k1, k2, report);
      place_where_reckoned(k2, timestamp_s, report);
      std::vector<map::LandmarkId> lms;
      map_->landmarks_of(k2, lms);
      for (map::LandmarkId l : lms) mapper_.add_recent(l, k1);
      report.inliers = current_.matched();
    } else {
      state_ = ir.state == InitState::kWaiting ? TrackingState::kInitializing : TrackingState::kNotInitialized;
      report.message = ir.message;
    }
  } else {
    // the constant-velocity prediction from the last tracked frame: once per frame since
    bool predict = motion_.available() && (state_ == TrackingState::kTracking || lost_frames_ < params_.coast_frames);
    geometry::SE3 velocity = motion_.velocity();
    for (int i = 0; predict && i < lost_frames_; ++i) velocity = motion_.velocity() * velocity;
    // in a metric map the odometry's motion since the last tracked frame replaces it
    double odometry_sigma = 0.0;
    if (metric()) {
      if (const std::optional<geometry::SE3> motion = odometry_.camera_motion(to_ns(last_.timestamp_s), to_ns(timestamp_s))) {
        velocity = *motion;
        predict = true;
        odometry_sigma = params_.odometry.prior_sigma(motion->translation().norm());
        report.odometry_prior = true;
      }
    }
    TrackReport tr;
    if (anywhere_) {
      tr.message = "not yet relocalised in the loaded map";
    } else {
      tr = tracker_.track(current_, last_, velocity, predict, *map_, &reference_, odometry_sigma);
    }
    report.matches = tr.matches;
    report.inliers = tr.inliers;
    if (tr.ok && odometry_sigma > 0.0) {
      // the vision's centre beyond the prior's 95 % gate: a wheel slipped, spun or stuck
      const geometry::Vec3 predicted = (velocity * last_.T_cw).inverse().translation();
      const double chi2 = (current_.T_cw.inverse().translation() - predicted).squaredNorm() / (odometry_sigma * odometry_sigma);
      if (chi2 > geometry::kChi2ThreeDof95) ++odometry_disagreements_;
    }
    // The turn step from a frame the odometry carried: its bearings only continue a pose the camera
    // never saw (after a kidnap the wheels did not feel, two frames of the new place match each
    // other well), so a relocalisation comes first, and the frame stays carried.
    if (tr.ok && tr.turn && carried_ && relocalise_carried(report)) {
      tr.turn = false;
    } else if (tr.ok && tr.turn && carried_) {
      seen_s_ = timestamp_s;  // the bearings tracked it: the carrying window goes on
      coast_m_ += velocity.translation().norm();
      report.odometry_pose = true;
      report.pose_sigma_m = params_.odometry.prior_sigma(coast_m_);
    } else if (tr.ok) {
      seen(timestamp_s);
    }
    if (tr.ok) {
      // after coasting, the per-frame velocity stays the one measured before
      if (state_ == TrackingState::kTracking && !report.relocalised) {
        motion_.tracked(current_.T_cw, last_.T_cw);
        measure_speed();
        if (!tr.turn && !carried_) measure_gyro_bias(tr.inliers);
      }
      state_ = TrackingState::kTracking;
      lost_frames_ = 0;
      keyframe_in_turn_ = tr.turn;
      keyframe_pending_ = tr.turn ? keyframe_policy_.needs_keyframe_in_turn()
                                  : keyframe_policy_.needs_keyframe(tr.inliers, *map_, reference_, timestamp_s,
                                                                    current_.T_cw.inverse().translation());
      // no keyframe where the camera is beyond the reach of a carried pose (a relocalisation there
      // awaits its confirmation): the map would be extended at the wrong place
      if (params_.localisation_only || report.relocalised || (report.odometry_pose && far_chain_))
        keyframe_pending_ = false;
    } else {
      report.message = tr.message;
      // the odometry carries tracking for a while (a kidnap it does not see is still relocalised)
      const bool coasting = can_coast(timestamp_s, report);
      if (state_ == TrackingState::kTracking && !coasting) {
        state_ = TrackingState::kLost;
        lost_since_s_ = timestamp_s;
        lost_frames_ = 0;
        far_chain_ = false;
      }
      if (lost_clock_pending_) start_in_loaded_map(timestamp_s);
      if (++lost_frames_ > params_.coast_frames) motion_.forget();
      const bool small = small_map();
      if (!small && relocalise(report)) {
        state_ = TrackingState::kTracking;
        seen(timestamp_s);
        lost_frames_ = 0;
        motion_.forget();
        tracker_.forget_turn();
      } else if (coasting) {
        coast(velocity, report);
        report.message += "; posed by the odometry";
      } else if (!params_.localisation_only && (small || timestamp_s - lost_since_s_ > params_.lost_timeout_s)) {
        start_new_map(report);
        report.message += "; a new map starts";
      }
      // otherwise the last frame with a pose stays the one to re-track from
      if (!report.relocalised && !report.map_reset && !coasting) dead_reckon(report);
    }
  }
  report.state = report.relocalised ? TrackingState::kRelocalized : state_;
  report.relocalisations = relocalisations_;
  report.loops_closed = loop_closer_.loops_closed();
  report.loops_refused = loop_closer_.loops_refused();
  report.merges = loop_closer_.merges();
  report.merges_refused = loop_closer_.merges_refused();
  report.metric = metric();
  report.floor_scaled = floor_scaled_;
  report.map_scale = map_scale_;
  report.odometry_disagreements = odometry_disagreements_;
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
  if (places_) {
    const std::int64_t start = clock_();
    places_->sync(*map_);
    report.place_ns += clock_() - start;
  }
  reckon(report.has_pose);
  if (report.has_pose) {
    // the SLAM's trajectory holds what the camera tracked: a pose the odometry carried may be
    // wrong without anyone noticing (a kidnap the wheels did not feel, until a relocalisation)
    // A frame the turn step tracked is posed from the last frame on bearings: it stays with the
    // keyframe its chain of frames last passed, not with the older one that shares the most of its
    // few landmarks (metres away, so that a later BA's turn of it moves the frame as far: on a dark
    // lane 1-2 m).
    const map::KeyframeId ref = keyframe_in_turn_ && map_->keyframe(chain_keyframe_) ? chain_keyframe_ : reference_;
    if (record_trajectory_ && !report.odometry_pose)
      trajectory_.add(current_.timestamp_s, current_.sequence, ref, current_.T_cw, *map_);
    report.T_cw = current_.T_cw;
    std::swap(current_, last_);
  }
  const map::MapStats ms = map_->stats();
  report.map_id = ms.map_id;
  report.resets = resets_;
  report.keyframes = ms.keyframes;
  report.landmarks = ms.landmarks;
  report.keyframe_capacity = ms.keyframe_capacity;
  report.keyframes_high_water = ms.keyframes_high_water;
  report.landmark_capacity = ms.landmark_capacity;
  report.landmarks_high_water = ms.landmarks_high_water;
}

// The first frame after load_map(): the lost clock starts, and the loaded keyframes' times move so
// that the newest is a second before this frame. The camera's clock of the run that saved them
// (monotonic since that boot, or a replay's) says nothing about this one's, while the map's
// "oldest first" (the budget's eviction) and the loop closer's path between two keyframes go by
// time; shifted together, the loaded keyframes keep their order and spacing.
void SlamSystem::start_in_loaded_map(double timestamp_s) {
  lost_since_s_ = timestamp_s;
  lost_clock_pending_ = false;
  double newest = -1e300;
  map_->for_each_keyframe([&](map::KeyframeId, const map::Keyframe& k) { newest = std::max(newest, k.timestamp_s); });
  const double shift = (timestamp_s - 1.0) - newest;
  map_->for_each_keyframe([&](map::KeyframeId id, const map::Keyframe&) { map_->keyframe(id)->timestamp_s += shift; });
}

Result<io::MapFileSummary> SlamSystem::save_map(const std::string& path) const {
  return io::save_map_file(*map_, map_file_context_, path);
}

Result<io::MapFileSummary> SlamSystem::load_map(const std::string& path) {
  Result<io::MapFileSummary> checked = io::check_map_file(path, map_file_context_, params_.capacity);
  if (!checked.ok()) return checked;
  reset();
  Result<io::MapFileSummary> loaded = io::load_map_file(path, map_file_context_, *map_);
  if (!loaded.ok()) return loaded;  // the store is empty: the next frames start a map
  if (loaded->keyframes == 0) return loaded;
  // the wheel odometry of the run that saved the map is another frame than this run's: the
  // loaded keyframes have none (odometry priors and checks link keyframes of this run only)
  map_->for_each_keyframe([&](map::KeyframeId id, const map::Keyframe&) { map_->keyframe(id)->has_odometry = false; });
  // lost in the loaded map, as after a kidnap: relocalisation from anywhere in it
  state_ = TrackingState::kLost;
  lost_frames_ = params_.coast_frames + 1;
  last_.has_pose = false;
  anywhere_ = true;
  lost_clock_pending_ = true;
  if (metric()) {
    floor_scaled_ = floor_.has_value();
    mapper_.set_odometry(&params_.odometry);
    mapper_.set_floor(params_.floor, floor_);
  }
  if (places_) places_->sync(*map_);
  return loaded;
}

}  // namespace ale::slam
