#include "core/map/map_store.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ale::map {

MapStore::MapStore(const MapCapacity& capacity)
    : capacity_(capacity),
      keyframes_("map keyframes", static_cast<std::size_t>(std::max(capacity.max_keyframes, 1))),
      landmarks_("map landmarks", static_cast<std::size_t>(std::max(capacity.max_landmarks, 1))) {
  capacity_.max_keyframes = static_cast<int>(keyframes_.capacity());
  capacity_.max_landmarks = static_cast<int>(landmarks_.capacity());
  capacity_.max_keypoints_per_keyframe = std::max(capacity_.max_keypoints_per_keyframe, 1);
  const std::size_t n = keyframes_.capacity() * static_cast<std::size_t>(capacity_.max_keypoints_per_keyframe);
  feature_arena_.resize(n);
  keypoint_landmark_arena_.resize(n);
  shared_counts_.assign(keyframes_.capacity(), 0);
  touched_slots_.reserve(keyframes_.capacity());
}

Result<KeyframeId> MapStore::add_keyframe(double timestamp_s, std::uint64_t frame_seq, const geometry::SE3& T_cw,
                                          const KeyframeFeature* features, int count) {
  if (count < 0 || count > capacity_.max_keypoints_per_keyframe) {
    return invalid_argument("map: a keyframe with " + std::to_string(count) + " keypoints, at most " +
                            std::to_string(capacity_.max_keypoints_per_keyframe) + " fit");
  }
  Keyframe kf;
  kf.timestamp_s = timestamp_s;
  kf.frame_seq = frame_seq;
  kf.T_cw = T_cw;
  kf.num_features = count;
  Result<KeyframeId> id = keyframes_.insert(kf);
  if (!id.ok()) return id.status();
  const std::size_t off = arena_offset(*id);
  std::copy(features, features + count, feature_arena_.begin() + static_cast<std::ptrdiff_t>(off));
  std::fill_n(keypoint_landmark_arena_.begin() + static_cast<std::ptrdiff_t>(off), count, LandmarkId{});
  if (!root_.valid()) root_ = *id;
  return id;
}

Result<LandmarkId> MapStore::add_landmark(const geometry::Vec3& p_w, const features::Descriptor& descriptor,
                                          KeyframeId first) {
  if (!p_w.allFinite()) return invalid_argument("map: a landmark with a non-finite position");
  Landmark lm;
  lm.p_w = p_w;
  lm.descriptor = descriptor;
  lm.first = first;
  lm.reference = first;
  return landmarks_.insert(lm);
}

Status MapStore::add_observation(LandmarkId lm_id, KeyframeId kf_id, int keypoint) {
  Landmark* lm = landmarks_.get(lm_id);
  Keyframe* kf = keyframes_.get(kf_id);
  if (!lm || !kf) return invalid_argument("map: observation of a stale landmark or keyframe id");
  if (keypoint < 0 || keypoint >= kf->num_features) {
    return invalid_argument("map: keypoint " + std::to_string(keypoint) + " out of range (keyframe has " +
                            std::to_string(kf->num_features) + ")");
  }
  LandmarkId& slot = keypoint_landmark_arena_[arena_offset(kf_id) + static_cast<std::size_t>(keypoint)];
  if (slot.valid()) return invalid_argument("map: keypoint " + std::to_string(keypoint) + " already has a landmark");
  for (int i = 0; i < lm->num_observations; ++i) {
    if (lm->observations[static_cast<std::size_t>(i)].keyframe == kf_id) {
      return invalid_argument("map: the landmark is already observed by this keyframe");
    }
  }
  if (lm->num_observations >= kMaxObservations) {
    ++refused_observations_;
    return out_of_memory("map: landmark has " + std::to_string(kMaxObservations) + " observations already");
  }
  lm->observations[static_cast<std::size_t>(lm->num_observations++)] = {kf_id, static_cast<std::uint32_t>(keypoint)};
  slot = lm_id;
  return Status::ok_status();
}

void MapStore::unlink_observation(Landmark& lm, KeyframeId kf, std::uint32_t keypoint) {
  for (int i = 0; i < lm.num_observations; ++i) {
    const Observation& o = lm.observations[static_cast<std::size_t>(i)];
    if (o.keyframe == kf && o.keypoint == keypoint) {
      // keep the order (the reference and descriptor choices depend on it)
      std::copy(lm.observations.begin() + i + 1, lm.observations.begin() + lm.num_observations,
                lm.observations.begin() + i);
      --lm.num_observations;
      break;
    }
  }
  if (lm.reference == kf) {
    lm.reference = lm.num_observations > 0 ? lm.observations[0].keyframe : KeyframeId{};
  }
}

void MapStore::erase_observation(KeyframeId kf_id, int keypoint) {
  const Keyframe* kf = keyframes_.get(kf_id);
  if (!kf || keypoint < 0 || keypoint >= kf->num_features) return;
  LandmarkId& slot = keypoint_landmark_arena_[arena_offset(kf_id) + static_cast<std::size_t>(keypoint)];
  if (Landmark* lm = landmarks_.get(slot)) unlink_observation(*lm, kf_id, static_cast<std::uint32_t>(keypoint));
  slot = LandmarkId{};
}

void MapStore::erase_landmark(LandmarkId lm_id) {
  Landmark* lm = landmarks_.get(lm_id);
  if (!lm) return;
  for (int i = 0; i < lm->num_observations; ++i) {
    const Observation& o = lm->observations[static_cast<std::size_t>(i)];
    if (keyframes_.contains(o.keyframe)) {
      keypoint_landmark_arena_[arena_offset(o.keyframe) + o.keypoint] = LandmarkId{};
    }
  }
  landmarks_.erase(lm_id);
}

void MapStore::replace_landmark(LandmarkId from_id, LandmarkId into_id) {
  if (from_id == into_id) return;
  Landmark* from = landmarks_.get(from_id);
  Landmark* into = landmarks_.get(into_id);
  if (!from || !into) return;
  for (int i = 0; i < from->num_observations; ++i) {
    const Observation o = from->observations[static_cast<std::size_t>(i)];
    LandmarkId& slot = keypoint_landmark_arena_[arena_offset(o.keyframe) + o.keypoint];
    slot = LandmarkId{};
    // a keyframe seeing both keeps its observation of `into`; otherwise it moves
    if (!add_observation(into_id, o.keyframe, static_cast<int>(o.keypoint)).ok()) continue;
  }
  into->visible += from->visible;
  into->found += from->found;
  landmarks_.erase(from_id);
}

void MapStore::remove_covisible(Keyframe& kf, KeyframeId other) {
  for (int i = 0; i < kf.num_covisible; ++i) {
    if (kf.covisible[static_cast<std::size_t>(i)].keyframe == other) {
      std::copy(kf.covisible.begin() + i + 1, kf.covisible.begin() + kf.num_covisible, kf.covisible.begin() + i);
      --kf.num_covisible;
      return;
    }
  }
}

namespace {
bool stronger(const Covisible& a, const Covisible& b) {
  return a.weight != b.weight ? a.weight > b.weight : a.keyframe < b.keyframe;
}
}  // namespace

void MapStore::set_covisible(Keyframe& kf, KeyframeId other, int weight) {
  remove_covisible(kf, other);
  if (weight <= 0) return;
  const Covisible c{other, weight};
  auto begin = kf.covisible.begin();
  auto end = begin + kf.num_covisible;
  auto pos = std::lower_bound(begin, end, c, stronger);
  if (kf.num_covisible == kMaxCovisible) {
    if (pos == end) return;  // weaker than every kept link
    --kf.num_covisible;      // drop the weakest
    end = begin + kf.num_covisible;
  }
  std::copy_backward(pos, end, end + 1);
  *pos = c;
  ++kf.num_covisible;
}

void MapStore::update_connections(KeyframeId kf_id, int min_weight) {
  Keyframe* kf = keyframes_.get(kf_id);
  if (!kf) return;
  touched_slots_.clear();
  const std::size_t off = arena_offset(kf_id);
  for (int k = 0; k < kf->num_features; ++k) {
    const Landmark* lm = landmarks_.get(keypoint_landmark_arena_[off + static_cast<std::size_t>(k)]);
    if (!lm) continue;
    for (int i = 0; i < lm->num_observations; ++i) {
      const KeyframeId other = lm->observations[static_cast<std::size_t>(i)].keyframe;
      if (other == kf_id || !keyframes_.contains(other)) continue;
      if (shared_counts_[other.slot()]++ == 0) touched_slots_.push_back(other.slot());
    }
  }
  // deterministic order whatever the landmarks' order
  std::sort(touched_slots_.begin(), touched_slots_.end());
  // Old links that no longer share anything are dropped on both sides.
  for (int i = kf->num_covisible - 1; i >= 0; --i) {
    const KeyframeId other = kf->covisible[static_cast<std::size_t>(i)].keyframe;
    if (!keyframes_.contains(other) || shared_counts_[other.slot()] == 0) {
      if (Keyframe* o = keyframes_.get(other)) remove_covisible(*o, kf_id);
      remove_covisible(*kf, other);
    }
  }
  KeyframeId best;
  int best_weight = 0;
  bool any_linked = false;
  for (std::uint32_t s : touched_slots_) {
    const int w = shared_counts_[s];
    const KeyframeId other = keyframes_.id_at_slot(s);
    if (w > best_weight) {
      best_weight = w;
      best = other;
    }
    if (w >= min_weight) {
      any_linked = true;
      set_covisible(*kf, other, w);
      set_covisible(*keyframes_.get(other), kf_id, w);
    } else {
      remove_covisible(*kf, other);
      remove_covisible(*keyframes_.get(other), kf_id);
    }
  }
  if (!any_linked && best.valid()) {
    set_covisible(*kf, best, best_weight);
    set_covisible(*keyframes_.get(best), kf_id, best_weight);
  }
  for (std::uint32_t s : touched_slots_) shared_counts_[s] = 0;
  if (!kf->parent.valid() && kf_id != root_ && best.valid()) kf->parent = best;
}

void MapStore::erase_keyframe(KeyframeId kf_id) {
  Keyframe* kf = keyframes_.get(kf_id);
  if (!kf) return;
  const std::size_t off = arena_offset(kf_id);
  for (int k = 0; k < kf->num_features; ++k) {
    LandmarkId& slot = keypoint_landmark_arena_[off + static_cast<std::size_t>(k)];
    if (Landmark* lm = landmarks_.get(slot)) unlink_observation(*lm, kf_id, static_cast<std::uint32_t>(k));
    slot = LandmarkId{};
  }
  std::vector<KeyframeId> neighbours;
  neighbours.reserve(static_cast<std::size_t>(kf->num_covisible));
  for (int i = 0; i < kf->num_covisible; ++i) neighbours.push_back(kf->covisible[static_cast<std::size_t>(i)].keyframe);
  std::vector<KeyframeId> children;
  children_of(kf_id, children);
  KeyframeId new_parent = kf->parent;
  if (kf_id == root_) {
    // the child sharing most with the old root becomes the root
    new_parent = KeyframeId{};
    int best = -1;
    for (KeyframeId c : children) {
      int w = 0;
      for (int i = 0; i < kf->num_covisible; ++i) {
        if (kf->covisible[static_cast<std::size_t>(i)].keyframe == c) w = kf->covisible[static_cast<std::size_t>(i)].weight;
      }
      if (w > best) {
        best = w;
        new_parent = c;
      }
    }
    root_ = new_parent;
    if (Keyframe* r = keyframes_.get(root_)) r->parent = KeyframeId{};
  }
  for (KeyframeId c : children) {
    if (c == new_parent) continue;
    if (Keyframe* ck = keyframes_.get(c)) ck->parent = new_parent;
  }
  ErasedKeyframe gone{kf_id, KeyframeId{}, geometry::SE3{}};
  if (const Keyframe* p = keyframes_.get(new_parent)) {
    gone.parent = new_parent;
    gone.T_cp = kf->T_cw * p->T_cw.inverse();
  }
  erased_.push_back(gone);
  keyframes_.erase(kf_id);
  for (KeyframeId n : neighbours) {
    if (Keyframe* nk = keyframes_.get(n)) remove_covisible(*nk, kf_id);
    update_connections(n);
  }
  if (keyframes_.size() == 0) root_ = KeyframeId{};
}

const KeyframeFeature* MapStore::features(KeyframeId kf) const {
  return keyframes_.contains(kf) ? feature_arena_.data() + arena_offset(kf) : nullptr;
}

const LandmarkId* MapStore::keypoint_landmarks(KeyframeId kf) const {
  return keyframes_.contains(kf) ? keypoint_landmark_arena_.data() + arena_offset(kf) : nullptr;
}

void MapStore::landmarks_of(KeyframeId kf_id, std::vector<LandmarkId>& out) const {
  const Keyframe* kf = keyframes_.get(kf_id);
  if (!kf) return;
  const LandmarkId* ids = keypoint_landmarks(kf_id);
  for (int k = 0; k < kf->num_features; ++k) {
    if (landmarks_.contains(ids[k])) out.push_back(ids[k]);
  }
}

void MapStore::children_of(KeyframeId kf, std::vector<KeyframeId>& out) const {
  keyframes_.for_each([&](KeyframeId id, const Keyframe& k) {
    if (k.parent == kf) out.push_back(id);
  });
}

void MapStore::update_descriptor(LandmarkId lm_id) {
  Landmark* lm = landmarks_.get(lm_id);
  if (!lm || lm->num_observations == 0) return;
  std::array<const features::Descriptor*, kMaxObservations> d{};
  int n = 0;
  for (int i = 0; i < lm->num_observations; ++i) {
    const Observation& o = lm->observations[static_cast<std::size_t>(i)];
    const KeyframeFeature* f = features(o.keyframe);
    if (f) d[static_cast<std::size_t>(n++)] = &f[o.keypoint].descriptor;
  }
  if (n == 0) return;
  int best = 0;
  int best_median = 1 << 30;
  std::array<int, kMaxObservations> dist{};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) dist[static_cast<std::size_t>(j)] = features::hamming_distance(*d[static_cast<std::size_t>(i)], *d[static_cast<std::size_t>(j)]);
    std::sort(dist.begin(), dist.begin() + n);
    const int median = dist[static_cast<std::size_t>((n - 1) / 2)];
    if (median < best_median) {
      best_median = median;
      best = i;
    }
  }
  lm->descriptor = *d[static_cast<std::size_t>(best)];
}

void MapStore::update_normal_and_depth(LandmarkId lm_id, const float* level_scales, int num_levels) {
  Landmark* lm = landmarks_.get(lm_id);
  if (!lm || lm->num_observations == 0 || num_levels <= 0) return;
  geometry::Vec3 sum = geometry::Vec3::Zero();
  int n = 0;
  for (int i = 0; i < lm->num_observations; ++i) {
    const Keyframe* kf = keyframes_.get(lm->observations[static_cast<std::size_t>(i)].keyframe);
    if (!kf) continue;
    const geometry::Vec3 centre = kf->T_cw.inverse().translation();
    const geometry::Vec3 ray = lm->p_w - centre;
    const double norm = ray.norm();
    if (norm > 0.0) {
      sum += ray / norm;
      ++n;
    }
  }
  if (n > 0 && sum.norm() > 0.0) lm->normal = sum.normalized();
  const Keyframe* ref = keyframes_.get(lm->reference);
  if (!ref) return;
  std::uint32_t ref_kp = 0;
  for (int i = 0; i < lm->num_observations; ++i) {
    if (lm->observations[static_cast<std::size_t>(i)].keyframe == lm->reference) ref_kp = lm->observations[static_cast<std::size_t>(i)].keypoint;
  }
  const double dist = (lm->p_w - ref->T_cw.inverse().translation()).norm();
  const int level = std::clamp<int>(features(lm->reference)[ref_kp].level, 0, num_levels - 1);
  // ORB-SLAM's range: the point could be seen at this octave from dist / scale(level) * top
  // octave's scale down to dist / scale(level).
  lm->max_distance = static_cast<float>(dist * level_scales[level]);
  lm->min_distance = lm->max_distance / level_scales[num_levels - 1];
}

void MapStore::take_erased(std::vector<ErasedKeyframe>& out) {
  out.clear();
  out.swap(erased_);
}

void MapStore::reset() {
  erased_.clear();
  keyframes_.clear();
  landmarks_.clear();
  root_ = KeyframeId{};
  ++map_id_;
}

MapStats MapStore::stats() const {
  MapStats s;
  s.keyframes = keyframes_.size();
  s.landmarks = landmarks_.size();
  s.keyframe_capacity = keyframes_.capacity();
  s.landmark_capacity = landmarks_.capacity();
  s.keyframes_high_water = keyframes_.high_water();
  s.landmarks_high_water = landmarks_.high_water();
  s.reserved_bytes = keyframes_.capacity() * sizeof(Keyframe) + landmarks_.capacity() * sizeof(Landmark) +
                     feature_arena_.size() * (sizeof(KeyframeFeature) + sizeof(LandmarkId)) +
                     shared_counts_.size() * (sizeof(int) + sizeof(std::uint32_t));
  s.refused_observations = refused_observations_;
  s.map_id = map_id_;
  return s;
}

}  // namespace ale::map
