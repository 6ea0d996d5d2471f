// The SLAM core's per-frame step (spec section 7), a state machine over its units: the keypoints
// are undistorted (KeypointUndistorter); until a map exists the Initializer tries frame pairs;
// then the Tracker poses each frame from the MotionPrior or the reference keyframe and the local
// map, the KeyframePolicy decides on keyframes, the MapBudget makes room in the fixed map and the
// LocalMapper maps inline. When tracking is lost it keeps trying against the last keyframes for a
// configured time, then resets and initialises a new map (counting resets). One thread,
// deterministic: the same frames give the same poses on every run.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/config_table.h"
#include "core/base/frame_record.h"
#include "core/base/frame_state.h"
#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/io/map_file.h"
#include "core/map/map_store.h"
#include "core/place/keyframe_database.h"
#include "core/place/vocabulary.h"
#include "core/slam/floor.h"
#include "core/slam/frame.h"
#include "core/slam/initializer.h"
#include "core/slam/keyframe_policy.h"
#include "core/slam/local_mapper.h"
#include "core/slam/loop_closer.h"
#include "core/slam/map_budget.h"
#include "core/slam/motion_prior.h"
#include "core/slam/odometry.h"
#include "core/slam/refined_trajectory.h"
#include "core/slam/relocaliser.h"
#include "core/slam/tracker.h"
#include "core/slam/undistortion.h"

namespace ale::slam {

struct SlamParams {
  map::MapCapacity capacity;
  InitializerParams initializer;
  TrackerParams tracker;
  LocalMapperParams mapping;
  MatcherParams matcher;              // for the initialiser, the tracker and the local mapper
  RelocaliserParams relocaliser;
  // Loop closing (core/slam/loop_closer.h): needs the vocabulary's keyframe database; off, the
  // trajectories are those of a core without it.
  LoopCloserParams loop_closing;
  // When tracking is lost, relocalisation is tried on every frame for this long; then, or at once
  // when the map has fewer than reset_below_keyframes keyframes, a new map starts.
  double lost_timeout_s = 3.0;
  int reset_below_keyframes = 3;      // a map this small is reset at once when tracking is lost
  // The first lost frames are still tracked against the map from where the constant-velocity
  // model puts them (the motion of the last tracked frame, applied once per frame since): a turn
  // on the spot goes on turning, while the last pose alone is a whole turn step behind each frame.
  // After coast_frames lost frames the model is forgotten. 0: forgotten at once.
  int coast_frames = 5;
  // Frames between keyframes at least. ORB-SLAM's 0 relies on its mapping thread being busy to
  // space keyframes out; inline mapping is never busy, so the view-change test alone would insert
  // nearly every frame of a sweeper (the floor ahead changes fast): measured on a rendered 40 s
  // loop, 0 gave 200 keyframes (the map full), 18.5 cm ATE and 307 ms mapping per frame; 6 gave
  // 81 keyframes, 5.0 cm and 38 ms (docs/slam.md). 7: 47.4 instead of 54.8 M ARM
  // instructions a frame at about the same accuracy on twelve loops (docs/performance.md).
  int keyframe_min_frames = 7;
  double keyframe_ref_ratio = 0.9;    // insert when tracked < ratio * reference keyframe's
  int keyframe_min_inliers = 15;
  // A turn on the spot takes the view off the map within a few frames: when a frame tracks fewer
  // than keyframe_urgent_ratio of the reference keyframe's landmarks, a keyframe comes after
  // keyframe_urgent_min_frames already, so the map follows the new view (core/slam/keyframe_policy.h).
  int keyframe_urgent_min_frames = 3;
  double keyframe_urgent_ratio = 0.5;
  // Back in a known place (the reference keyframe older than keyframe_revisit_age_s, the camera
  // on its line of sight: at most keyframe_revisit_radius_depths of its median depth aside of it;
  // the next cleaning lane is farther aside), a keyframe only
  // when the frame tracks fewer than keyframe_revisit_ratio of its landmarks, so laps over the
  // same rooms do not grow the map (core/slam/keyframe_policy.h). With loop closing only
  // (slam.loop_closing.enabled): off, the trajectories are those of a core without it. 0: off.
  double keyframe_revisit_age_s = 10.0;
  double keyframe_revisit_ratio = 0.5;
  double keyframe_revisit_radius_depths = 0.05;
  // Frames per second the SLAM processes when the camera delivers more: the caller picks evenly
  // spaced frames by their timestamps and releases the rest unprocessed (the daemon's
  // FrameSelector; the robot profile, board/mr133/ale-slamd.conf, says 15 of the sensor's 30).
  // The system itself processes every frame it is given. 0: every frame.
  double process_fps = 0;
  // Wheel odometry (core/slam/odometry.h): its buffer's checks and the camera's mounting on the
  // base. Used only when samples are given (add_odometry); without them everything is as before.
  OdometryParams odometry;
  // The floor as a scale cue (core/slam/floor.h), from the camera's mounting odometry.T_bc: with
  // its height known the map is in metres from initialisation, odometry or not.
  FloorParams floor;
  // Localisation only: the map is frozen (no keyframe, no local mapping, no loop closing, no new
  // map): the robot relocalises in the loaded map and tracks against it. Without a map it waits.
  bool localisation_only = false;
};

// kInvalidArgument naming the first field out of range.
Status validate(const SlamParams& p);
// The keys of SlamParams a deployment tunes (core/base/config_table.h; the daemon's `slam.*`).
const ConfigTable& slam_config_table();

struct SlamReport {
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
  geometry::SE3 T_cw;               // when has_pose
  int features = 0;
  int matches = 0;
  int inliers = 0;
  bool keyframe_inserted = false;
  bool map_reset = false;            // this frame started a new map (a new trajectory segment)
  std::uint32_t map_id = 0;
  int resets = 0;
  bool relocalised = false;          // this frame was posed by relocalisation (state kRelocalized)
  int relocalisations = 0;           // since start
  int relocalisation_candidates = 0; // keyframes this frame tried to relocalise against
  bool metric = false;               // the map is in metres (the floor or the odometry at initialisation)
  bool floor_scaled = false;         // ... by the floor (core/slam/floor.h), not the odometry
  bool odometry_prior = false;       // this frame was predicted and held by the odometry
  // Posed by the odometry alone: T_cw is the last posed frame moved on by the odometry since,
  // pose_sigma_m how far off it may be by now (metres). Within OdometryParams::coast_s of the last
  // frame the camera tracked, the frame is tracked that way (has_pose, state kTracking); after that
  // it is lost (has_pose false) and the pose only reported.
  bool odometry_pose = false;
  double pose_sigma_m = 0.0;
  // The map's scale against the odometry: map units per metre of camera travel, the median over
  // the last 15 keyframe pairs that moved at least 5 cm (1 in a metric map that kept its scale; 0
  // while unknown). The scale confidence the motion controller can watch.
  double map_scale = 0.0;
  // Tracked frames (since start) whose camera centre the vision put beyond the 95 % gate of the
  // odometry's prior: a wheel that slipped, spun or stuck (the prior's Huber kernel let the
  // vision win).
  int odometry_disagreements = 0;
  // Place recognition's time in this frame, a part of the `track` and `map` stages: on a lost
  // frame the bag of words, the keyframe database's query and the relocaliser (candidates, matching,
  // PnP, refinement); on every frame the database's sync with the map (the new keyframes' bags of
  // words into the inverted index, erased ones out). The clock of set_clock().
  std::int64_t place_ns = 0;
  // Loop closing, run before this frame was tracked (on the keyframe before it): what the lookup
  // found (loop.closed: the map and the poses moved), the counts since start, and its time (a part
  // of the `map_ba` stage; the clock of set_clock()).
  LoopReport loop;
  int loops_closed = 0;
  int loops_refused = 0;              // verified loops the correction bound refused (look-alike places)
  // Maps joined since start: a keyframe of the current map recognised a place of an older map
  // kept since tracking was lost, and the current map moved into it (its poses continue in the
  // older map's frame and map_id). merges_refused: verified places of another map not joined
  // (the map or its keyframe gone before the merge, a degenerate similarity).
  int merges = 0;
  int merges_refused = 0;
  std::int64_t loop_ns = 0;
  // Held in the store, every map together (the one budget counts them all).
  std::size_t keyframes = 0;
  std::size_t landmarks = 0;
  // The map store's fixed arenas: their capacity and how full they ever got.
  std::size_t keyframe_capacity = 0, keyframes_high_water = 0;
  std::size_t landmark_capacity = 0, landmarks_high_water = 0;
  MappingReport mapping;
  std::string message;               // why there is no pose
};

class SlamSystem {
 public:
  // camera: the real camera (with its distortion) of the keypoints handed to process();
  // levels/scale_factor: the front end's pyramid. vocabulary: for place recognition (the keyframe
  // database relocalisation takes its candidates from); without one a lost frame tries the
  // reference keyframe's neighbourhood and a sweep over the map, matched exhaustively.
  static Result<std::unique_ptr<SlamSystem>> create(const SlamParams& params, const geometry::Camera& camera, int levels,
                                   float scale_factor, std::shared_ptr<const place::Vocabulary> vocabulary = nullptr);

  // One frame: `features` holds the keypoints in distorted pixels (u, v), their level, angle and
  // descriptor; they are undistorted here (keypoints that cannot be are dropped). Timestamps
  // must increase (kFrameRejected otherwise, nothing changes).
  Result<SlamReport> process(double timestamp_s, std::uint64_t sequence, const std::vector<map::KeyframeFeature>& features);

  // process() in three parts, for the frame path's `map_ba`, `track` and `map` stages
  // (core/slam/slam_pipeline.h): finish_mapping() runs the local BA and keyframe culling that the
  // last keyframe deferred (LocalMapperParams::defer_ba) before the next frame is tracked, so the
  // trajectory is the one without deferral while no frame pays for a whole keyframe; its figures
  // go into the next frame's report. track_frame() initialises or tracks the frame and takes the
  // keyframe decision; map_frame() inserts the keyframe and runs local mapping when one was decided, then hands
  // the frame on as the last one. report() is the frame's report once map_frame() has run. A
  // track_frame() that fails (kFrameRejected for a timestamp that does not increase) changes nothing, and the
  // map_frame() after it does nothing.
  void finish_mapping();
  // One odometry report, in the order the MCU sent them, before the frames it precedes are
  // processed. kFrameRejected naming the problem (counted in odometry()) for a bad sample.
  Status add_odometry(const OdometrySample& sample);
  const OdometryBuffer& odometry() const { return odometry_; }
  Status track_frame(double timestamp_s, std::uint64_t sequence, const std::vector<map::KeyframeFeature>& features);
  void map_frame();
  const SlamReport& report() const { return report_; }

  // The frames' poses relative to their reference keyframes (core/slam/refined_trajectory.h),
  // kept while record_trajectory(true): resolve_trajectory() composes those of the current map
  // with its keyframes' poses now (reset() does it for the map it ends).
  void record_trajectory(bool on) { record_trajectory_ = on; }
  void resolve_trajectory();
  const RefinedTrajectory& trajectory() const { return trajectory_; }

  const map::MapStore& map() const { return *map_; }
  TrackingState state() const { return state_; }
  // The clock SlamReport::place_ns is taken with (steady_clock_ns by default; the frame path's).
  void set_clock(MonotonicClock clock) { clock_ = clock; }
  void reset();

  // The map file (core/io/map_file.h): every map held, written between two frames (what the
  // next frame's tracking changes is not in it). The camera and the vocabulary are recorded.
  Result<io::MapFileSummary> save_map(const std::string& path) const;
  // Replaces every map held by the file's. The file is checked whole first: a file that is
  // refused (missing, corrupt, another version, vocabulary or camera, too large for the store's
  // capacity) changes nothing. Then the system is lost in the file's current map and the next
  // frames relocalise anywhere in it (no continuity prior: the robot may have been carried since
  // the save), tracking in its frame and map_id; when that fails for lost_timeout_s a new map
  // starts as always, and the loaded ones are kept for merging (slam.loop_closing.merge).
  Result<io::MapFileSummary> load_map(const std::string& path);
  const io::MapFileContext& map_file_context() const { return map_file_context_; }

 private:
  SlamSystem(const SlamParams& params, const geometry::Camera& camera, const ScalePyramid& pyramid,
             std::shared_ptr<const place::Vocabulary> vocabulary);
  void insert_keyframe(SlamReport& report);
  void start_new_map(SlamReport& report);
  void reset_tracking();
  void start_in_loaded_map(double timestamp_s);
  void set_metric();
  // The current map is in metres (MapInfo::metric: the floor or the odometry scaled it).
  bool metric() const;
  void to_metres(map::KeyframeId k1, map::KeyframeId k2, SlamReport& report);
  std::optional<FloorFit> fit_floor(map::KeyframeId kf, int min_observations);
  void scale_by_floor();
  void rescale(double factor);
  void record_odometry(map::KeyframeId kf);
  void dead_reckon(SlamReport& report);  // the odometry's base pose at its time, when known
  bool small_map() const;
  void seen(double timestamp_s);
  bool can_coast(double timestamp_s, const SlamReport& report) const;
  void coast(const geometry::SE3& motion, SlamReport& report);
  bool relocalise_carried(SlamReport& report);
  void reckon(bool posed);
  std::optional<geometry::SE3> reckoned_at(double timestamp_s) const;
  void place_where_reckoned(map::KeyframeId kf, double timestamp_s, SlamReport& report);
  void take_erased();
  void close_loop(bool adjusted);
  void follow_loop(map::KeyframeId kf);
  bool relocalise(SlamReport& report);
  void relocalisation_candidates();
  // How far the robot can have gone in `seconds` (map units; RelocaliserParams' reach).
  double reach(double seconds);
  void measure_speed();
  void measure_gyro_bias(int inliers);
  bool far_confirmed(const RelocaliseReport& rr, double timestamp_s, SlamReport& report);

  SlamParams params_;
  io::MapFileContext map_file_context_;
  KeypointUndistorter undistorter_;
  std::unique_ptr<map::MapStore> map_;
  std::shared_ptr<const place::Vocabulary> vocabulary_;
  std::unique_ptr<place::KeyframeDatabase> places_;  // when there is a vocabulary
  std::vector<features::Descriptor> descriptors_;    // the lost frame's, for its bag of words
  place::BowVector frame_bow_;
  place::FeatureVector frame_fv_;
  Initializer initializer_;
  Tracker tracker_;
  Relocaliser relocaliser_;
  LoopCloser loop_closer_;
  // the newest keyframe, or the one a relocalisation tracked from: what turn-step frames are kept
  // relative to in the trajectory
  map::KeyframeId chain_keyframe_;
  map::KeyframeId loop_keyframe_;  // the last keyframe, looked up for a loop once its BA ran
  LoopReport loop_;                 // close_loop()'s figures, for the next track_frame()'s report
  std::int64_t loop_ns_ = 0;
  std::vector<map::KeyframeId> candidates_;  // scratch of relocalisation_candidates()
  std::vector<map::KeyframeId> place_candidates_;
  std::vector<map::LandmarkId> depth_landmarks_;  // scratch of reach()
  std::vector<double> depths_;
  std::vector<map::KeyframeId> keyframe_ids_;
  std::size_t candidate_cursor_ = 0;         // where the next lost frame's sweep over the map starts
  int relocalisations_ = 0;
  MonotonicClock clock_ = steady_clock_ns;
  LocalMapper mapper_;
  KeyframePolicy keyframe_policy_;
  MapBudget map_budget_;
  MotionPrior motion_;
  OdometryBuffer odometry_;
  std::optional<FloorGeometry> floor_;  // the camera's height is known
  std::vector<geometry::Vec3> floor_points_;  // scratch of fit_floor()
  bool floor_scaled_ = false;     // the map's scale is the floor's (to_metres or scale_by_floor)
  double floor_candidate_ = 0.0;  // scale_by_floor's last factor, confirmed by the next
  // map_scale: the last keyframe with an odometry pose, and the recent pairs' ratios (a ring)
  map::KeyframeId scale_keyframe_;
  std::array<double, 15> scale_ratios_{};
  int scale_count_ = 0;
  double map_scale_ = 0.0;
  int odometry_disagreements_ = 0;
  void check_scale(map::KeyframeId kf);
  TrackingState state_ = TrackingState::kNotInitialized;
  Frame current_, last_;
  map::KeyframeId reference_;
  double last_timestamp_s_ = -1e300;
  double lost_since_s_ = 0.0;
  double seen_s_ = 0.0;           // the last frame the camera tracked (seen(), coast())
  double coast_m_ = 0.0;          // the odometry's travel since
  bool carried_ = false;          // the last posed frame was carried by the odometry (coast()), or
                                  // turn-stepped from one: not a pose the camera saw in the map
  std::vector<map::LandmarkId> carried_landmarks_;  // scratch of relocalise_carried()
  // reckon(): the camera's pose in the last metric map's frame, at reckoned_s_, while reckoned_
  bool reckoned_ = false;
  geometry::SE3 reckoned_T_cw_;
  double reckoned_s_ = 0.0;
  int lost_frames_ = 0;           // frames since the last tracked one, while lost
  int resets_ = 0;
  // the camera's speed over the last tracked frames (map units per second), for the reach
  double speed_ = 0.0;
  GyroBias gyro_bias_;
  bool has_speed_ = false;
  // a relocalisation beyond the reach being confirmed: since when, where the last frame put it
  bool far_chain_ = false;
  // lost in a loaded map: relocalise anywhere in it, the lost clock starting at the next frame
  bool anywhere_ = false;
  bool lost_clock_pending_ = false;
  double far_since_s_ = 0.0, far_last_s_ = 0.0;
  geometry::Vec3 far_centre_ = geometry::Vec3::Zero();
  SlamReport report_;
  MappingReport deferred_;        // finish_mapping()'s figures, for the next track_frame()'s report
  bool tracked_ = false;          // track_frame() ran on this frame and map_frame() has not yet
  bool keyframe_pending_ = false;  // track_frame() decided a keyframe
  bool keyframe_in_turn_ = false;  // ... on a frame of the tracker's turn step
  bool record_trajectory_ = false;
  RefinedTrajectory trajectory_;
  std::vector<map::ErasedKeyframe> erased_;  // scratch of take_erased()
  map::EventCursor erased_cursor_;           // the trajectory's place in the map's keyframe events
};

}  // namespace ale::slam
