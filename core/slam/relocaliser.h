// Relocalisation of a frame in the map when tracking is lost (ORB-SLAM's Relocalization): each
// candidate keyframe in turn (the caller's order: the place-recognition database's, or the last
// keyframes when there is none), its landmarks matched to the frame's keypoints by descriptor,
// a pose from P3P in seeded RANSAC (core/geometry/pnp.h) on those matches, refined by the
// tracker's PoseRefiner; when the refined pose has fewer than min_inliers, the candidate's local
// map (it and its covisible keyframes) is searched by projection at that pose and the pose
// refined again. The first candidate that reaches min_inliers wins. Deterministic: candidates
// in the given order, RANSAC seeded. No allocation after warm-up for a given map capacity.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/geometry/pnp.h"
#include "core/map/map_store.h"
#include "core/slam/frame.h"
#include "core/slam/match/base.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/pose_refiner.h"

namespace ale::slam {

struct RelocaliserParams {
  int max_candidates = 8;         // keyframes tried per frame, at most (bounds the frame's cost)
  int min_matches = 15;           // descriptor matches a candidate needs for a PnP
  float match_ratio = 0.75f;      // best / second-best Hamming distance of a descriptor match
  int pnp_min_inliers = 10;       // of the RANSAC and its refinement
  int min_inliers = 50;           // after pose refinement (ORB-SLAM's 50): a relocalised frame
  float projection_radius_px = 10.0f;  // of the search in the candidate's local map
  int covisible_per_keyframe = 10;     // the candidate's local map
  std::uint64_t seed = 0x5e10ca1;      // of the RANSAC (the same frame gives the same pose)
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
  std::string message;  // why not
};

class Relocaliser {
 public:
  Relocaliser(const RelocaliserParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
              const MatcherParams& matcher, const PoseRefinerParams& refiner);

  // On success frame.T_cw, frame.has_pose and its landmarks (the inliers) are set. The frame's
  // matches are cleared on failure.
  RelocaliseReport relocalise(Frame& frame, const map::MapStore& map, const std::vector<map::KeyframeId>& candidates);

 private:
  MatchContext match_context() { return {pinhole_, pyramid_, matcher_, scratch_}; }
  int match_keyframe(const Frame& frame, const map::MapStore& map, map::KeyframeId kf);
  bool try_candidate(Frame& frame, const map::MapStore& map, map::KeyframeId kf, RelocaliseReport& report);

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
};

}  // namespace ale::slam
