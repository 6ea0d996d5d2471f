#include "core/slam/loop_closer.h"

#include <algorithm>
#include <cmath>

#include "core/base/median.h"
#include "core/geometry/chi_square.h"
#include "core/slam/local_map.h"
#include "core/slam/local_mapper.h"
#include "core/slam/match/bow.h"
#include "core/slam/match/projection.h"

namespace ale::slam {
namespace {

// The rigid pose a similarity world -> camera stands for: the same rotation, the translation in
// the world's units.
geometry::SE3 rigid(const geometry::Sim3& S) { return geometry::SE3(S.so3(), S.translation() / S.scale()); }

bool overlaps(const std::vector<map::KeyframeId>& a, const std::vector<map::KeyframeId>& b) {
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (*i == *j) return true;
    if (*i < *j) ++i; else ++j;
  }
  return false;
}

// The path from keyframe `from` to keyframe `to` through the keyframes `take` accepts between their
// times, in time order: the sum of step(a, b) over consecutive ones. by_time: scratch.
template <class Take, class Step>
double path_between(const map::Keyframe& from, const map::Keyframe& to, const map::MapStore& map, Take take, Step step,
                    std::vector<std::pair<double, map::KeyframeId>>& by_time) {
  by_time.clear();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    if (take(k) && k.timestamp_s >= from.timestamp_s && k.timestamp_s <= to.timestamp_s) by_time.emplace_back(k.timestamp_s, id);
  });
  std::sort(by_time.begin(), by_time.end());
  double path = 0.0;
  for (std::size_t i = 1; i < by_time.size(); ++i) path += step(*map.keyframe(by_time[i - 1].second), *map.keyframe(by_time[i].second));
  return path;
}

// 99 % gate of a chi-square with 2 degrees of freedom (ORB-SLAM's Sim3 check).
constexpr double kChi2TwoDof99 = 9.21;

}  // namespace

LoopCloser::LoopCloser(const LoopCloserParams& params, const geometry::Camera& pinhole, const ScalePyramid& pyramid,
                       const ImageBounds& bounds, const MatcherParams& matcher, const PoseRefinerParams& refiner,
                       const map::MapCapacity& capacity)
    : params_(params),
      matcher_(matcher),
      pinhole_(pinhole),
      pyramid_(pyramid),
      bounds_(bounds),
      refiner_(refiner, pinhole),
      ba_(pinhole, pyramid) {
  const std::size_t k = static_cast<std::size_t>(capacity.max_keyframes);
  moved_stamp_.assign(k, 0);
  before_.resize(k);
  factor_.assign(k, 1.0);
  corrected_.resize(k);
  connected_stamp_.assign(k, 0);
  neighbours_before_.resize(k);
  for (auto& n : neighbours_before_) n.reserve(map::kMaxCovisible);
  vertex_of_slot_.assign(k, -1);
  pre_loop_.resize(k);
  pre_loop_stamp_.assign(k, 0);
  landmark_keyframe_.resize(static_cast<std::size_t>(capacity.max_landmarks));
  landmark_stamp_.assign(static_cast<std::size_t>(capacity.max_landmarks), 0);
}

void LoopCloser::reset() {
  groups_.clear();
  next_groups_.clear();
  keyframes_since_loop_ = 0;
  stage_ = Stage::kIdle;
  moved_ = false;
}

double LoopCloser::length_factor(map::KeyframeId kf) const {
  const std::size_t s = kf.slot();
  return moved_ && s < moved_stamp_.size() && moved_stamp_[s] == move_stamp_ ? factor_[s] : 1.0;
}

geometry::SE3 LoopCloser::pose_before(map::KeyframeId kf, const map::MapStore& map) const {
  const std::size_t s = kf.slot();
  if (moved_ && s < moved_stamp_.size() && moved_stamp_[s] == move_stamp_) return before_[s];
  const map::Keyframe* k = map.keyframe(kf);
  return k ? k->T_cw : geometry::SE3{};
}

// ORB-SLAM's DetectLoop: the candidates' groups (each with its covisible keyframes) that overlap
// a group kept from the previous keyframe carry its consistency on; a candidate whose group
// reaches params_.consistency is verified.
void LoopCloser::consistent_candidates(const map::MapStore& map, LoopReport& report) {
  consistent_.clear();
  next_groups_.clear();
  group_taken_.assign(groups_.size(), 0);
  for (const place::PlaceCandidate& c : candidates_) {
    group_scratch_.clear();
    group_scratch_.push_back(c.keyframe);
    for (const map::Covisible& n : map.covisible_of(c.keyframe)) group_scratch_.push_back(n.keyframe);
    std::sort(group_scratch_.begin(), group_scratch_.end());
    bool enough = false;
    bool some = false;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (!overlaps(group_scratch_, groups_[g].keyframes)) continue;
      some = true;
      const int consistency = groups_[g].consistency + 1;
      if (!group_taken_[g]) {
        next_groups_.push_back({group_scratch_, consistency});
        group_taken_[g] = 1;
      }
      if (consistency >= params_.consistency && !enough) {
        consistent_.push_back(c.keyframe);
        enough = true;
      }
    }
    if (!some) next_groups_.push_back({group_scratch_, 0});
  }
  std::swap(groups_, next_groups_);
  report.consistent = static_cast<int>(consistent_.size());
}

LoopReport LoopCloser::step(map::KeyframeId kf, map::MapStore& map, const place::KeyframeDatabase& places,
                            bool fixed_scale, LocalMapper& mapper) {
  LoopReport report;
  report.keyframe = kf;
  moved_ = false;
  switch (stage_) {
    case Stage::kCorrect:
      correct(map, mapper, report);
      return report;
    case Stage::kGraph:
      optimise_essential_graph(map, report);
      stage_ = params_.global_ba_iterations > 0 ? Stage::kGlobalBa : Stage::kIdle;
      global_ba_left_ = params_.global_ba_iterations;
      return report;
    case Stage::kGlobalBa:
      global_bundle_adjustment(map, report);
      return report;
    case Stage::kMerge:
      merge(map, mapper, report);
      return report;
    case Stage::kWeld:
      weld(map, report);
      return report;
    case Stage::kIdle:
      break;
  }
  if (!params_.enabled || !map.keyframe(kf) || !places.contains(kf)) return report;
  detect(kf, map, places, fixed_scale, report);
  loops_refused_ += report.refused ? 1 : 0;
  return report;
}

void LoopCloser::detect(map::KeyframeId kf, const map::MapStore& map, const place::KeyframeDatabase& places,
                        bool fixed_scale, LoopReport& report) {
  ++keyframes_since_loop_;
  if (static_cast<int>(map.stats().map_keyframes) < params_.min_keyframes || keyframes_since_loop_ < params_.keyframes_between) {
    groups_.clear();
    return;
  }
  report.checked = true;
  report.time_s = map.keyframe(kf)->timestamp_s;
  // the lowest score of the keyframe against its neighbours: a loop must look at least as alike
  const place::BowVector* bow = places.bow(kf);
  float min_score = 1.0f;
  bool any = false;
  for (const map::Covisible& c : map.covisible_of(kf)) {
    const place::BowVector* nb = places.bow(c.keyframe);
    if (!nb) continue;
    min_score = std::min(min_score, static_cast<float>(place::Vocabulary::score(*bow, *nb)));
    any = true;
  }
  if (!any) {
    groups_.clear();
    return;
  }
  places.loop_candidates(kf, map, min_score, candidates_);
  report.candidates = static_cast<int>(candidates_.size());
  consistent_candidates(map, report);
  for (map::KeyframeId loop : consistent_) {
    // a place of an older map: a rigid motion only when both maps are metric
    const map::MapId other = map.keyframe(loop)->map_id;
    const bool merging = other != map.keyframe(kf)->map_id;
    const map::MapInfo* other_info = map.map_info(other);
    if (merging && !(params_.merge && other_info)) continue;
    if (!verify(kf, loop, map, places, fixed_scale && (!merging || other_info->metric), report)) continue;
    const map::Keyframe& k = *map.keyframe(kf);
    const map::Keyframe& l = *map.keyframe(loop);
    report.loop_keyframe = loop;
    report.loop_time_s = l.timestamp_s;
    report.scale = loop_scale_;
    if (merging) {
      // the two maps have no common frame to bound a correction in: the verification decides,
      // and the wheel odometry, which runs on through the loss, when there is one
      if (fixed_scale && other_info->metric) {
        std::vector<map::LandmarkId>& scratch = local_;
        if (odometry_disagrees(k, l, map, keyframe_median_depth(map, kf, scratch, depths_), report)) continue;
      }
      report.refused = false;
      report.message = "place of map " + std::to_string(other.value) + " recognised: the map merges into it";
      loop_kf_ = kf;
      loop_ = loop;
      stage_ = Stage::kMerge;
      keyframes_since_loop_ = 0;
      groups_.clear();
      return;
    }
    // the correction bound: drift since the place was seen, not a jump across the map
    report.correction = (geometry::camera_centre(loop_pose_) - geometry::camera_centre(k.T_cw)).norm();
    std::vector<map::LandmarkId>& scratch = local_;
    const double depth = keyframe_median_depth(map, kf, scratch, depths_);
    const double bound = drift_bound(driven_since(l, k, map), depth);
    if (report.correction > bound) {
      report.refused = true;
      report.message = "loop to the keyframe of " + std::to_string(l.timestamp_s) + " s refused: it moves the keyframe " +
                       std::to_string(report.correction) + " map units, more than the drift bound " + std::to_string(bound) +
                       " (the loop's scale " + std::to_string(loop_scale_) + ")";
      continue;
    }
    // verified: the map moves on the next frames
    report.refused = false;
    report.message.clear();
    report.closed = true;
    loop_kf_ = kf;
    loop_ = loop;
    stage_ = Stage::kCorrect;
    ++loops_closed_;
    keyframes_since_loop_ = 0;
    groups_.clear();
    return;
  }
}

// A merge in metric maps with odometry: where the odometry since the older keyframe l puts the
// camera of k in the older map, against where the merge puts it (loop_pose_); refused (counted)
// beyond the loop's drift bound over the odometry's path from l to k (the keyframes of every map
// in between, in time order).
bool LoopCloser::odometry_disagrees(const map::Keyframe& k, const map::Keyframe& l, const map::MapStore& map,
                                    double depth, LoopReport& report) {
  if (!odometry_ || !k.has_odometry || !l.has_odometry) return false;
  const geometry::SE3 T_lk = camera_between(odometry_->T_bc, keyframe_odometry(l), keyframe_odometry(k));
  const geometry::Vec3 predicted = geometry::camera_centre(T_lk.inverse() * l.T_cw);
  const double off = (geometry::camera_centre(loop_pose_) - predicted).norm();
  const double path = path_between(
      l, k, map, [](const map::Keyframe& c) { return c.has_odometry; },
      [](const map::Keyframe& a, const map::Keyframe& b) {
        return std::hypot(b.odometry_x_m - a.odometry_x_m, b.odometry_y_m - a.odometry_y_m);
      },
      by_time_);
  const double bound = drift_bound(path, depth);
  if (off <= bound) return false;
  ++merges_refused_;
  report.merge_refused = true;
  report.message = "merge with the keyframe of " + std::to_string(l.timestamp_s) + " s refused: it puts the camera " +
                   std::to_string(off) + " m from where the odometry does, more than the bound " + std::to_string(bound);
  return true;
}

// The path the keyframes between the loop's keyframe and kf drove (map units), from their
// centres in time order.
double LoopCloser::driven_since(const map::Keyframe& loop, const map::Keyframe& kf, const map::MapStore& map) {
  return path_between(
      loop, kf, map, [&](const map::Keyframe& k) { return k.map_id == kf.map_id; },
      [](const map::Keyframe& a, const map::Keyframe& b) {
        return (geometry::camera_centre(b.T_cw) - geometry::camera_centre(a.T_cw)).norm();
      },
      by_time_);
}

// The drift the robot can have gathered over `path` (map units) near a keyframe of median depth
// `depth`: what a loop's correction, or a merge's disagreement with the odometry, may reach.
double LoopCloser::drift_bound(double path, double depth) const {
  return params_.max_correction_ratio * path + params_.max_correction_floor_depths * depth;
}

bool LoopCloser::verify(map::KeyframeId kf, map::KeyframeId loop, const map::MapStore& map,
                        const place::KeyframeDatabase& places, bool fixed_scale, LoopReport& report) {
  const map::Keyframe* k = map.keyframe(kf);
  const map::Keyframe* l = map.keyframe(loop);
  const place::FeatureVector* kfv = places.feature_vector(kf);
  const place::FeatureVector* lfv = places.feature_vector(loop);
  if (!k || !l || !kfv || !lfv) return false;
  const Span<const map::KeyframeFeature> features = map.features_of(kf);
  frame_.features.assign(features.begin(), features.end());
  frame_.index(bounds_);
  const int bow_matches = search_by_bow(match_context(), {frame_.view(), *kfv, frame_.landmarks}, map, loop, *lfv);
  report.bow_matches = std::max(report.bow_matches, bow_matches);
  if (bow_matches < params_.min_bow_matches) return false;

  // the matched landmarks in each keyframe's camera: x in the loop's, y in the keyframe's
  const map::LandmarkId* own = map.keypoint_landmarks(kf);
  x_.clear();
  y_.clear();
  pair_keypoint_.clear();
  for (int i = 0; i < frame_.size(); ++i) {
    const map::LandmarkId theirs = frame_.landmarks[static_cast<std::size_t>(i)];
    const map::Landmark* q = map.landmark(theirs);
    const map::Landmark* p = map.landmark(own[i]);
    if (!q || !p || own[i] == theirs) {
      frame_.landmarks[static_cast<std::size_t>(i)] = map::LandmarkId{};
      continue;
    }
    x_.push_back(l->T_cw * q->p_w);
    y_.push_back(k->T_cw * p->p_w);
    pair_keypoint_.push_back(i);
  }
  if (static_cast<int>(x_.size()) < params_.min_bow_matches) return false;
  depths_.clear();
  for (const geometry::Vec3& y : y_) depths_.push_back(y.z());
  const double depth_y = median_in_place(depths_);
  depths_.clear();
  for (const geometry::Vec3& x : x_) depths_.push_back(x.z());
  const double depth_x = median_in_place(depths_);
  if (!(depth_x > 0.0) || !(depth_y > 0.0)) return false;

  geometry::Sim3RansacParams rp;
  rp.ransac.seed = params_.seed;
  rp.ransac.max_iterations = 300;
  rp.with_scale = !fixed_scale;
  rp.max_error_y = params_.sim3_gate_depths * depth_y;
  rp.max_error_x = params_.sim3_gate_depths * depth_x;
  rp.min_inliers = params_.min_sim3_inliers;
  if (!geometry::solve_sim3_ransac(x_, y_, rp, &sim3_, sim3_scratch_).ok()) return false;
  const geometry::Sim3 S_kl = sim3_.S_yx;
  const geometry::Sim3 S_lk = S_kl.inverse();

  // reprojection in both keyframes
  const map::KeyframeFeature* lf = map.features(loop);
  int inliers = 0;
  for (std::size_t m = 0; m < x_.size(); ++m) {
    const std::size_t i = static_cast<std::size_t>(pair_keypoint_[m]);
    bool ok = sim3_.inlier_mask[m] != 0;
    geometry::Vec2 uv;
    if (ok) {
      const map::KeyframeFeature& f = frame_.features[i];
      const int level = std::clamp<int>(f.level, 0, pyramid_.levels - 1);
      ok = pinhole_.project(S_kl * x_[m], &uv) &&
           (uv - geometry::Vec2(f.u, f.v)).squaredNorm() * pyramid_.inv_sigma2[level] <= kChi2TwoDof99;
    }
    if (ok) {
      ok = false;
      for (const map::Observation& o : map.observations_of(frame_.landmarks[i])) {
        if (o.keyframe != loop) continue;
        const map::KeyframeFeature& g = lf[o.keypoint];
        const int level = std::clamp<int>(g.level, 0, pyramid_.levels - 1);
        ok = pinhole_.project(S_lk * y_[m], &uv) &&
             (uv - geometry::Vec2(g.u, g.v)).squaredNorm() * pyramid_.inv_sigma2[level] <= kChi2TwoDof99;
        break;
      }
    }
    if (ok) {
      ++inliers;
    } else {
      frame_.landmarks[i] = map::LandmarkId{};
    }
  }
  report.sim3_inliers = std::max(report.sim3_inliers, inliers);
  if (inliers < params_.min_sim3_inliers) return false;

  // the keyframe posed in the loop's place, then more of the loop's neighbourhood found there
  frame_.T_cw = rigid(S_kl * geometry::Sim3(l->T_cw));
  neighbourhood_landmarks(map, loop, params_.covisible_per_keyframe, local_);
  // the keyframe's own landmarks are not the loop's: a projection search must not match them
  local_.erase(std::remove_if(local_.begin(), local_.end(),
                              [&](map::LandmarkId id) {
                                for (const map::Observation& o : map.observations_of(id)) {
                                  if (o.keyframe == kf) return true;
                                }
                                return false;
                              }),
               local_.end());
  search_by_projection(match_context(), {frame_.view(), frame_.T_cw, frame_.landmarks}, map, local_,
                       params_.projection_radius_px);
  frame_.has_pose = true;
  int refined = 0;
  if (!refiner_.refine(frame_, map, &refined)) refined = 0;
  report.inliers = std::max(report.inliers, refined);
  if (refined < params_.min_inliers) return false;
  loop_pose_ = frame_.T_cw;
  loop_matches_.assign(frame_.landmarks.begin(), frame_.landmarks.end());
  for (std::size_t i = 0; i < loop_matches_.size(); ++i) {
    if (frame_.outlier[i]) loop_matches_[i] = map::LandmarkId{};
  }
  // The scale from the refined pose: the median ratio of each matched keypoint's depth in the
  // keyframe's map to its depth in the loop's place (the similarity's scale rests on the few
  // RANSAC inliers and the monocular depths' noise; a few percent off it shrinks or stretches
  // the whole neighbourhood).
  loop_scale_ = 1.0;
  if (!fixed_scale) {
    depths_.clear();
    for (std::size_t i = 0; i < loop_matches_.size(); ++i) {
      const map::Landmark* q = map.landmark(loop_matches_[i]);
      const map::Landmark* p = map.landmark(own[i]);
      if (!q || !p || own[i] == loop_matches_[i]) continue;
      const double zq = (loop_pose_ * q->p_w).z();
      const double zp = (k->T_cw * p->p_w).z();
      if (zq > 0.0 && zp > 0.0) depths_.push_back(zp / zq);
    }
    loop_scale_ = static_cast<int>(depths_.size()) >= params_.min_sim3_inliers ? median_in_place(depths_) : S_kl.scale();
  }
  return true;
}

void LoopCloser::begin_move(const map::MapStore& map) {
  if (++move_stamp_ == 0) {
    std::fill(moved_stamp_.begin(), moved_stamp_.end(), 0u);
    move_stamp_ = 1;
  }
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    before_[id.slot()] = k.T_cw;
    factor_[id.slot()] = 1.0;
    moved_stamp_[id.slot()] = move_stamp_;
  });
  moved_ = true;
}

// The first frame after a verified loop: the keyframe and its covisible neighbours, with the
// landmarks they see, where the loop puts them; the landmarks seen twice fused; the two places
// linked.
void LoopCloser::correct(map::MapStore& map, LocalMapper& mapper, LoopReport& report) {
  stage_ = Stage::kIdle;
  const map::KeyframeId kf = loop_kf_;
  const map::KeyframeId loop = loop_;
  if (!map.keyframe(kf) || !map.keyframe(loop)) {
    report.message = "loop not closed: a keyframe of it left the map";
    return;
  }
  next_stamp();
  begin_move(map);
  // every keyframe's pose before the loop: the essential graph's measurements
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    pre_loop_[id.slot()] = k.T_cw;
    pre_loop_stamp_[id.slot()] = stamp_;
  });

  const geometry::SE3 T_kw = map.keyframe(kf)->T_cw;
  const geometry::Sim3 S_kw(loop_pose_.so3(), loop_scale_ * loop_pose_.translation(), loop_scale_);
  connected_.clear();
  connected_.push_back(kf);
  for (const map::Covisible& c : map.covisible_of(kf)) connected_.push_back(c.keyframe);
  for (map::KeyframeId c : connected_) {
    const std::size_t s = c.slot();
    connected_stamp_[s] = stamp_;
    corrected_[s] = geometry::Sim3(map.keyframe(c)->T_cw * T_kw.inverse()) * S_kw;
    neighbours_before_[s].clear();
    for (const map::Covisible& n : map.covisible_of(c)) neighbours_before_[s].push_back(n.keyframe);
    std::sort(neighbours_before_[s].begin(), neighbours_before_[s].end());
  }
  for (map::KeyframeId c : connected_) {
    const std::size_t s = c.slot();
    const geometry::SE3 T_cw = map.keyframe(c)->T_cw;
    landmarks_.clear();
    map.landmarks_of(c, landmarks_);
    for (map::LandmarkId id : landmarks_) {
      map::Landmark* lm = map.landmark(id);
      if (!lm || landmark_stamp_[id.slot()] == stamp_) continue;
      landmark_stamp_[id.slot()] = stamp_;
      landmark_keyframe_[id.slot()] = c;
      lm->p_w = corrected_[s].inverse() * (T_cw * lm->p_w);
    }
  }
  for (map::KeyframeId c : connected_) {
    map.keyframe(c)->T_cw = rigid(corrected_[c.slot()]);
    factor_[c.slot()] = 1.0 / loop_scale_;
  }

  fuse_place(kf, loop, map, mapper, report);
  report.corrected_keyframes = static_cast<int>(connected_.size());
  stage_ = Stage::kGraph;
}

// The landmarks kf and the loop's place both see fused (the loop's survive), the loop's
// neighbourhood fused into connected_, and the two places linked.
void LoopCloser::fuse_place(map::KeyframeId kf, map::KeyframeId loop, map::MapStore& map, LocalMapper& mapper,
                            LoopReport& report) {
  for (std::size_t i = 0; i < loop_matches_.size(); ++i) {
    const map::LandmarkId theirs = loop_matches_[i];
    if (!map.landmark(theirs)) continue;
    const map::LandmarkId mine = map.keypoint_landmarks(kf)[i];
    if (mine == theirs) continue;
    if (map.landmark(mine)) {
      if (!map.replace_landmark(mine, theirs, map::WhenFull::kDropOverflow).ok()) continue;
    } else if (!map.add_observation(theirs, kf, static_cast<int>(i)).ok()) {
      continue;
    }
    map.update_descriptor(theirs);
    ++report.landmarks_fused;
  }
  // the loop's neighbourhood into the moved keyframes
  neighbourhood_landmarks(map, loop, params_.covisible_per_keyframe, local_);
  for (map::KeyframeId c : connected_) report.landmarks_fused += mapper.fuse_landmarks(c, local_, map);
  for (map::KeyframeId c : connected_) map.update_connections(c);
  map.update_connections(loop);
  (void)map.add_loop_edge(kf, loop);
  report.keyframe = kf;
  report.loop_keyframe = loop;
}

// The frame after a verified place of an older map: the current map moves into the older one's
// frame and units by the similarity the place gives, the two become one, and the place's
// landmarks are fused.
void LoopCloser::merge(map::MapStore& map, LocalMapper& mapper, LoopReport& report) {
  stage_ = Stage::kIdle;
  const map::KeyframeId kf = loop_kf_;
  const map::KeyframeId loop = loop_;
  const map::Keyframe* k = map.keyframe(kf);
  const map::Keyframe* l = map.keyframe(loop);
  report.keyframe = kf;
  report.loop_keyframe = loop;
  auto refuse = [&](const std::string& why) {
    ++merges_refused_;
    report.merge_refused = true;
    report.message = "merge not made: " + why;
  };
  if (!k || !l) return refuse("a keyframe of it left the map");
  const map::MapId from = k->map_id;
  const map::MapId into = l->map_id;
  if (from != map.current_map() || from == into || !map.map_info(into)) return refuse("its map is no longer held");
  // older world -> the keyframe's camera (in the current map's units), and current world -> older world
  const geometry::Sim3 S_kw(loop_pose_.so3(), loop_scale_ * loop_pose_.translation(), loop_scale_);
  const geometry::Sim3 G = S_kw.inverse() * geometry::Sim3(k->T_cw);
  if (!(G.scale() > 0.0) || !std::isfinite(G.scale()) || !G.translation().allFinite() ||
      !G.so3().quaternion().coeffs().allFinite()) {
    return refuse("a degenerate similarity");
  }
  const geometry::Sim3 G_inv = G.inverse();
  begin_move(map);
  next_stamp();
  vertex_keyframe_.clear();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& c) {
    if (c.map_id == from) vertex_keyframe_.push_back(id);
  });
  for (map::KeyframeId id : vertex_keyframe_) {
    map::Keyframe& c = *map.keyframe(id);
    c.T_cw = rigid(geometry::Sim3(c.T_cw) * G_inv);
    factor_[id.slot()] = 1.0 / loop_scale_;
    connected_stamp_[id.slot()] = stamp_;
  }
  landmarks_.clear();
  map.for_each_landmark([&](map::LandmarkId id, const map::Landmark& lm) {
    if (lm.map_id == from) landmarks_.push_back(id);
  });
  const float distance_factor = static_cast<float>(G.scale());
  for (map::LandmarkId id : landmarks_) {
    map::Landmark& lm = *map.landmark(id);
    lm.p_w = G * lm.p_w;
    lm.normal = G.so3() * lm.normal;
    lm.min_distance *= distance_factor;
    lm.max_distance *= distance_factor;
  }
  if (Status s = map.merge_map(from, into, loop); !s.ok()) return refuse(s.message());
  connected_.clear();
  connected_.push_back(kf);
  for (const map::Covisible& c : map.covisible_of(kf)) connected_.push_back(c.keyframe);
  fuse_place(kf, loop, map, mapper, report);
  report.merged = true;
  report.corrected_keyframes = static_cast<int>(vertex_keyframe_.size());
  ++merges_;
  stage_ = Stage::kWeld;
}

// The frame after a merge: a bundle adjustment around the seam, the moved keyframe's
// neighbourhood free, every other keyframe that sees its landmarks (the older map's) fixed.
void LoopCloser::weld(map::MapStore& map, LoopReport& report) {
  stage_ = Stage::kIdle;
  const map::KeyframeId kf = loop_kf_;
  if (!map.keyframe(kf)) return;
  ba_.reset(map);
  connected_.clear();
  connected_.push_back(kf);
  for (const map::Covisible& c : map.covisible_of(kf)) {
    if (connected_stamp_[c.keyframe.slot()] == stamp_) connected_.push_back(c.keyframe);
  }
  for (map::KeyframeId c : connected_) ba_.add_keyframe(c, false);
  landmarks_.clear();
  for (map::KeyframeId c : connected_) map.landmarks_of(c, landmarks_);
  std::sort(landmarks_.begin(), landmarks_.end());
  landmarks_.erase(std::unique(landmarks_.begin(), landmarks_.end()), landmarks_.end());
  for (map::LandmarkId id : landmarks_) {
    for (const map::Observation& o : map.observations_of(id)) ba_.add_keyframe(o.keyframe, true);
  }
  for (map::LandmarkId id : landmarks_) ba_.add_landmark(id);
  optim::BaOptions options;
  options.lm.max_iterations = params_.welding_ba_iterations;
  if (!MapBundleAdjustment::usable(ba_.solve(options))) return;
  ba_.write_back(map);
  for (map::LandmarkId id : landmarks_) map.update_normal_and_depth(id, pyramid_.scale, pyramid_.levels);
  report.welded_keyframes = static_cast<int>(connected_.size());
}

void LoopCloser::next_stamp() {
  if (++stamp_ == 0) {
    std::fill(connected_stamp_.begin(), connected_stamp_.end(), 0u);
    std::fill(landmark_stamp_.begin(), landmark_stamp_.end(), 0u);
    std::fill(pre_loop_stamp_.begin(), pre_loop_stamp_.end(), 0u);
    stamp_ = 1;
  }
}

// The next frame: the correction spread over the map by the essential graph, the loop's old
// keyframe fixed; each landmark follows the keyframe that corrected it or its reference keyframe.
void LoopCloser::optimise_essential_graph(map::MapStore& map, LoopReport& report) {
  const map::KeyframeId loop = loop_;
  if (!map.keyframe(loop)) {
    report.message = "essential graph not optimised: the loop's keyframe left the map";
    return;
  }
  begin_move(map);
  // vertices: the map's keyframes in slot order
  vertex_keyframe_.clear();
  vertex_initial_.clear();
  const map::MapId current = map.current_map();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    if (k.map_id != current) return;
    const std::size_t s = id.slot();
    vertex_of_slot_[s] = static_cast<int>(vertex_keyframe_.size());
    vertex_keyframe_.push_back(id);
    // the loop's neighbourhood at the scale the loop gave it (its map poses are the rigid parts)
    const double scale = connected_stamp_[s] == stamp_ ? loop_scale_ : 1.0;
    vertex_initial_.emplace_back(k.T_cw.so3(), scale * k.T_cw.translation(), scale);
  });
  auto vertex = [&](map::KeyframeId id) {
    const map::Keyframe* k = map.keyframe(id);
    return k && k->map_id == current ? vertex_of_slot_[id.slot()] : -1;
  };
  // the relative poses before the loop (the odometry of the map) and with the loop's correction
  auto before = [&](int v) {
    const std::size_t s = vertex_keyframe_[static_cast<std::size_t>(v)].slot();
    return pre_loop_stamp_[s] == stamp_ ? geometry::Sim3(pre_loop_[s]) : vertex_initial_[static_cast<std::size_t>(v)];
  };
  edges_.clear();
  auto add_edge = [&](int i, int j, const geometry::Sim3& S_ij) {
    optim::PoseGraphEdge<geometry::Sim3> e;
    e.i = i;
    e.j = j;
    e.T_ij = S_ij;
    edges_.push_back(e);
  };
  // the new loop links: what fusion joined that was not joined before
  for (map::KeyframeId c : connected_) {
    const int i = vertex(c);
    if (i < 0) continue;
    const std::vector<map::KeyframeId>& old = neighbours_before_[c.slot()];
    for (const map::Covisible& n : map.covisible_of(c)) {
      if (connected_stamp_[n.keyframe.slot()] == stamp_ && map.keyframe(n.keyframe)) continue;
      if (std::binary_search(old.begin(), old.end(), n.keyframe)) continue;
      const int j = vertex(n.keyframe);
      if (j < 0) continue;
      add_edge(i, j, vertex_initial_[static_cast<std::size_t>(i)] * vertex_initial_[static_cast<std::size_t>(j)].inverse());
    }
  }
  // the spanning tree, the loop edges and the strong covisibility links, as measured before
  for (int i = 0; i < static_cast<int>(vertex_keyframe_.size()); ++i) {
    const map::KeyframeId id = vertex_keyframe_[static_cast<std::size_t>(i)];
    const map::Keyframe& k = *map.keyframe(id);
    const geometry::Sim3 S_i = before(i);
    const int p = vertex(k.parent);
    if (p >= 0) add_edge(i, p, S_i * before(p).inverse());
    for (map::KeyframeId other : map.loop_edges(id)) {
      const int j = vertex(other);
      if (j >= 0 && j < i) add_edge(i, j, S_i * before(j).inverse());
    }
    for (const map::Covisible& n : map.covisible_of(id)) {
      if (n.weight < params_.strong_covisibility) break;
      const int j = vertex(n.keyframe);
      if (j < 0 || j >= i || j == p) continue;
      if (map.keyframe(n.keyframe)->parent == id) continue;
      add_edge(i, j, S_i * before(j).inverse());
    }
  }
  report.graph_keyframes = static_cast<int>(vertex_keyframe_.size());
  report.graph_edges = static_cast<int>(edges_.size());
  graph_poses_ = vertex_initial_;
  const int fixed = vertex(loop);
  optim::LmOptions options;
  options.max_iterations = params_.pose_graph_iterations;
  const std::vector<int> fixed_vertices{fixed};
  const Result<optim::PoseGraphSummary> summary = graph_.optimize(edges_, fixed_vertices, options, &graph_poses_);
  if (!summary.ok() && summary.status().code() != StatusCode::kNotConverged) {
    // the local correction alone stands
    graph_poses_ = vertex_initial_;
    report.message = "essential graph: " + summary.status().message();
  }

  // keyframes and landmarks follow
  for (std::size_t v = 0; v < vertex_keyframe_.size(); ++v) {
    const map::KeyframeId id = vertex_keyframe_[v];
    map.keyframe(id)->T_cw = rigid(graph_poses_[v]);
    factor_[id.slot()] = vertex_initial_[v].scale() / graph_poses_[v].scale();
  }
  map.for_each_landmark([&](map::LandmarkId id, const map::Landmark& lm) {
    if (lm.map_id != current) return;
    int v = -1;
    if (landmark_stamp_[id.slot()] == stamp_) v = vertex(landmark_keyframe_[id.slot()]);
    if (v < 0) v = vertex(lm.reference);
    if (v < 0) v = vertex(lm.first);
    if (v < 0 && lm.num_observations > 0) v = vertex(lm.observations[0].keyframe);
    if (v < 0) return;
    map::Landmark* m = map.landmark(id);
    m->p_w = graph_poses_[static_cast<std::size_t>(v)].inverse() * (vertex_initial_[static_cast<std::size_t>(v)] * m->p_w);
  });
  map.for_each_landmark([&](map::LandmarkId id, const map::Landmark& lm) {
    if (lm.map_id == current) map.update_normal_and_depth(id, pyramid_.scale, pyramid_.levels);
  });
}

// The frames after: a bundle adjustment of the whole map, a few iterations a frame (each a solve
// from where the last left the map), the loop's old keyframe fixed.
void LoopCloser::global_bundle_adjustment(map::MapStore& map, LoopReport& report) {
  const int iterations = std::min(global_ba_left_, params_.global_ba_iterations_per_frame);
  global_ba_left_ -= iterations;
  if (global_ba_left_ <= 0) stage_ = Stage::kIdle;
  if (!map.keyframe(loop_)) return;
  ba_.reset(map);
  const map::MapId current = map.current_map();
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    if (k.map_id == current) ba_.add_keyframe(id, id == loop_);
  });
  map.for_each_landmark([&](map::LandmarkId id, const map::Landmark& lm) {
    if (lm.map_id == current) ba_.add_landmark(id);
  });
  optim::BaOptions options;
  options.lm.max_iterations = iterations;
  if (!MapBundleAdjustment::usable(ba_.solve(options))) return;
  ba_.write_back(map);
  report.global_ba_iterations = iterations;
}

namespace {
constexpr ConfigField kLoopFields[] = {
    flag<&LoopCloserParams::enabled>("enabled", "loop closing: recognised places correct the map's drift"),
    number<&LoopCloserParams::min_keyframes>("min_keyframes", 0, 100000, "keyframes in the map before loops are looked for"),
    number<&LoopCloserParams::keyframes_between>("keyframes_between", 0, 100000, "keyframes after a loop before the next"),
    number<&LoopCloserParams::consistency>("consistency", 1, 100, "consecutive keyframes that must see the place"),
    number<&LoopCloserParams::min_bow_matches>("min_bow_matches", 3, 100000, "feature matches to a candidate"),
    number<&LoopCloserParams::min_sim3_inliers>("min_sim3_inliers", 3, 100000, "inliers of the similarity"),
    number<&LoopCloserParams::min_inliers>("min_inliers", 3, 100000, "inliers of the keyframe's pose in the loop's place"),
    number<&LoopCloserParams::sim3_gate_depths>("sim3_gate_depths", 1e-4, 10,
                                                "similarity RANSAC's 3-D gate, share of the median depth"),
    number<&LoopCloserParams::max_correction_ratio>("max_correction_ratio", 0, 100,
                                                    "a loop may move the keyframe this share of the path since"),
    number<&LoopCloserParams::max_correction_floor_depths>("max_correction_floor_depths", 0, 1000,
                                                           "... plus this many median depths"),
    number<&LoopCloserParams::strong_covisibility>("strong_covisibility", 1, 100000,
                                                   "essential graph: covisibility links of this weight"),
    number<&LoopCloserParams::pose_graph_iterations>("pose_graph_iterations", 1, 1000, "essential graph's iterations"),
    number<&LoopCloserParams::global_ba_iterations>("global_ba_iterations", 0, 1000,
                                                    "whole-map bundle adjustment after a loop, iterations (0: none)"),
    number<&LoopCloserParams::global_ba_iterations_per_frame>("global_ba_iterations_per_frame", 1, 1000,
                                                              "... at most this many on one frame"),
    flag<&LoopCloserParams::merge>("merge", "keep a map when tracking is lost and merge it when its places come back"),
    number<&LoopCloserParams::max_maps>("max_maps", 1, 8, "maps held for merging, the current one included"),
    number<&LoopCloserParams::welding_ba_iterations>("welding_ba_iterations", 0, 1000,
                                                     "bundle adjustment around a merge's seam, iterations"),
};
}  // namespace

extern constexpr ConfigTable kLoopCloserConfig = table_of<LoopCloserParams>(kLoopFields);

}  // namespace ale::slam
