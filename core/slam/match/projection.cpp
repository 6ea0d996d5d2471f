#include "core/slam/match/projection.h"

#include <algorithm>

namespace ale::slam {

int search_by_projection(const MatchContext& ctx, const ProjectionTarget& target, const map::MapStore& map,
                         const std::vector<map::LandmarkId>& candidates, float radius_px,
                         std::vector<map::LandmarkId>* in_view) {
  if (in_view) in_view->clear();
  const FrameFeatures& frame = target.frame;
  std::vector<map::LandmarkId>& frame_landmarks = target.landmarks;
  if (!frame.grid || static_cast<int>(frame_landmarks.size()) != frame.count) return 0;
  MatcherScratch& scratch = ctx.scratch;
  const geometry::Vec3 centre = target.T_cw.inverse().translation();
  // ORB-SLAM widens its radius from 2.5 to 4 (x scale) at oblique views
  const float oblique_radius_px = radius_px * 4.0f / 2.5f;
  // landmarks the frame has already, sorted for lookup
  scratch.seen.clear();
  for (map::LandmarkId id : frame_landmarks) {
    if (id.valid()) scratch.seen.push_back(id.value);
  }
  std::sort(scratch.seen.begin(), scratch.seen.end());
  int n = 0;
  LandmarkView view;
  const features::HammingKernel hamming = features::hamming_kernel();
  for (map::LandmarkId id : candidates) {
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    if (std::binary_search(scratch.seen.begin(), scratch.seen.end(), id.value)) continue;
    if (!landmark_in_view(*lm, target.T_cw, centre, ctx.pinhole, frame.grid->bounds(), ctx.pyramid, &view)) continue;
    if (in_view) in_view->push_back(id);
    const int level = view.level;
    const float r = (view.view_cos > 0.998 ? radius_px : oblique_radius_px) * ctx.pyramid.scale[level];
    scratch.candidates.clear();
    frame.grid->query(view.u, view.v, r, level - 1, level, scratch.candidates);
    Best2 b;
    for (int i : scratch.candidates) {
      if (frame_landmarks[static_cast<std::size_t>(i)].valid()) continue;
      b.offer(hamming(lm->descriptor, frame.features[i].descriptor), i, frame.features[i].level);
    }
    if (b.index == kNoMatch || b.dist > ctx.params.th_high) continue;
    if (b.level == b.level2 && static_cast<float>(b.dist) > ctx.params.ratio_projection * static_cast<float>(b.dist2)) {
      continue;
    }
    frame_landmarks[static_cast<std::size_t>(b.index)] = id;
    ++n;
  }
  return n;
}

int search_last_frame(const MatchContext& ctx, const ProjectionTarget& target, const FrameFeatures& last,
                      const std::vector<map::LandmarkId>& last_landmarks, const map::MapStore& map, float radius_px) {
  const FrameFeatures& current = target.frame;
  std::vector<map::LandmarkId>& current_landmarks = target.landmarks;
  if (!current.grid || static_cast<int>(current_landmarks.size()) != current.count ||
      static_cast<int>(last_landmarks.size()) != last.count) {
    return 0;
  }
  MatcherScratch& scratch = ctx.scratch;
  const ScalePyramid& pyramid = ctx.pyramid;
  scratch.matched.assign(static_cast<std::size_t>(last.count), kNoMatch);  // current keypoint per last keypoint
  int n = 0;
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int il = 0; il < last.count; ++il) {
    const map::LandmarkId id = last_landmarks[static_cast<std::size_t>(il)];
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    float u = 0.0f, v = 0.0f;
    if (!project_pinhole(ctx.pinhole, target.T_cw * lm->p_w, &u, &v) || !current.grid->bounds().contains(u, v)) continue;
    const int level = last.features[il].level;
    const float r = radius_px * pyramid.scale[std::clamp(level, 0, pyramid.levels - 1)];
    scratch.candidates.clear();
    current.grid->query(u, v, r, level - 1, level + 1, scratch.candidates);
    Best2 b;
    for (int i : scratch.candidates) {
      if (current_landmarks[static_cast<std::size_t>(i)].valid()) continue;
      b.offer(hamming(lm->descriptor, current.features[i].descriptor), i, current.features[i].level);
    }
    if (b.index == kNoMatch || b.dist > ctx.params.th_high) continue;
    current_landmarks[static_cast<std::size_t>(b.index)] = id;
    scratch.matched[static_cast<std::size_t>(il)] = b.index;
    ++n;
  }
  if (ctx.params.rotation.enabled) {
    n -= drop_inconsistent_rotations(last, current, ctx.params.rotation.bins, scratch.matched, scratch.bins,
                                     [&](int, int i) { current_landmarks[static_cast<std::size_t>(i)] = map::LandmarkId{}; });
  }
  return n;
}

}  // namespace ale::slam
