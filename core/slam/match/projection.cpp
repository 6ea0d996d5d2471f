#include "core/slam/match/projection.h"

#include <algorithm>

namespace ale::slam {

namespace {
// The nearest and second-nearest free keypoint of the target (no landmark yet) to `descriptor`
// within radius_px * scale(level) of (u, v), on level - 1 .. level + 1.
Best2 nearest_free(const MatchContext& ctx, const ProjectionTarget& target, features::HammingKernel hamming,
                   const features::Descriptor& descriptor, float u, float v, int level, float radius_px) {
  const FrameFeatures& frame = target.frame;
  const float r = radius_px * ctx.pyramid.scale[std::clamp(level, 0, ctx.pyramid.levels - 1)];
  ctx.scratch.candidates.clear();
  frame.grid->query(u, v, r, level - 1, level + 1, ctx.scratch.candidates);
  Best2 b;
  for (int i : ctx.scratch.candidates) {
    if (target.landmarks[static_cast<std::size_t>(i)].valid()) continue;
    b.offer(hamming(descriptor, frame.features[i].descriptor), i, frame.features[i].level);
  }
  return b;
}
}  // namespace

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
  scratch.matched.assign(static_cast<std::size_t>(last.count), kNoMatch);  // current keypoint per last keypoint
  int n = 0;
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int il = 0; il < last.count; ++il) {
    const map::LandmarkId id = last_landmarks[static_cast<std::size_t>(il)];
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    float u = 0.0f, v = 0.0f;
    if (!project_pinhole(ctx.pinhole, target.T_cw * lm->p_w, &u, &v) || !current.grid->bounds().contains(u, v)) continue;
    const Best2 b = nearest_free(ctx, target, hamming, lm->descriptor, u, v, last.features[il].level, radius_px);
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

int search_bearings(const MatchContext& ctx, const ProjectionTarget& target, const FrameFeatures& last,
                    const std::vector<map::LandmarkId>& last_landmarks, const geometry::SE3& last_T_cw, float radius_px,
                    std::vector<std::pair<int, int>>& pairs) {
  pairs.clear();
  const FrameFeatures& current = target.frame;
  const std::vector<map::LandmarkId>& current_landmarks = target.landmarks;
  if (!current.grid || static_cast<int>(current_landmarks.size()) != current.count ||
      static_cast<int>(last_landmarks.size()) != last.count) {
    return 0;
  }
  const geometry::CameraIntrinsics& k = ctx.pinhole.intrinsics();
  // the rotation from the last camera to the target's
  const geometry::Mat3 R = target.T_cw.rotation() * last_T_cw.rotation().transpose();
  MatcherScratch& scratch = ctx.scratch;
  scratch.matched.assign(static_cast<std::size_t>(last.count), kNoMatch);
  // the target keypoint's best last keypoint so far: one pair per target keypoint
  scratch.owner.assign(static_cast<std::size_t>(current.count), kNoMatch);
  scratch.best_dist.assign(static_cast<std::size_t>(current.count), 1 << 30);
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int il = 0; il < last.count; ++il) {
    if (last_landmarks[static_cast<std::size_t>(il)].valid()) continue;
    const map::KeyframeFeature& f = last.features[il];
    const geometry::Vec3 ray((f.u - k.cx) / k.fx, (f.v - k.cy) / k.fy, 1.0);
    float u = 0.0f, v = 0.0f;
    if (!project_pinhole(ctx.pinhole, R * ray, &u, &v) || !current.grid->bounds().contains(u, v)) continue;
    const Best2 b = nearest_free(ctx, target, hamming, f.descriptor, u, v, f.level, radius_px);
    if (b.index == kNoMatch || b.dist > ctx.params.th_low) continue;
    if (b.level == b.level2 && static_cast<float>(b.dist) > ctx.params.ratio_projection * static_cast<float>(b.dist2)) {
      continue;
    }
    const std::size_t t = static_cast<std::size_t>(b.index);
    if (b.dist >= scratch.best_dist[t]) continue;
    if (scratch.owner[t] != kNoMatch) scratch.matched[static_cast<std::size_t>(scratch.owner[t])] = kNoMatch;
    scratch.owner[t] = il;
    scratch.best_dist[t] = b.dist;
    scratch.matched[static_cast<std::size_t>(il)] = b.index;
  }
  if (ctx.params.rotation.enabled) {
    drop_inconsistent_rotations(last, current, ctx.params.rotation.bins, scratch.matched, scratch.bins, [](int, int) {});
  }
  for (int il = 0; il < last.count; ++il) {
    const int i = scratch.matched[static_cast<std::size_t>(il)];
    if (i != kNoMatch) pairs.emplace_back(il, i);
  }
  return static_cast<int>(pairs.size());
}

}  // namespace ale::slam
