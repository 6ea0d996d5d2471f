// Relocalisation of a frame in the map when tracking is lost (ORB-SLAM's Relocalization): each
// candidate keyframe in turn (the caller's order: the reference keyframe's neighbourhood, then the
// place-recognition database's or a sweep over the map), its landmarks matched to the frame's
// keypoints by descriptor (under shared vocabulary nodes when the database holds the keyframe:
// search_by_bow; else against every keypoint),
// a pose from P3P in seeded RANSAC (core/geometry/pnp.h) on those matches, refined by the
// tracker's PoseRefiner; when the refined pose has fewer than min_inliers, the candidate's local
// map (it and its covisible keyframes) is searched by projection at that pose and the pose
// refined again.
// Without a continuity prior the first candidate that reaches min_inliers wins. With one (where
// the robot was last tracked and how far it can have gone since, Continuity) every candidate is
// tried: the pose with the most inliers within that reach is taken when it has near_min_inliers;
// else the pose with the most inliers beyond it ("far") when it has min_inliers: the caller
// decides whether to take that at once (SlamSystem confirms it over far_confirm_s first).
// Deterministic: candidates in the given order, RANSAC seeded. No allocation after warm-up for a
// given map capacity.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/geometry/pnp.h"
#include "core/map/map_store.h"
#include "core/place/keyframe_database.h"
#include "core/slam/frame.h"
#include "core/slam/match/base.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/pose_refiner.h"

namespace ale::slam {

struct RelocaliserParams {
  // keyframes from place recognition (or the sweep) tried per lost frame, at most (with
  // near_candidates, bounds the frame's cost)
  int max_candidates = 8;
  int min_matches = 15;           // descriptor matches a candidate needs for a PnP
  float match_ratio = 0.75f;      // best / second-best Hamming distance of a descriptor match
  int pnp_min_inliers = 10;       // of the RANSAC and its refinement
  int min_inliers = 50;           // after pose refinement (ORB-SLAM's 50): a relocalised frame
  float projection_radius_px = 10.0f;  // of the search in the candidate's local map
  int covisible_per_keyframe = 10;     // the candidate's local map
  std::uint64_t seed = 0x5e10ca1;      // of the RANSAC (the same frame gives the same pose)
  // Continuity: a robot that lost track for a moment cannot have gone far (SlamSystem).
  // The reference keyframe and its strongest covisible neighbours, this many in all, are tried
  // ahead of place recognition's candidates.
  int near_candidates = 4;
  // Inliers of a pose within reach of the last tracked pose. 50 as min_inliers: the tracker's
  // local-map 30 relocalised mid-turn frames on poorer poses (rendered lanes_hall7x5_w30_t90:
  // 4 relocalisations and 93 cm ATE against 2 and 12 cm; docs/slam.md).
  int near_min_inliers = 50;
  // The reach: reach_margin x the speed before the loss (map units per second, smoothed over
  // about half a second of tracked frames) x the time since the last tracked frame, and at least
  // reach_floor_depths x the reference keyframe's median scene depth.
  double reach_margin = 2.0;
  double reach_floor_depths = 0.5;
  // A pose beyond the reach (a kidnap, or a look-alike place) is taken only once lost frames have
  // relocalised beyond it at mutually consistent poses for this long, while no candidate within
  // reach reached pnp_min_inliers; a near pose that qualifies meanwhile wins. 0: at once.
  double far_confirm_s = 0.4;
};

// Where the robot was last tracked (camera centre, map units) and how far it can have gone
// since (reach, map units).
struct Continuity {
  geometry::Vec3 centre = geometry::Vec3::Zero();
  double reach = 0.0;
  bool near(const geometry::SE3& T_cw) const { return (T_cw.inverse().translation() - centre).norm() <= reach; }
};
// Its keys (core/base/config_table.h; the daemon's `slam.relocaliser.*`).
extern const ConfigTable kRelocaliserConfig;

struct RelocaliseReport {
  bool ok = false;
  int candidates = 0;   // offered
  int tried = 0;        // with enough matches for a PnP
  int matches = 0;      // of the best candidate
  int inliers = 0;      // of the best candidate, after refinement
  map::KeyframeId keyframe;  // the candidate that relocalised the frame
  // With a continuity prior: the pose is beyond its reach (ok, the caller decides), and whether
  // some candidate's pose within the reach had pnp_min_inliers (evidence that the robot is near).
  bool far = false;
  bool near_evidence = false;
  std::string message;  // why not
};

class Relocaliser {
 public:
  Relocaliser(const RelocaliserParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
              const MatcherParams& matcher, const PoseRefinerParams& refiner);

  // Tries every candidate given (the caller bounds the list). On success frame.T_cw,
  // frame.has_pose and its landmarks (the inliers) are set. The frame's matches are cleared on
  // failure.
  // places/frame_fv: the keyframe database and the frame's feature vector (same vocabulary and
  // node level) for the guided matching; nullptr: every candidate is matched exhaustively.
  // continuity: where the robot was last tracked and its reach (the file's comment); nullptr:
  // none known, the first candidate with min_inliers wins.
  RelocaliseReport relocalise(Frame& frame, const map::MapStore& map, const std::vector<map::KeyframeId>& candidates,
                              const place::KeyframeDatabase* places = nullptr,
                              const place::FeatureVector* frame_fv = nullptr, const Continuity* continuity = nullptr);

 private:
  MatchContext match_context() { return {pinhole_, pyramid_, matcher_, scratch_}; }
  int match_keyframe(const Frame& frame, const map::MapStore& map, map::KeyframeId kf);
  // The candidate's refined pose in frame (T_cw, landmarks, outlier): its inliers, 0 without a pose.
  int try_candidate(Frame& frame, const map::MapStore& map, map::KeyframeId kf, const place::KeyframeDatabase* places,
                    const place::FeatureVector* frame_fv, RelocaliseReport& report);

  RelocaliserParams params_;
  MatcherParams matcher_;
  geometry::Camera pinhole_;
  ScalePyramid pyramid_;
  MatcherScratch scratch_;
  PoseRefiner refiner_;
  // scratch, kept between calls
  std::vector<map::LandmarkId> matched_;   // per frame keypoint
  std::vector<int> best_dist_;             // per frame keypoint
  std::vector<int> matches12_;             // per keyframe keypoint: the frame keypoint, or kNoMatch
  std::vector<std::vector<int>> rotation_bins_;
  std::vector<geometry::Vec3> points_;
  std::vector<geometry::Vec2> pixels_;
  std::vector<double> sigmas_;
  std::vector<int> keypoints_;
  geometry::PnpResult pnp_;
  geometry::PnpScratch pnp_scratch_;
  std::vector<map::LandmarkId> local_;
  // the best pose within the reach and beyond it so far (Continuity)
  struct Kept {
    int inliers = 0;
    map::KeyframeId keyframe;
    geometry::SE3 T_cw;
    std::vector<map::LandmarkId> landmarks;
    std::vector<std::uint8_t> outlier;
    void keep(const Frame& frame, map::KeyframeId kf, int n);
    void restore(Frame& frame) const;
  };
  Kept near_, far_;
};

}  // namespace ale::slam
