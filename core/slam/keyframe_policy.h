// When tracking makes a keyframe (ORB-SLAM's NeedNewKeyFrame, trimmed for inline mapping): at
// least min_frames frames after the last one, when the frame tracks fewer than ref_ratio of the
// reference keyframe's trusted landmarks (the view has changed) and still enough of them to
// anchor the new keyframe. Inline mapping is never busy, so ORB-SLAM's "mapper idle" condition
// always holds and the view change alone decides.
#pragma once

#include <cstdint>

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
};

class KeyframePolicy {
 public:
  explicit KeyframePolicy(const KeyframePolicyParams& params) : params_(params) {}

  // A frame arrived (tracked or not).
  void frame_arrived() { ++frames_since_keyframe_; }
  // A keyframe was made: from the current frame, or by the initialiser (its second keyframe).
  void keyframe_made() { frames_since_keyframe_ = 0; }
  // Whether the frame just tracked with `inliers` should become a keyframe. `reference` is the
  // tracker's reference keyframe (none: yes, once min_frames have passed).
  bool needs_keyframe(int inliers, const map::MapStore& map, map::KeyframeId reference) const;
  // The same for a frame the tracker's turn step posed (the map no longer holds the view, so
  // the inlier test says nothing): once urgent_min_frames have passed.
  bool needs_keyframe_in_turn() const {
    return frames_since_keyframe_ >= static_cast<std::uint64_t>(params_.urgent_min_frames);
  }

 private:
  KeyframePolicyParams params_;
  std::uint64_t frames_since_keyframe_ = 0;
};

}  // namespace ale::slam
