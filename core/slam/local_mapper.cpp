#include "core/slam/local_mapper.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/chi_square.h"
#include "core/geometry/triangulation.h"
#include "core/slam/local_map.h"

namespace ale::slam {

void LocalMapper::finish_landmark(map::LandmarkId id, map::MapStore& map) {
  map.update_descriptor(id);
  map.update_normal_and_depth(id, pyramid_.scale, pyramid_.levels);
}

MappingReport LocalMapper::process(map::KeyframeId kf, const Frame& frame, map::MapStore& map, map::KeyframeId previous) {
  MappingReport r;
  if (pending_.valid()) r = finish_pending(map);  // only when the caller skipped finish_pending()
  if (!map.keyframe(kf)) return r;
  // the tracked matches become observations of the keyframe
  for (int i = 0; i < frame.size(); ++i) {
    const map::LandmarkId id = frame.landmarks[static_cast<std::size_t>(i)];
    if (!map.landmark(id)) continue;
    if (map.add_observation(id, kf, i).ok()) {
      finish_landmark(id, map);
      ++r.observations_added;
    }
  }
  map.update_connections(kf);
  for (Recent& rc : recent_) ++rc.keyframes_since;
  cull_recent(map, r);
  triangulate(kf, previous, map, r);
  fuse(kf, map, r);
  map.update_connections(kf);
  if (params_.defer_ba) {
    pending_ = kf;
  } else {
    adjust(kf, map, r);
  }
  return r;
}

MappingReport LocalMapper::finish_pending(map::MapStore& map) {
  MappingReport r;
  const map::KeyframeId kf = pending_;
  pending_ = map::KeyframeId{};
  if (kf.valid() && map.keyframe(kf)) adjust(kf, map, r);
  return r;
}

void LocalMapper::adjust(map::KeyframeId kf, map::MapStore& map, MappingReport& r) {
  local_bundle_adjustment(kf, map, r);
  if (params_.cull_keyframes) cull_keyframes(kf, map, r);
}

void LocalMapper::cull_recent(map::MapStore& map, MappingReport& r) {
  std::size_t kept = 0;
  for (const Recent& rc : recent_) {
    const map::Landmark* lm = map.landmark(rc.id);
    if (!lm) continue;
    const double found_ratio = lm->visible > 0 ? static_cast<double>(lm->found) / lm->visible : 0.0;
    if (found_ratio < params_.min_found_ratio || (rc.keyframes_since >= 2 && lm->num_observations <= 2)) {
      map.erase_landmark(rc.id);
      ++r.landmarks_culled;
      continue;
    }
    if (rc.keyframes_since >= 3) continue;  // survived: no longer recent
    recent_[kept++] = rc;
  }
  recent_.resize(kept);
}

void LocalMapper::triangulate(map::KeyframeId kf_id, map::KeyframeId previous, map::MapStore& map, MappingReport& r) {
  const map::Keyframe* kf = map.keyframe(kf_id);
  const geometry::Vec3 c1 = geometry::camera_centre(kf->T_cw);
  const Span<const map::KeyframeFeature> f1 = map.features_of(kf_id);
  grid_a_.build(f1.data(), f1.size(), bounds_);
  const FrameFeatures v1{f1.data(), f1.size(), &grid_a_};
  tri_kfs_.clear();
  for (const map::Covisible& c : map.covisible_of(kf_id).first(params_.triangulation_neighbours)) tri_kfs_.push_back(c.keyframe);
  if (previous.valid() && previous != kf_id && map.keyframe(previous) &&
      std::find(tri_kfs_.begin(), tri_kfs_.end(), previous) == tri_kfs_.end()) {
    tri_kfs_.push_back(previous);
  }
  for (const map::KeyframeId nb_id : tri_kfs_) {
    kf = map.keyframe(kf_id);  // the map does not move objects, but stay explicit after edits
    const map::Keyframe* nb = map.keyframe(nb_id);
    if (!nb) continue;
    const double baseline = (geometry::camera_centre(nb->T_cw) - c1).norm();
    // a keyframe without landmarks (only `previous` can be one) has no depth to compare the
    // baseline with: the parallax test of each pair still holds
    const double depth = keyframe_median_depth(map, nb_id, lms_b_, depths_);
    if (depth > 0.0 ? baseline / depth < params_.min_baseline_depth_ratio : nb_id != previous) continue;
    // beyond this depth the two keyframes' rays meet at less than the triangulation's minimum
    // parallax (the baseline subtends at most baseline / distance); 5 % margin
    const double max_depth =
        1.05 * baseline / std::sqrt(std::max(1e-12, 1.0 - params_.max_cos_parallax * params_.max_cos_parallax));
    const Span<const map::KeyframeFeature> f2 = map.features_of(nb_id);
    grid_b_.build(f2.data(), f2.size(), bounds_);
    const FrameFeatures v2{f2.data(), f2.size(), &grid_b_};
    search_for_triangulation(match_context(), {v1, kf->T_cw, map.keypoint_landmarks(kf_id)},
                             {v2, nb->T_cw, map.keypoint_landmarks(nb_id)}, max_depth, pairs_);
    geometry::TriangulationParams tp;
    tp.max_cos_parallax = params_.max_cos_parallax;
    for (const auto& [i1, i2] : pairs_) {
      const map::KeyframeFeature& a = f1[i1];
      const map::KeyframeFeature& b = f2[i2];
      const int la = std::clamp<int>(a.level, 0, pyramid_.levels - 1);
      const int lb = std::clamp<int>(b.level, 0, pyramid_.levels - 1);
      const geometry::Triangulation t =
          geometry::triangulate_pixels(pinhole_, kf->T_cw, nb->T_cw, geometry::Vec2(a.u, a.v), geometry::Vec2(b.u, b.v),
                                       pyramid_.scale[la], pyramid_.scale[lb], tp);
      if (!t.ok()) continue;
      // scale consistency: the distance ratio must agree with the octave ratio
      const double d1 = (t.p_w - c1).norm(), d2 = (t.p_w - geometry::camera_centre(nb->T_cw)).norm();
      if (d1 <= 0.0 || d2 <= 0.0) continue;
      const double ratio_dist = d2 / d1;
      const double ratio_octave = static_cast<double>(pyramid_.scale[la]) / pyramid_.scale[lb];
      const double factor = 1.5 * pyramid_.scale_factor;
      if (ratio_dist * factor < ratio_octave || ratio_dist > ratio_octave * factor) continue;
      Result<map::LandmarkId> lm = map.add_landmark(t.p_w, a.descriptor, kf_id);
      if (!lm.ok()) return;  // the map is full
      if (!map.add_observation(*lm, kf_id, i1).ok() || !map.add_observation(*lm, nb_id, i2).ok()) {
        map.erase_landmark(*lm);
        continue;
      }
      finish_landmark(*lm, map);
      recent_.push_back({*lm, kf_id, 0});
      ++r.landmarks_created;
    }
  }
}

int LocalMapper::fuse_into(map::KeyframeId target_id, const std::vector<map::LandmarkId>& landmarks, map::MapStore& map) {
  const map::Keyframe* target = map.keyframe(target_id);
  if (!target) return 0;
  const Span<const map::KeyframeFeature> target_features = map.features_of(target_id);
  grid_b_.build(target_features.data(), target_features.size(), bounds_);
  const FusionTarget t{target_id, {target_features.data(), target_features.size(), &grid_b_}, target->T_cw,
                       geometry::camera_centre(target->T_cw)};
  const MatchContext ctx = match_context();
  int fused = 0;
  for (map::LandmarkId id : landmarks) {
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    const int best_i = search_for_fusion(ctx, t, *lm, params_.fuse_radius);
    if (best_i == kNoMatch) continue;
    const map::LandmarkId existing = map.keypoint_landmarks_of(target_id)[best_i];
    if (map.landmark(existing)) {
      // the better-observed landmark survives
      // The survivor keeps the observations that fit (kMaxObservations); the store counts those
      // dropped (MapStats::dropped_observations).
      if (map.landmark(existing)->num_observations >= lm->num_observations) {
        if (!map.replace_landmark(id, existing, map::WhenFull::kDropOverflow).ok()) continue;
        finish_landmark(existing, map);
      } else {
        if (!map.replace_landmark(existing, id, map::WhenFull::kDropOverflow).ok()) continue;
        finish_landmark(id, map);
      }
    } else if (map.add_observation(id, target_id, best_i).ok()) {
      finish_landmark(id, map);
    } else {
      continue;
    }
    ++fused;
  }
  return fused;
}

void LocalMapper::fuse(map::KeyframeId kf_id, map::MapStore& map, MappingReport& r) {
  std::vector<map::KeyframeId>& targets = kfs_;
  targets.clear();
  for (const map::Covisible& c : map.covisible_of(kf_id).first(params_.fuse_neighbours)) targets.push_back(c.keyframe);
  lms_.clear();
  map.landmarks_of(kf_id, lms_);
  for (map::KeyframeId t : targets) r.landmarks_fused += fuse_into(t, lms_, map);
  // and the neighbours' landmarks into the keyframe
  std::vector<map::LandmarkId>& theirs = lms_b_;
  theirs.clear();
  for (map::KeyframeId t : targets) map.landmarks_of(t, theirs);
  std::sort(theirs.begin(), theirs.end());
  theirs.erase(std::unique(theirs.begin(), theirs.end()), theirs.end());
  r.landmarks_fused += fuse_into(kf_id, theirs, map);
}

// A free keyframe's odometry prior comes from the latest earlier keyframe in the problem: its
// predecessor in the map joins, fixed, when it sees none of the window's landmarks. Without it a
// window of keyframes that share nothing with older ones (a turn in the dark, made on the turn
// step's bearings) had no fixed pose and no prior to the map, and floated: on a dark lane two
// such keyframes went 1.7 m off in one BA, and the frames kept relative to them followed.
void LocalMapper::anchor_odometry(const map::MapStore& map, MappingReport& r) {
  // each free local keyframe with odometry: its time, and the latest keyframe before it so far
  anchors_.clear();
  for (map::KeyframeId k : ba_kfs_) {
    const map::Keyframe* local = map.keyframe(k);
    if (local->has_odometry && k != map.root()) anchors_.push_back({map::KeyframeId{}, local->timestamp_s, -1e300});
  }
  const map::MapId current = map.current_map();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    if (!k.has_odometry || k.map_id != current) return;
    for (Anchor& a : anchors_) {
      if (k.timestamp_s < a.before_s && k.timestamp_s > a.anchor_s) a = {id, a.before_s, k.timestamp_s};
    }
  });
  for (const Anchor& a : anchors_) {
    if (a.anchor.valid() && ba_.add_keyframe(a.anchor, true)) ++r.ba_fixed;
  }
}

void LocalMapper::local_bundle_adjustment(map::KeyframeId kf_id, map::MapStore& map, MappingReport& r) {
  ba_kfs_.assign(1, kf_id);
  // covisible is by weight, descending
  for (const map::Covisible& c : map.covisible_of(kf_id).first(params_.ba_max_keyframes - 1)) ba_kfs_.push_back(c.keyframe);
  std::sort(ba_kfs_.begin() + 1, ba_kfs_.end());
  ba_lms_.clear();
  for (map::KeyframeId k : ba_kfs_) map.landmarks_of(k, ba_lms_);
  std::sort(ba_lms_.begin(), ba_lms_.end());
  ba_lms_.erase(std::unique(ba_lms_.begin(), ba_lms_.end()), ba_lms_.end());
  if (ba_lms_.empty()) return;
  // every keyframe that sees a local landmark takes part; those outside the local set are fixed
  std::vector<map::KeyframeId>& all = kfs_;
  all = ba_kfs_;
  for (map::LandmarkId l : ba_lms_) {
    for (const map::Observation& o : map.observations_of(l)) all.push_back(o.keyframe);
  }
  std::sort(all.begin() + static_cast<std::ptrdiff_t>(ba_kfs_.size()), all.end());
  all.erase(std::unique(all.begin() + static_cast<std::ptrdiff_t>(ba_kfs_.size()), all.end()), all.end());
  ba_.reset(map);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const map::KeyframeId k = all[i];
    const bool local = i < ba_kfs_.size();
    const bool fixed = !local || k == map.root();
    if (!ba_.add_keyframe(k, fixed)) continue;
    if (local && !fixed) ++r.ba_keyframes;
    if (fixed) ++r.ba_fixed;
  }
  for (map::LandmarkId l : ba_lms_) ba_.add_landmark(l);
  if (odometry_) {
    anchor_odometry(map, r);
    ba_.add_odometry_priors(*odometry_, gyro_bias_rps_);
  }
  if (floor_) r.ba_floor = ba_.add_floor_observations(floor_params_, *floor_);
  r.ba_points = static_cast<int>(ba_lms_.size());
  optim::BaOptions options;
  options.lm.max_iterations = params_.ba_iterations;
  options.passes = 2;
  options.first_pass_iterations = params_.ba_first_pass_iterations;
  options.lm.function_tolerance = params_.ba_function_tolerance;
  options.first_pass_function_tolerance = params_.ba_first_pass_function_tolerance;
  if (!MapBundleAdjustment::usable(ba_.solve(options))) return;
  ba_.write_back(map);
  for (int k = 0; k < ba_.num_observations(); ++k) {
    if (ba_.is_inlier(k)) continue;
    map.erase_observation(ba_.observation(k).first, ba_.observation(k).second);
    ++r.ba_outliers;
  }
  for (map::LandmarkId l : ba_lms_) {
    const map::Landmark* lm = map.landmark(l);
    if (lm && lm->num_observations < 2) {
      map.erase_landmark(l);
    } else if (lm) {
      finish_landmark(l, map);
    }
  }
}

void LocalMapper::cull_keyframes(map::KeyframeId kf_id, map::MapStore& map, MappingReport& r) {
  std::vector<map::KeyframeId>& local = kfs_;
  local.clear();
  for (const map::Covisible& c : map.covisible_of(kf_id)) local.push_back(c.keyframe);
  std::sort(local.begin(), local.end());
  for (map::KeyframeId id : local) {
    if (id == map.root() || id == kf_id || !map.keyframe(id)) continue;
    const Span<const map::LandmarkId> ids = map.keypoint_landmarks_of(id);
    const Span<const map::KeyframeFeature> features = map.features_of(id);
    int total = 0, redundant = 0;
    for (int i = 0; i < ids.size(); ++i) {
      const map::Landmark* lm = map.landmark(ids[i]);
      if (!lm) continue;
      ++total;
      if (lm->num_observations <= params_.redundant_observers) continue;
      const int level = features[i].level;
      int observers = 0;
      for (const map::Observation& ob : map.observations_of(ids[i])) {
        if (observers >= params_.redundant_observers) break;
        if (ob.keyframe == id) continue;
        if (map.features_of(ob.keyframe)[static_cast<int>(ob.keypoint)].level <= level + 1) ++observers;
      }
      if (observers >= params_.redundant_observers) ++redundant;
    }
    if (total > 0 && redundant > params_.redundant_share * total) {
      map.erase_keyframe(id);
      ++r.keyframes_culled;
    }
  }
}

namespace {
constexpr ConfigField kMappingFields[] = {
    number<&LocalMapperParams::max_cos_parallax>("max_cos_parallax", 0.9, 1.0,
                                                 "new landmarks need rays at least this far apart (cosine)"),
    number<&LocalMapperParams::triangulation_neighbours>("triangulation_neighbours", 1, 1000,
                                                          "covisible keyframes new points are triangulated with"),
    number<&LocalMapperParams::fuse_neighbours>("fuse_neighbours", 0, 1000, "keyframes searched for duplicates"),
    number<&LocalMapperParams::ba_iterations>("ba_iterations", 0, 1000, "local BA iterations per pass"),
    number<&LocalMapperParams::ba_first_pass_iterations>("ba_first_pass_iterations", 1, 1000,
                                                         "at most, of the local BA's first pass (outlier separation)"),
    number<&LocalMapperParams::ba_function_tolerance>("ba_function_tolerance", 0.0, 1.0,
                                                      "relative cost change that ends a local BA pass"),
    number<&LocalMapperParams::ba_first_pass_function_tolerance>(
        "ba_first_pass_function_tolerance", 0.0, 1.0, "... that ends the first pass (the larger of the two)"),
    number<&LocalMapperParams::ba_max_keyframes>("ba_max_keyframes", 1, 1000,
                                                  "free keyframes of the local BA (the new one, its most covisible)"),
    number<&LocalMapperParams::min_found_ratio>("min_found_ratio", 0, 1, "recent points found less often are culled"),
    flag<&LocalMapperParams::cull_keyframes>("cull_keyframes", "drop keyframes whose points others see"),
    flag<&LocalMapperParams::defer_ba>("defer_ba", "run a keyframe's local BA and culling on the next frame"),
};
}  // namespace

extern constexpr ConfigTable kLocalMapperConfig = table_of<LocalMapperParams>(kMappingFields);

}  // namespace ale::slam
