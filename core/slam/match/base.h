// What the SLAM core's descriptor searches share (spec section 7; ORB-SLAM's ORBmatcher without
// bag-of-words, split by kind as stella_vslam's match/ is):
//   projection.h     landmarks (local map, reference keyframe) and the last frame's matches
//                    projected into a frame at a predicted pose;
//   triangulation.h  two keyframes' unmatched keypoints along their epipolar lines;
//   pairs.h          two frames without a pose: the initialiser's windowed search, brute force
//                    and the band of a candidate epipolar geometry;
//   fuse.h           a landmark projected into a keyframe to find its duplicate there;
//   bow.h            a frame and a keyframe without a pose, features under the same vocabulary
//                    node only (relocalisation).
// Here: the one set of parameters, the buffers, the context every search takes, the Hamming
// gates' bookkeeping, the rotation-consistency check (a histogram of orientation differences;
// matches outside its three strongest bins are dropped) and the test that a landmark is in view.
// Results depend only on the inputs (ties go to the lower index), so replays are deterministic.
#pragma once

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/base/config_table.h"
#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/slam/match/feature_grid.h"

namespace ale::slam {

// The rotation-consistency check of a search (drop_inconsistent_rotations): one definition for
// every search that runs it.
struct RotationCheck {
  bool enabled = true;
  int bins = 30;  // over 360 deg
};
// Its keys (`slam.matcher.rotation.*`).
extern const ConfigTable kRotationCheckConfig;

// The matcher's parameters, one set for the whole core (SlamParams::matcher).
struct MatcherParams {
  int th_high = 100;             // Hamming gate for projection searches
  int th_low = 50;               // Hamming gate for initialisation, triangulation and fusion
  float ratio_initialization = 0.9f;
  float ratio_projection = 0.8f;
  float ratio_bow = 0.75f;       // search_by_bow (ORB-SLAM's relocalisation: 0.75)
  // Triangulation search: the best candidate along the epipolar line must beat, by this ratio,
  // every candidate farther than ratio_separation x its level's scale from it (another place on
  // the line, so another depth; nearer ones are the same corner on a neighbouring level).
  // ORB-SLAM has no ratio test here because bag-of-words already narrows the candidates; along
  // the whole line repeated texture (floor planks, stripes) otherwise gives wrong depths: on the
  // rendered loops a quarter of new floor points were more than 30 % off. 1 disables it.
  float ratio_triangulation = 0.8f;
  float ratio_separation = 3.0f;
  // Keypoints of the reference frame up to this level take part in the initialisation search
  // (ORB-SLAM: level 0 only; all levels here: on the 20 TUM fr2_desk frames level 0 alone gives
  // 70-110 matches between frames and never initialises, all levels 390-460); candidates are on
  // the keypoint's level +-1.
  int initialization_max_level = 15;
  RotationCheck rotation;
};
// Its keys (core/base/config_table.h; the daemon's `slam.matcher.*`).
extern const ConfigTable kMatcherConfig;

// A frame's features (undistorted pixels) and their grid (nullptr for the pair searches, which
// need none).
struct FrameFeatures {
  const map::KeyframeFeature* features = nullptr;
  int count = 0;
  const FeatureGrid* grid = nullptr;
};

// The nearest and second-nearest Hamming distance seen for one keypoint, and the nearest's index.
struct Nearest2 {
  int index = -1;
  int best = 1 << 30;
  int second = 1 << 30;
};

// A keypoint pair (f1, f2) whose descriptors are close enough to matter to a pair search.
struct DescriptorPair {
  int i1 = 0;
  int i2 = 0;
  int distance = 0;
};

// A keypoint of the triangulation search's second keyframe as its epipolar tests read it, filled
// once a search (the tests run on every keypoint in the cells along every line).
struct EpipolarKeypoint {
  double u = 0.0, v = 0.0;  // the pixel
  double gate = 0.0;        // its level's epipolar gate, squared pixels
  double tol = 0.0;         // the gate's square root: the tolerance along the line, pixels
  int level = 0;            // clamped to the pyramid
  bool mapped = false;      // it has a landmark
};

// Reused buffers of the searches (no allocation once warm).
struct MatcherScratch {
  std::vector<DescriptorPair> near_pairs;
  std::vector<Nearest2> nearest12, nearest21;
  std::vector<float> line_sigma;
  std::vector<geometry::Vec3> lines;
  std::vector<int> candidates;
  std::vector<int> best_dist;
  std::vector<int> owner;
  std::vector<std::vector<int>> bins;
  std::vector<int> matched;
  std::vector<std::uint32_t> seen;
  std::vector<std::pair<int, int>> scored;  // (keypoint, Hamming distance) along one epipolar line
  std::vector<EpipolarKeypoint> epipolar;   // the triangulation search's second keyframe
};

// What every posed search takes besides its frames: the camera of the undistorted keypoints, the
// pyramid they came from, the parameters and the buffers. A unit builds one at the call site
// from its members.
struct MatchContext {
  const geometry::Camera& pinhole;
  const ScalePyramid& pyramid;
  const MatcherParams& params;
  MatcherScratch& scratch;
};

constexpr int kNoMatch = -1;

// The two smallest Hamming distances offered, the index and level of the smallest and the level
// of the second. An equal distance does not displace the one held (ties go to the first offered).
struct Best2 {
  int dist = std::numeric_limits<int>::max();
  int dist2 = std::numeric_limits<int>::max();
  int index = kNoMatch;
  int level = -1;
  int level2 = -1;
  void offer(int d, int idx, int lvl) {
    if (d < dist) {
      dist2 = dist;
      level2 = level;
      dist = d;
      index = idx;
      level = lvl;
    } else if (d < dist2) {
      dist2 = d;
      level2 = lvl;
    }
  }
};

// The pixel (as floats) of a point in the camera frame; false behind the camera.
bool project_pinhole(const geometry::Camera& pinhole, const geometry::Vec3& p_c, float* u, float* v);

// The rotation-consistency check. matches12[i] is the keypoint of `second` matched to keypoint i
// of `first`, or kNoMatch. The orientation changes angle(first) - angle(second) go into `bins`
// bins over 360 deg; matches outside the three strongest bins (a bin counts when it holds at
// least a tenth of the strongest; ORB-SLAM's ComputeThreeMaxima) are reported to
// dropped(i, matches12[i]) and then unset. Returns how many were dropped.
template <class Dropped>
int drop_inconsistent_rotations(const FrameFeatures& first, const FrameFeatures& second, int bins,
                                std::vector<int>& matches12, std::vector<std::vector<int>>& bin_storage,
                                Dropped&& dropped);
int drop_inconsistent_rotations(const FrameFeatures& first, const FrameFeatures& second, int bins,
                                std::vector<int>& matches12, std::vector<std::vector<int>>& bin_storage);

// The last step of the pair and triangulation searches: the matches in scratch.matched (first
// index -> second index, or kNoMatch; first.count entries) pass the rotation check when it is
// enabled, and the rest are appended to pairs in first's order. Returns pairs.size().
int list_matched_pairs(const FrameFeatures& first, const FrameFeatures& second, const RotationCheck& rotation,
                       MatcherScratch& scratch, std::vector<std::pair<int, int>>& pairs);

// Where a landmark appears to a camera at T_cw, when it is in view.
struct LandmarkView {
  geometry::Vec2 uv;         // undistorted pixel
  float u = 0.0f, v = 0.0f;  // the same, as the grid takes it
  float distance = 0.0f;     // from the camera centre, map units
  double view_cos = 0.0;     // cosine between the viewing ray and the landmark's mean viewing direction
  int level = 0;             // the pyramid level it is predicted at (ScalePyramid::predict_level)
};

// The "landmark is in view" test of every projection search (ORB-SLAM's isInFrustum): in front
// of the camera, projecting inside `bounds`, its distance within [0.8 min_distance,
// 1.2 max_distance] (its scale-invariance range) and seen within 60 deg of its mean viewing
// direction. centre_w is the camera centre (T_cw.inverse().translation()). False when not; the
// view is filled only when true.
bool landmark_in_view(const map::Landmark& lm, const geometry::SE3& T_cw, const geometry::Vec3& centre_w,
                      const geometry::Camera& pinhole, const ImageBounds& bounds, const ScalePyramid& pyramid,
                      LandmarkView* view);

// ---------------------------------------------------------------------------------------------
// Implementation of the template above.

namespace detail {
// The kept bins of the rotation histogram in bin_storage (filled by add_rotation): writes up to
// three bin indices into kept (-1 where unused).
void strongest_rotation_bins(const std::vector<std::vector<int>>& bin_storage, int kept[3]);
void add_rotation(std::vector<std::vector<int>>& bin_storage, float angle1_deg, float angle2_deg, int item);
}  // namespace detail

template <class Dropped>
int drop_inconsistent_rotations(const FrameFeatures& first, const FrameFeatures& second, int bins,
                                std::vector<int>& matches12, std::vector<std::vector<int>>& bin_storage,
                                Dropped&& dropped) {
  bin_storage.resize(static_cast<std::size_t>(bins < 1 ? 1 : bins));
  for (std::vector<int>& b : bin_storage) b.clear();
  for (int i = 0; i < first.count; ++i) {
    const int j = matches12[static_cast<std::size_t>(i)];
    if (j != kNoMatch) detail::add_rotation(bin_storage, first.features[i].angle_deg, second.features[j].angle_deg, i);
  }
  int kept[3];
  detail::strongest_rotation_bins(bin_storage, kept);
  int n = 0;
  for (int b = 0; b < static_cast<int>(bin_storage.size()); ++b) {
    if (b == kept[0] || b == kept[1] || b == kept[2]) continue;
    for (int i : bin_storage[static_cast<std::size_t>(b)]) {
      dropped(i, matches12[static_cast<std::size_t>(i)]);
      matches12[static_cast<std::size_t>(i)] = kNoMatch;
      ++n;
    }
  }
  return n;
}

}  // namespace ale::slam
