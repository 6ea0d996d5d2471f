// Local mapping, run inline after tracking decided on a keyframe (spec section 7; ORB-SLAM's
// LocalMapping on one thread): the keyframe's matches become observations, recently created
// landmarks that are rarely found are culled, new landmarks are triangulated with covisible
// keyframes, duplicates are fused, a local bundle adjustment refines the keyframe's
// neighbourhood, and keyframes whose landmarks are mostly seen by three others are culled.
// Deterministic: every list is walked in id order.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/slam/map_ba.h"
#include "core/slam/frame.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/match/fuse.h"
#include "core/slam/match/triangulation.h"

namespace ale::slam {

struct LocalMapperParams {
  int triangulation_neighbours = 20;
  double min_baseline_depth_ratio = 0.01;
  double max_cos_parallax = 0.9998;
  int fuse_neighbours = 20;
  float fuse_radius = 3.0f;        // x scale of the keypoint's level
  int ba_iterations = 10;          // per pass; two passes with outlier removal between
  int ba_first_pass_iterations = 10;  // at most, of the first pass (it only separates the outliers)
  double ba_function_tolerance = 1e-6;  // relative cost change that ends a pass
  double ba_first_pass_function_tolerance = 0.0;  // ... that ends the first pass (the larger one counts)
  // The local BA's free keyframes: the new one and its most covisible neighbours (ORB-SLAM takes
  // every covisible keyframe; on one Cortex-A7 core the BA's cost must stay bounded as the map
  // grows). Keyframes outside the window that see its points are fixed.
  int ba_max_keyframes = 10;
  double min_found_ratio = 0.25;   // recent landmarks found in fewer of the frames that saw them go
  int redundant_observers = 3;
  double redundant_share = 0.9;
  bool cull_keyframes = true;
  // The local BA and the keyframe culling of a keyframe wait for finish_pending(), which the
  // system runs on the next frame before tracking it (SlamSystem::finish_mapping): the keyframe's
  // frame pays for the triangulation and fusion only, so no frame pays for a whole keyframe (the
  // 95th-percentile frame time), and the next frame is tracked against the same map as without
  // deferral. Deterministic: the split is by frame, not by a clock.
  bool defer_ba = true;
};
// Its keys (core/base/config_table.h; the daemon's `slam.mapping.*`).
extern const ConfigTable kLocalMapperConfig;

struct MappingReport {
  int observations_added = 0;
  int landmarks_created = 0;
  int landmarks_culled = 0;
  int landmarks_fused = 0;
  int ba_keyframes = 0;
  int ba_fixed = 0;
  int ba_points = 0;
  int ba_outliers = 0;
  int ba_floor = 0;            // landmarks held on the floor (MapBundleAdjustment::add_floor_observations)
  int keyframes_culled = 0;
  int keyframes_evicted = 0;   // the map was full: the oldest keyframes outside the local map went
  int landmarks_evicted = 0;   // with the landmarks no other keyframe saw

  MappingReport& operator+=(const MappingReport& o) {
    observations_added += o.observations_added;
    landmarks_created += o.landmarks_created;
    landmarks_culled += o.landmarks_culled;
    landmarks_fused += o.landmarks_fused;
    ba_keyframes += o.ba_keyframes;
    ba_fixed += o.ba_fixed;
    ba_points += o.ba_points;
    ba_outliers += o.ba_outliers;
    ba_floor += o.ba_floor;
    keyframes_culled += o.keyframes_culled;
    keyframes_evicted += o.keyframes_evicted;
    landmarks_evicted += o.landmarks_evicted;
    return *this;
  }
};

class LocalMapper {
 public:
  LocalMapper(const LocalMapperParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
              const ImageBounds& bounds, const MatcherParams& matcher = MatcherParams{})
      : params_(params), matcher_(matcher), pinhole_(pinhole), pyramid_(pyramid), bounds_(bounds), ba_(pinhole, pyramid) {}

  // Processes a keyframe just added to the map from `frame` (same keypoints, in order). With
  // defer_ba, the local BA and the keyframe culling wait for finish_pending(); a keyframe still
  // pending when the next one comes is finished first.
  // previous (when valid): a keyframe to triangulate with besides the covisible ones, for a
  // keyframe that may share no landmark with the map (made by the tracker's turn step).
  MappingReport process(map::KeyframeId kf, const Frame& frame, map::MapStore& map,
                        map::KeyframeId previous = map::KeyframeId{});
  // The deferred local BA and keyframe culling of the last processed keyframe, if any (nothing
  // when it has left the map meanwhile). Reports their fields only.
  MappingReport finish_pending(map::MapStore& map);
  map::KeyframeId pending() const { return pending_; }
  // Fuses each landmark into the keyframe where it duplicates one of its keypoints (the
  // better-observed landmark survives) or adds the observation to a keypoint without one, at the
  // keyframe's pose in the map (loop closing's fusion). Returns how many were fused.
  int fuse_landmarks(map::KeyframeId target, const std::vector<map::LandmarkId>& landmarks, map::MapStore& map) {
    return fuse_into(target, landmarks, map);
  }
  bool has_pending() const { return pending_.valid(); }
  // Landmarks created by the initialiser count as recent too.
  void add_recent(map::LandmarkId lm, map::KeyframeId created_by) { recent_.push_back({lm, created_by, 0}); }
  void reset() {
    recent_.clear();
    pending_ = map::KeyframeId{};
    odometry_ = nullptr;
    floor_.reset();
  }
  // The local BA holds keyframes to the wheel odometry between them (MapBundleAdjustment::
  // add_odometry_priors) while `odometry` is set: in a metric map. nullptr: no odometry.
  void set_odometry(const OdometryParams* odometry) { odometry_ = odometry; }
  // The gyro's bias taken off the rotation priors' targets (GyroBias::rate_rps), rad/s.
  void set_gyro_bias(double rps) { gyro_bias_rps_ = rps; }
  // The local BA holds landmarks on the floor (MapBundleAdjustment::add_floor_observations) while
  // a floor is set: in a metric map whose camera height is known. nullopt: no floor.
  void set_floor(const FloorParams& params, const std::optional<FloorGeometry>& floor) {
    floor_params_ = params;
    floor_ = floor;
  }

 private:
  struct Recent {
    map::LandmarkId id;
    map::KeyframeId created_by;
    int keyframes_since = 0;
  };
  MatchContext match_context() { return {pinhole_, pyramid_, matcher_, scratch_}; }
  void cull_recent(map::MapStore& map, MappingReport& r);
  void triangulate(map::KeyframeId kf, map::KeyframeId previous, map::MapStore& map, MappingReport& r);
  void fuse(map::KeyframeId kf, map::MapStore& map, MappingReport& r);
  int fuse_into(map::KeyframeId target, const std::vector<map::LandmarkId>& landmarks, map::MapStore& map);
  void local_bundle_adjustment(map::KeyframeId kf, map::MapStore& map, MappingReport& r);
  void anchor_odometry(const map::MapStore& map, MappingReport& r);
  void cull_keyframes(map::KeyframeId kf, map::MapStore& map, MappingReport& r);
  void finish_landmark(map::LandmarkId id, map::MapStore& map);
  void adjust(map::KeyframeId kf, map::MapStore& map, MappingReport& r);

  LocalMapperParams params_;
  MatcherParams matcher_;
  geometry::Camera pinhole_;
  ScalePyramid pyramid_;
  ImageBounds bounds_;
  std::vector<Recent> recent_;
  map::KeyframeId pending_;  // processed, its local BA and culling deferred (defer_ba)
  FeatureGrid grid_a_, grid_b_;
  MatcherScratch scratch_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<map::LandmarkId> lms_, lms_b_;
  MapBundleAdjustment ba_;
  const OdometryParams* odometry_ = nullptr;
  double gyro_bias_rps_ = 0.0;
  FloorParams floor_params_;
  std::optional<FloorGeometry> floor_;
  std::vector<map::KeyframeId> ba_kfs_;
  struct Anchor {
    map::KeyframeId anchor;  // the latest keyframe with odometry before before_s, at anchor_s
    double before_s = 0.0;
    double anchor_s = 0.0;
  };
  std::vector<Anchor> anchors_;  // anchor_odometry()'s, one per free local keyframe with odometry
  std::vector<map::KeyframeId> kfs_;  // scratch of fuse(), the local BA and keyframe culling
  std::vector<map::KeyframeId> tri_kfs_;  // scratch of triangulate()
  std::vector<double> depths_;        // scratch of triangulate()
  std::vector<map::LandmarkId> ba_lms_;
};

}  // namespace ale::slam
