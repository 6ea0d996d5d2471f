// Frame-to-map tracking (spec section 7; ORB-SLAM's Tracking without bag-of-words):
// 1. the constant-velocity model: the last frame's matches projected at the predicted pose
//    (radius 15 px, doubled when fewer than 20 match), then motion-only optimisation;
// 2. when there is no velocity or it fails, the reference keyframe: its landmarks projected at
//    the predicted pose (the last pose without a velocity) with a wide radius, then motion-only
//    optimisation;
// 3. the local map: keyframes that see the frame's landmarks and their strongest covisible
//    neighbours, all their landmarks projected at the estimated pose, then a last optimisation.
// 4. when these fail right after a tracked frame, the turn step (TrackerParams::turn_min_bearings).
// The optimisations use the confirmed landmarks only (pose_min_observations) when there are
// enough of them.
// Each step reports its matches and inliers; the frame keeps its inlier landmarks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/optim/motion_only.h"
#include "core/slam/frame.h"
#include "core/slam/local_map.h"
#include "core/slam/pose_refiner.h"
#include "core/slam/match/projection.h"

namespace ale::slam {

struct TrackerParams {
  float motion_radius_px = 15.0f;
  int motion_min_matches = 20;
  float reference_radius_px = 30.0f;
  int reference_min_matches = 15;
  int min_inliers = 10;             // after each motion-only optimisation
  float local_map_radius_px = 2.5f; // of the local-map projection (search_by_projection)
  int local_map_min_inliers = 30;
  int local_keyframes_max = 80;
  int covisible_per_keyframe = 10;
  // Landmarks seen by fewer keyframes than this are matched (so the next keyframe observes them
  // and its bundle adjustment checks them) but do not pull on the pose, as long as at least
  // pose_min_confirmed matches are seen that often. A landmark from two keyframes fits any match
  // that obeys their epipolar geometry, right or wrong, so it is unconfirmed: on the rendered
  // loops a quarter of them were more than 30 % off in depth, and tracking on them drifted in
  // heading and scale at the turns. 0 uses every match.
  int pose_min_observations = 3;
  int pose_min_confirmed = 60;
  // The camera centre predicted by the constant-velocity model is a soft prior of the pose
  // optimisations that follow a motion-model prediction (core/optim/motion_only.h CentrePrior),
  // sigma = max(centre_prior_step x the predicted step, centre_prior_depth x the mean depth of
  // the last frame's landmarks). It keeps a turn on the spot from becoming a sideways slide
  // where the view holds points at one depth. 0 and 0: no prior.
  double centre_prior_step = 0.0;
  double centre_prior_depth = 0.0;
  // The turn step (4. above): when the map no longer holds the pose, the last frame's keypoints
  // without a landmark are matched as bearings (rays without depth, placed at the scene's mean
  // depth), and the pose is refined on them (mostly rotation) with the landmarks still matched and
  // the constant-velocity centre as a prior (translation). The
  // frame is tracked when at least turn_min_bearings bearings are inliers, for at most
  // turn_max_frames frames in a row (then the map must hold the pose again or tracking is lost).
  // 0 bearings: no turn step.
  int turn_min_bearings = 50;
  int turn_max_frames = 30;
  optim::MotionOnlyOptions motion_only;
};
// Its keys (core/base/config_table.h; the daemon's `slam.tracker.*`).
extern const ConfigTable kTrackerConfig;

struct TrackReport {
  bool ok = false;
  bool used_motion_model = false;
  bool turn = false;      // tracked by the turn step
  int bearings = 0;       // its bearing inliers
  int matches = 0;        // of the first step that succeeded
  int inliers = 0;        // after the local map
  int local_keyframes = 0;
  int local_landmarks = 0;
  std::string message;    // why tracking failed
};

class Tracker {
 public:
  Tracker(const TrackerParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
          const MatcherParams& matcher = MatcherParams{});

  // Tracks `frame` (features indexed, no matches) from `last` (tracked, with its matches).
  // velocity = T_last_to_current, used when has_velocity. On success frame.T_cw and its
  // landmarks are set and *reference (in/out) becomes the local keyframe sharing most
  // landmarks with it. The map's landmark counters (visible, found) are updated.
  // odometry_sigma > 0: the velocity is the odometry's motion (in map units) and every pose
  // optimisation of the frame holds the camera centre at its prediction with this sigma (map
  // units) instead of the centre_prior_* one; the turn step takes it too.
  TrackReport track(Frame& frame, const Frame& last, const geometry::SE3& velocity, bool has_velocity,
                    map::MapStore& map, map::KeyframeId* reference, double odometry_sigma = 0.0);

  // Step 3 alone, for a frame posed another way (a relocalised one): the local map around its
  // matches searched at frame.T_cw, then the last optimisation. True when it has
  // local_map_min_inliers.
  bool track_local_map(Frame& frame, map::MapStore& map, map::KeyframeId* reference, TrackReport& report);
  const PoseRefinerParams& pose_refiner_params() const { return refiner_.params(); }
  // A new map or a relocalisation: the turn step's count of frames in a row starts again.
  void forget_turn() { turn_frames_ = 0; }
  // The map was scaled by `factor`: the distances the tracker keeps too.
  void rescale(double factor) { scene_depth_ *= factor; }

 private:
  MatchContext match_context() { return {pinhole_, pyramid_, matcher_, scratch_}; }
  optim::CentrePrior centre_prior(const Frame& last, const geometry::SE3& predicted_cw, const map::MapStore& map) const;
  bool track_motion_model(Frame& frame, const Frame& last, const geometry::SE3& velocity, map::MapStore& map,
                          TrackReport& report);
  bool track_turn(Frame& frame, const Frame& last, const geometry::SE3& velocity, map::MapStore& map,
                  map::KeyframeId* reference, TrackReport& report);
  // The local map around `seeds` (landmark ids), searched at frame.T_cw; its landmarks in view
  // counted visible. The caller refines, then count_found().
  void search_local_map(Frame& frame, const std::vector<map::LandmarkId>& seeds, map::MapStore& map,
                        map::KeyframeId* reference, TrackReport& report);
  static void count_found(const Frame& frame, map::MapStore& map);
  bool turn_from(Frame& frame, const Frame& last, const geometry::SE3& start_cw, map::MapStore& map,
                 map::KeyframeId* reference, TrackReport& report);
  void ray_points(const Frame& last, double depth);
  bool track_reference(Frame& frame, const geometry::SE3& start_cw, map::KeyframeId reference, map::MapStore& map,
                       TrackReport& report);

  TrackerParams params_;
  MatcherParams matcher_;
  geometry::Camera pinhole_;
  ScalePyramid pyramid_;
  MatcherScratch scratch_;
  PoseRefiner refiner_;
  LocalMap local_map_;
  std::vector<map::LandmarkId> landmarks_;
  std::vector<map::LandmarkId> in_view_;
  std::vector<std::pair<int, int>> bearing_pairs_;  // (last keypoint, frame keypoint), turn step
  std::vector<geometry::Vec3> bearing_points_;
  std::vector<int> bearing_keypoints_;
  int turn_frames_ = 0;
  optim::CentrePrior odometry_prior_;  // of the frame being tracked; sigma 0: none
  double scene_depth_ = 1.0;           // the turn step's last mean landmark distance (map units)
};

}  // namespace ale::slam
