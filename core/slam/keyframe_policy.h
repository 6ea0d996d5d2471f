// When tracking makes a keyframe (ORB-SLAM's NeedNewKeyFrame, trimmed for inline mapping): at
// least min_frames frames after the last one, when the frame tracks fewer than ref_ratio of the
// reference keyframe's trusted landmarks (the view has changed) and still enough of them to
// anchor the new keyframe. Inline mapping is never busy, so ORB-SLAM's "mapper idle" condition
// always holds and the view change alone decides.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/map_store.h"

namespace ale::slam {

struct KeyframePolicyParams {
  int min_frames = 7;
  double ref_ratio = 0.9;
  int min_inliers = 15;
  // The view is leaving the map fast (a turn on the spot): a keyframe as soon as urgent_min_frames
  // have passed when the frame tracks fewer than urgent_ratio of the reference's landmarks.
  int urgent_min_frames = 3;
  double urgent_ratio = 0.5;
  // A known place: when the reference keyframe was made more than revisit_age_s before the frame
  // and the camera is on its line of sight (at most revisit_radius_depths of its median depth
  // aside of it, anywhere along it: the robot is back on the path it drove), the view has to
  // change as far as revisit_ratio before a keyframe comes: the map already holds the place, and
  // each keyframe added there would stay (its own new points keep culling from finding it
  // redundant), growing the map on every lap. The radius keeps the rule off the next cleaning lanes,
  // which see the walls of a lane before from 0.3 m aside and more: a view the map does not hold.
  // revisit_age_s 0: off.
  double revisit_age_s = 0.0;
  double revisit_ratio = 0.5;
  double revisit_radius_depths = 0.05;
};

class KeyframePolicy {
 public:
  explicit KeyframePolicy(const KeyframePolicyParams& params) : params_(params) {}

  // A frame arrived (tracked or not).
  void frame_arrived() { ++frames_since_keyframe_; }
  // A keyframe was made: from the current frame, or by the initialiser (its second keyframe).
  void keyframe_made() { frames_since_keyframe_ = 0; }
  // Room for the median depth of a keyframe of `keypoints` keypoints (no allocation per frame).
  void reserve(int keypoints);
  // Whether the frame just tracked with `inliers` at `timestamp_s`, its camera centre at
  // `centre_w`, should become a keyframe. `reference` is the tracker's reference keyframe (none:
  // yes, once min_frames have passed).
  bool needs_keyframe(int inliers, const map::MapStore& map, map::KeyframeId reference, double timestamp_s,
                      const geometry::Vec3& centre_w);
  // The same for a frame the tracker's turn step posed (the map no longer holds the view, so
  // the inlier test says nothing): once urgent_min_frames have passed.
  bool needs_keyframe_in_turn() const {
    return frames_since_keyframe_ >= static_cast<std::uint64_t>(params_.urgent_min_frames);
  }

 private:
  // Back in a known place (revisit_age_s and revisit_radius_depths).
  bool revisit(const map::MapStore& map, map::KeyframeId reference, double timestamp_s, const geometry::Vec3& centre_w);

  KeyframePolicyParams params_;
  std::uint64_t frames_since_keyframe_ = 0;
  std::vector<map::LandmarkId> landmarks_;  // scratch of revisit()
  std::vector<double> depths_;
};

}  // namespace ale::slam
