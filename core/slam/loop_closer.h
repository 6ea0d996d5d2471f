// Loop closing on the SLAM thread (ORB-SLAM's LoopClosing, trimmed): each new keyframe, once its
// local BA has run, is looked up in the keyframe database among the keyframes it is not joined
// to; a place that keeps coming back over several consecutive keyframes (covisibility
// consistency) is verified geometrically: the keyframe's features matched to the candidate's
// landmarks under shared vocabulary nodes, a similarity between the two keyframes' landmark sets
// in seeded RANSAC (core/geometry/sim3_solver.h) checked by reprojection in both keyframes, a
// projection search in the candidate's neighbourhood and a pose refinement. A loop accepted then
//   1. moves the keyframe and its covisible neighbours, with the landmarks they see, to where the
//      loop puts them (a similarity: a monocular map's scale drifts too);
//   2. fuses the landmarks seen twice (the older one survives) and links the two places;
//   3. spreads the correction over the map by a Sim(3) pose graph (core/optim/pose_graph.h) over
//      the essential graph: the spanning tree, earlier loop edges, strong covisibility links and
//      the new loop links, the loop's old keyframe held fixed; each landmark follows the keyframe
//      that corrected it or its reference keyframe.
// A loop whose correction moves the keyframe farther than the drift the robot can have gathered
// since it saw the place is refused (a look-alike room), counted in the report.
//
// Map merging (ORB-SLAM3's Atlas, trimmed): the candidates also come from the older maps the store
// holds (a map kept when tracking was lost and a new one started). A verified place of an older
// map merges the current map into it on the next frame: every keyframe and landmark of the
// current map moves by the one similarity the place gives (current map -> older map), the maps
// become one (MapStore::merge_map, the current map's spanning tree under the place's keyframe),
// the landmarks seen twice are fused and the two places linked; on the frame after, a welding
// bundle adjustment around the seam (the keyframe's neighbourhood free, the older map's fixed)
// joins them. The poses go on in the older map's frame and id. Drift between the two maps is left
// to the loops the merged map closes afterwards.
//
// One thread, deterministic: keyframes in slot order, RANSAC seeded. Buffers are reserved for the
// map's capacity at construction.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/geometry/lie.h"
#include "core/geometry/sim3_solver.h"
#include "core/map/map_store.h"
#include "core/optim/pose_graph.h"
#include "core/place/keyframe_database.h"
#include "core/slam/frame.h"
#include "core/slam/map_ba.h"
#include "core/slam/odometry.h"
#include "core/slam/match/base.h"
#include "core/slam/match/feature_grid.h"
#include "core/slam/pose_refiner.h"

namespace ale::slam {

class LocalMapper;

struct LoopCloserParams {
  bool enabled = true;
  int min_keyframes = 12;         // keyframes in the map before loops are looked for
  int keyframes_between = 10;     // keyframes after a closed loop before the next is looked for
  int consistency = 3;            // consecutive keyframes whose candidate groups overlap (ORB-SLAM's 3)
  int min_bow_matches = 20;       // feature matches to a candidate under shared vocabulary nodes
  int min_sim3_inliers = 20;      // of the similarity, by reprojection in both keyframes
  int min_inliers = 40;           // of the keyframe's pose in the loop's neighbourhood, refined
  // The similarity RANSAC's 3-D gate, in each keyframe's units: this share of its landmarks'
  // median depth (monocular depths are a few percent uncertain; reprojection decides next).
  double sim3_gate_depths = 0.1;
  float projection_radius_px = 10.0f;  // the search in the candidate's neighbourhood
  int covisible_per_keyframe = 10;     // the candidate's neighbourhood: it and this many neighbours
  // A loop whose correction moves the keyframe by more than max_correction_ratio x the path the
  // keyframes drove since the loop's old keyframe, plus max_correction_floor_depths x the
  // keyframe's median depth, is refused: drift is a few percent of the path, a look-alike place
  // anywhere. On the rendered twin rooms (640x480) the look-alike loops need 1.7 x the bound or
  // more; at 0.15 and 1 one of them was closed (2.8 map units, the bound 2.79). The price: a true
  // loop of a lane route whose scale drifted by a quarter (0.59 units, the bound 0.50) is refused
  // too (docs/slam.md).
  double max_correction_ratio = 0.1;
  double max_correction_floor_depths = 0.5;
  int strong_covisibility = 100;  // covisibility links of the essential graph: at least this weight
  int pose_graph_iterations = 100;
  // A bundle adjustment of the whole map after the essential graph, this many iterations (0: none),
  // at most global_ba_iterations_per_frame on one frame. Off by default: on the 10-minute run
  // (a lap driven 23 times) 20 iterations gave 2.1 instead of 3.9 cm ATE but 81 instead of 61 MB
  // peak RSS, over the 64 MB budget (docs/slam.md).
  int global_ba_iterations = 0;
  int global_ba_iterations_per_frame = 1;
  // Map merging: a map that ends (tracking lost for slam.lost_timeout_s) with at least
  // min_keyframes keyframes is kept for merging, up to max_maps maps held with the current one
  // (the oldest goes); smaller maps are dropped. Off (or loop closing off): a new map replaces
  // the old one.
  bool merge = true;
  int max_maps = 3;
  int welding_ba_iterations = 10;
  std::uint64_t seed = 0x100bc105;
};
// Its keys (core/base/config_table.h; the daemon's `slam.loop.*`).
extern const ConfigTable kLoopCloserConfig;

struct LoopReport {
  bool checked = false;        // the keyframe was looked up
  int candidates = 0;          // of the database, not joined to the keyframe
  int consistent = 0;          // of those, consistent over `consistency` keyframes
  int bow_matches = 0;         // best of the consistent candidates
  int sim3_inliers = 0;
  int inliers = 0;
  bool closed = false;
  bool refused = false;        // a geometrically verified loop refused by the correction bound
  bool merged = false;         // the place was in an older map: the current map moves into it
  bool merge_refused = false;  // a verified merge not made (its map or keyframe left, a bad similarity)
  map::KeyframeId keyframe;    // the new keyframe
  map::KeyframeId loop_keyframe;
  double time_s = 0.0, loop_time_s = 0.0;  // the two keyframes' timestamps
  double correction = 0.0;     // how far the keyframe moved (map units of the loop's place)
  double scale = 1.0;          // the keyframe's map units per unit of the loop's place
  int landmarks_fused = 0;
  int corrected_keyframes = 0;   // moved with the keyframe by the loop (the first frame after it)
  int graph_keyframes = 0;       // of the essential graph (the frame after)
  int graph_edges = 0;
  int global_ba_iterations = 0;   // of the whole map's BA on this frame
  int welded_keyframes = 0;       // free in the welding BA after a merge (the frame after the merge)
  std::string message;         // why a verified candidate was not closed
};

class LoopCloser {
 public:
  LoopCloser(const LoopCloserParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
             const ImageBounds& bounds, const MatcherParams& matcher, const PoseRefinerParams& refiner,
             const map::MapCapacity& capacity);

  // One frame's share of loop closing, called once a frame before tracking. While no loop is
  // being closed, a valid kf (a keyframe made since the last call, in the database, its local BA
  // run) is looked up and a loop verified (report.closed); the map moves on the next frames: the
  // loop's neighbourhood and the fusion, then the essential graph, then the whole map's BA a few
  // iterations a frame (no frame pays for all of it). fixed_scale: the map is metric (the
  // similarity is a rigid motion). mapper: its landmark fusion.
  LoopReport step(map::KeyframeId kf, map::MapStore& map, const place::KeyframeDatabase& places, bool fixed_scale,
                  LocalMapper& mapper);
  // The last step moved keyframes; then length_factor(kf) is the factor lengths measured
  // relative to keyframe kf before it (a frame's pose relative to it) take in the moved map, and
  // pose_before(kf) kf's pose before it. 1 and the current pose for keyframes it did not move.
  bool moved() const { return moved_; }
  double length_factor(map::KeyframeId kf) const;
  geometry::SE3 pose_before(map::KeyframeId kf, const map::MapStore& map) const;
  bool busy() const { return stage_ != Stage::kIdle; }
  int loops_closed() const { return loops_closed_; }
  // Keyframes whose verified loop the correction bound refused (look-alike places), since start.
  int loops_refused() const { return loops_refused_; }
  // With wheel odometry (both keyframes of a merge carry an odometry pose, both maps metric), a
  // merge must put the keyframe where the odometry since the older keyframe does, within the
  // loop's drift bound over the odometry's path: the odometry runs on through the loss, so a
  // look-alike room is told from the same room. nullptr: no such check.
  void set_odometry(const OdometryParams* odometry) { odometry_ = odometry; }
  // Maps merged into older ones, and verified merges not made, since start.
  int merges() const { return merges_; }
  int merges_refused() const { return merges_refused_; }
  void reset();

 private:
  enum class Stage { kIdle, kCorrect, kGraph, kGlobalBa, kMerge, kWeld };
  struct Group {
    std::vector<map::KeyframeId> keyframes;  // sorted
    int consistency = 0;
  };
  MatchContext match_context() { return {pinhole_, pyramid_, matcher_, scratch_}; }
  void detect(map::KeyframeId kf, const map::MapStore& map, const place::KeyframeDatabase& places, bool fixed_scale,
              LoopReport& report);
  void consistent_candidates(const map::MapStore& map, LoopReport& report);
  void begin_move(const map::MapStore& map);
  bool verify(map::KeyframeId kf, map::KeyframeId loop, const map::MapStore& map, const place::KeyframeDatabase& places,
              bool fixed_scale, LoopReport& report);
  double driven_since(const map::Keyframe& loop, const map::Keyframe& kf, const map::MapStore& map);
  double drift_bound(double path, double depth) const;
  void correct(map::MapStore& map, LocalMapper& mapper, LoopReport& report);
  void optimise_essential_graph(map::MapStore& map, LoopReport& report);
  void global_bundle_adjustment(map::MapStore& map, LoopReport& report);
  void merge(map::MapStore& map, LocalMapper& mapper, LoopReport& report);
  void fuse_place(map::KeyframeId kf, map::KeyframeId loop, map::MapStore& map, LocalMapper& mapper,
                  LoopReport& report);
  void weld(map::MapStore& map, LoopReport& report);
  void next_stamp();

  LoopCloserParams params_;
  MatcherParams matcher_;
  geometry::Camera pinhole_;
  ScalePyramid pyramid_;
  ImageBounds bounds_;
  MatcherScratch scratch_;
  PoseRefiner refiner_;
  int keyframes_since_loop_ = 0;
  int loops_closed_ = 0;
  int loops_refused_ = 0;
  int merges_ = 0;
  int merges_refused_ = 0;
  const OdometryParams* odometry_ = nullptr;
  bool odometry_disagrees(const map::Keyframe& k, const map::Keyframe& l, const map::MapStore& map, double depth,
                          LoopReport& report);
  Stage stage_ = Stage::kIdle;
  map::KeyframeId loop_kf_, loop_;  // the loop being closed: the new keyframe and the old one
  int global_ba_left_ = 0;
  bool moved_ = false;

  // detection
  std::vector<place::PlaceCandidate> candidates_;
  std::vector<Group> groups_, next_groups_;
  std::vector<std::uint8_t> group_taken_;
  std::vector<map::KeyframeId> consistent_;
  std::vector<map::KeyframeId> group_scratch_;

  // verification: the keyframe as a frame, matched to the loop's landmarks
  Frame frame_;
  std::vector<geometry::Vec3> x_, y_;
  std::vector<int> pair_keypoint_;
  std::vector<double> depths_;
  geometry::Sim3RansacResult sim3_;
  geometry::Sim3Scratch sim3_scratch_;
  std::vector<map::LandmarkId> local_;
  geometry::SE3 loop_pose_;    // the keyframe's pose in the loop's place
  double loop_scale_ = 1.0;    // the keyframe's units per unit of the loop's place
  std::vector<map::LandmarkId> loop_matches_;  // per keyframe keypoint, the loop's landmark

  // what the last step moved, by keyframe slot (valid where moved_stamp_ is move_stamp_)
  std::uint32_t move_stamp_ = 0;
  std::vector<std::uint32_t> moved_stamp_;
  std::vector<geometry::SE3> before_;      // pose before the step
  std::vector<double> factor_;             // length factor of the step
  // the loop being closed, by keyframe or landmark slot (valid where the stamp is stamp_)
  std::uint32_t stamp_ = 0;
  std::vector<geometry::SE3> pre_loop_;    // pose before the loop moved anything
  std::vector<std::uint32_t> pre_loop_stamp_;
  std::vector<geometry::Sim3> corrected_;  // world -> keyframe after the local correction
  std::vector<std::uint32_t> connected_stamp_;
  std::vector<map::KeyframeId> connected_;
  std::vector<std::vector<map::KeyframeId>> neighbours_before_;  // per connected keyframe
  std::vector<int> vertex_of_slot_;
  std::vector<map::KeyframeId> vertex_keyframe_;
  std::vector<geometry::Sim3> vertex_initial_, graph_poses_;
  std::vector<optim::PoseGraphEdge<geometry::Sim3>> edges_;
  optim::PoseGraphOptimizer<geometry::Sim3> graph_;
  std::vector<map::KeyframeId> landmark_keyframe_;  // by landmark slot: the keyframe that corrected it
  std::vector<std::uint32_t> landmark_stamp_;
  std::vector<map::LandmarkId> landmarks_;
  std::vector<std::pair<double, map::KeyframeId>> by_time_;
  MapBundleAdjustment ba_;
};

}  // namespace ale::slam
