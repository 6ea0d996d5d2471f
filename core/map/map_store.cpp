#include "core/map/map_store.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ale::map {

MapStore::MapStore(const MapCapacity& capacity)
    : capacity_(capacity),
      keyframes_("map keyframes", static_cast<std::size_t>(std::max(capacity.max_keyframes, 1))),
      landmarks_("map landmarks", static_cast<std::size_t>(std::max(capacity.max_landmarks, 1))),
      keyframe_events_(2 * keyframes_.capacity() + 16),
      landmark_events_(landmarks_.capacity() +
                       2 * static_cast<std::size_t>(std::max(capacity.max_keypoints_per_keyframe, 1))) {
  capacity_.max_keyframes = static_cast<int>(keyframes_.capacity());
  capacity_.max_landmarks = static_cast<int>(landmarks_.capacity());
  capacity_.max_keypoints_per_keyframe = std::max(capacity_.max_keypoints_per_keyframe, 1);
  const std::size_t n = keyframes_.capacity() * static_cast<std::size_t>(capacity_.max_keypoints_per_keyframe);
  feature_arena_.resize(n);
  keypoint_landmark_arena_.resize(n);
  shared_counts_.assign(keyframes_.capacity(), 0);
  touched_slots_.reserve(keyframes_.capacity());
  erase_scratch_.reserve(keyframes_.capacity());
  maps_.reserve(8);
  maps_.push_back(MapInfo{current_, {}, 0, 0, false});
}

MapInfo* MapStore::info(MapId map) { return const_cast<MapInfo*>(map_info(map)); }

const MapInfo* MapStore::map_info(MapId map) const {
  for (const MapInfo& m : maps_) {
    if (m.id == map) return &m;
  }
  return nullptr;
}

KeyframeId MapStore::root_of(MapId map) const {
  const MapInfo* m = map_info(map);
  return m ? m->root : KeyframeId{};
}

void MapStore::set_metric(MapId map, bool metric) {
  if (MapInfo* m = info(map)) m->metric = metric;
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
  kf.map_id = current_map();
  Result<KeyframeId> id = keyframes_.insert(kf);
  if (!id.ok()) return id.status();
  keyframe_events_.push(KeyframeEvent{MapEventKind::kKeyframeAdded, kf.map_id, ErasedKeyframe{*id, {}, {}}});
  const std::size_t off = arena_offset(*id);
  std::copy(features, features + count, feature_arena_.begin() + static_cast<std::ptrdiff_t>(off));
  std::fill_n(keypoint_landmark_arena_.begin() + static_cast<std::ptrdiff_t>(off), count, LandmarkId{});
  MapInfo& m = *info(current_);
  ++m.keyframes;
  if (!m.root.valid()) m.root = *id;
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
  lm.map_id = current_map();
  Result<LandmarkId> id = landmarks_.insert(lm);
  if (id.ok()) {
    landmark_events_.push(LandmarkEvent{MapEventKind::kLandmarkAdded, lm.map_id, *id});
    ++info(current_)->landmarks;
  }
  return id;
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
  erase_landmark_object(lm_id, *lm);
}

void MapStore::erase_landmark_object(LandmarkId id, const Landmark& lm) {
  landmark_events_.push(LandmarkEvent{MapEventKind::kLandmarkErased, lm.map_id, id});
  if (MapInfo* m = info(lm.map_id)) --m->landmarks;
  landmarks_.erase(id);
}

namespace {
bool observed_by(const Landmark& lm, KeyframeId kf) {
  for (int i = 0; i < lm.num_observations; ++i) {
    if (lm.observations[static_cast<std::size_t>(i)].keyframe == kf) return true;
  }
  return false;
}
}  // namespace

Result<LandmarkReplacement> MapStore::replace_landmark(LandmarkId from_id, LandmarkId into_id, WhenFull when_full) {
  Landmark* from = landmarks_.get(from_id);
  Landmark* into = landmarks_.get(into_id);
  if (!from || !into || from_id == into_id) {
    return invalid_argument("map: replace_landmark with a stale landmark id or a landmark by itself");
  }
  LandmarkReplacement r;
  for (int i = 0; i < from->num_observations; ++i) {
    if (!observed_by(*into, from->observations[static_cast<std::size_t>(i)].keyframe)) ++r.moved;
  }
  if (into->num_observations + r.moved > kMaxObservations && when_full == WhenFull::kRefuse) {
    ++refused_replacements_;
    return out_of_memory("map: replace_landmark would give a landmark " +
                         std::to_string(into->num_observations + r.moved) + " observations, at most " +
                         std::to_string(kMaxObservations) + " fit");
  }
  r.moved = 0;
  for (int i = 0; i < from->num_observations; ++i) {
    const Observation o = from->observations[static_cast<std::size_t>(i)];
    LandmarkId& slot = keypoint_landmark_arena_[arena_offset(o.keyframe) + o.keypoint];
    slot = LandmarkId{};
    // a keyframe seeing both keeps its observation of `into`; otherwise it moves if it fits
    if (observed_by(*into, o.keyframe)) {
      ++r.merged;
    } else if (into->num_observations == kMaxObservations) {
      ++r.dropped;
      ++dropped_observations_;
    } else {
      into->observations[static_cast<std::size_t>(into->num_observations++)] = o;
      slot = into_id;
      ++r.moved;
    }
  }
  into->visible += from->visible;
  into->found += from->found;
  erase_landmark_object(from_id, *from);
  return r;
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
  if (!kf->parent.valid() && kf_id != root_of(kf->map_id) && best.valid()) set_parent(kf_id, *kf, best);
}

// Only a live parent lists its children; the field itself takes whatever it is given (a parent
// id that went stale reads as no parent, and update_connections leaves it, as it always has).
void MapStore::set_parent(KeyframeId child, Keyframe& c, KeyframeId parent) {
  if (Keyframe* old = keyframes_.get(c.parent)) {
    KeyframeId* link = &old->first_child;
    while (link->valid() && *link != child) link = &keyframes_.get(*link)->next_sibling;
    if (link->valid()) *link = c.next_sibling;
  }
  c.parent = parent;
  c.next_sibling = KeyframeId{};
  Keyframe* p = keyframes_.get(parent);
  if (!p) return;
  KeyframeId* link = &p->first_child;
  while (link->valid() && link->slot() < child.slot()) link = &keyframes_.get(*link)->next_sibling;
  c.next_sibling = *link;
  *link = child;
}

void MapStore::remove_loop_edge(Keyframe& kf, KeyframeId other) {
  auto end = kf.loop_edges.begin() + kf.num_loop_edges;
  auto it = std::find(kf.loop_edges.begin(), end, other);
  if (it == end) return;
  std::copy(it + 1, end, it);
  --kf.num_loop_edges;
}

Status MapStore::add_loop_edge(KeyframeId a_id, KeyframeId b_id) {
  Keyframe* a = keyframes_.get(a_id);
  Keyframe* b = keyframes_.get(b_id);
  if (!a || !b || a_id == b_id) return invalid_argument("map: a loop edge with a stale keyframe id or to itself");
  const Span<const KeyframeId> edges = loop_edges(a_id);
  if (std::find(edges.begin(), edges.end(), b_id) != edges.end()) return Status::ok_status();
  if (a->num_loop_edges >= kMaxLoopEdges || b->num_loop_edges >= kMaxLoopEdges) {
    return out_of_memory("map: a keyframe has " + std::to_string(kMaxLoopEdges) + " loop edges already");
  }
  a->loop_edges[static_cast<std::size_t>(a->num_loop_edges++)] = b_id;
  b->loop_edges[static_cast<std::size_t>(b->num_loop_edges++)] = a_id;
  return Status::ok_status();
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
  // copied: update_connections below rewrites the lists this one is on
  std::array<KeyframeId, kMaxCovisible> neighbours;
  const int num_neighbours = kf->num_covisible;
  for (int i = 0; i < num_neighbours; ++i) {
    neighbours[static_cast<std::size_t>(i)] = kf->covisible[static_cast<std::size_t>(i)].keyframe;
  }
  for (int i = 0; i < kf->num_loop_edges; ++i) {
    if (Keyframe* o = keyframes_.get(kf->loop_edges[static_cast<std::size_t>(i)])) remove_loop_edge(*o, kf_id);
  }
  KeyframeId new_parent = kf->parent;
  MapInfo* m = info(kf->map_id);
  if (m && kf_id == m->root) {
    // the child sharing most with the old root becomes the root (the first in slot order of equals)
    new_parent = KeyframeId{};
    int best = -1;
    for_each_child(kf_id, [&](KeyframeId c) {
      int w = 0;
      for (int i = 0; i < kf->num_covisible; ++i) {
        if (kf->covisible[static_cast<std::size_t>(i)].keyframe == c) w = kf->covisible[static_cast<std::size_t>(i)].weight;
      }
      if (w > best) {
        best = w;
        new_parent = c;
      }
    });
    m->root = new_parent;
    if (Keyframe* r = keyframes_.get(new_parent)) set_parent(new_parent, *r, KeyframeId{});
  }
  while (kf->first_child.valid()) {
    const KeyframeId c = kf->first_child;
    Keyframe& ck = *keyframes_.get(c);
    if (c == new_parent) {
      // a cycle (kf's parent is also its child): that child keeps kf as its parent, a stale id
      // from now on, as before the store kept children lists
      kf->first_child = ck.next_sibling;
      ck.next_sibling = KeyframeId{};
      continue;
    }
    set_parent(c, ck, new_parent);
  }
  set_parent(kf_id, *kf, KeyframeId{});
  ErasedKeyframe gone{kf_id, KeyframeId{}, geometry::SE3{}};
  if (const Keyframe* p = keyframes_.get(new_parent)) {
    gone.parent = new_parent;
    gone.T_cp = kf->T_cw * p->T_cw.inverse();
  }
  keyframe_events_.push(KeyframeEvent{MapEventKind::kKeyframeErased, kf->map_id, gone});
  keyframes_.erase(kf_id);
  if (m && --m->keyframes == 0) m->root = KeyframeId{};
  for (int i = 0; i < num_neighbours; ++i) {
    const KeyframeId n = neighbours[static_cast<std::size_t>(i)];
    if (Keyframe* nk = keyframes_.get(n)) remove_covisible(*nk, kf_id);
    update_connections(n);
  }
}

Span<const KeyframeFeature> MapStore::features_of(KeyframeId kf) const {
  const Keyframe* k = keyframes_.get(kf);
  return k ? Span<const KeyframeFeature>(feature_arena_.data() + arena_offset(kf), k->num_features)
           : Span<const KeyframeFeature>();
}

Span<const LandmarkId> MapStore::keypoint_landmarks_of(KeyframeId kf) const {
  const Keyframe* k = keyframes_.get(kf);
  return k ? Span<const LandmarkId>(keypoint_landmark_arena_.data() + arena_offset(kf), k->num_features)
           : Span<const LandmarkId>();
}

Span<const Observation> MapStore::observations_of(LandmarkId lm) const {
  const Landmark* l = landmarks_.get(lm);
  return l ? Span<const Observation>(l->observations.data(), l->num_observations) : Span<const Observation>();
}

Span<const Covisible> MapStore::covisible_of(KeyframeId kf) const {
  const Keyframe* k = keyframes_.get(kf);
  return k ? Span<const Covisible>(k->covisible.data(), k->num_covisible) : Span<const Covisible>();
}

Span<const KeyframeId> MapStore::loop_edges(KeyframeId kf) const {
  const Keyframe* k = keyframes_.get(kf);
  return k ? Span<const KeyframeId>(k->loop_edges.data(), k->num_loop_edges) : Span<const KeyframeId>();
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
  for_each_child(kf, [&](KeyframeId c) { out.push_back(c); });
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
  // the distances between the observations' descriptors, each pair measured once
  std::array<std::array<int, kMaxObservations>, kMaxObservations> pair{};
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int i = 0; i < n; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    pair[si][si] = 0;
    for (int j = i + 1; j < n; ++j) {
      const std::size_t sj = static_cast<std::size_t>(j);
      pair[si][sj] = pair[sj][si] = hamming(*d[si], *d[sj]);
    }
  }
  int best = 0;
  int best_median = 1 << 30;
  std::array<int, kMaxObservations> dist{};
  for (int i = 0; i < n; ++i) {
    std::copy_n(pair[static_cast<std::size_t>(i)].begin(), n, dist.begin());
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
  keyframe_events_.read(take_erased_cursor_, [&](const KeyframeEvent& e) {
    if (e.kind == MapEventKind::kKeyframeErased) out.push_back(e.keyframe);
    if (e.kind == MapEventKind::kMapReset) out.clear();  // reset() drops what was not taken
  });
}

void MapStore::reset() {
  keyframe_events_.push(KeyframeEvent{MapEventKind::kMapReset, current_map(), {}});
  landmark_events_.push(LandmarkEvent{MapEventKind::kMapReset, current_map(), {}});
  keyframes_.clear();
  landmarks_.clear();
  maps_.clear();
  start_map();
}

void MapStore::start_map() {
  current_ = MapId{++map_id_};
  maps_.push_back(MapInfo{current_, {}, 0, 0, false});
}

Status MapStore::merge_map(MapId from, MapId into, KeyframeId attach) {
  MapInfo* f = info(from);
  MapInfo* t = info(into);
  if (!f || !t || from == into) {
    return invalid_argument("map: merge of map " + std::to_string(from.value) + " into " + std::to_string(into.value) +
                            ": " + (from == into ? "the same map" : "a map the store does not hold"));
  }
  keyframes_.for_each([&](KeyframeId, Keyframe& k) {
    if (k.map_id == from) k.map_id = into;
  });
  landmarks_.for_each([&](LandmarkId, Landmark& l) {
    if (l.map_id == from) l.map_id = into;
  });
  const Keyframe* a = keyframes_.get(attach);
  if (Keyframe* r = keyframes_.get(f->root); r && a && a->map_id == into) set_parent(f->root, *r, attach);
  t->keyframes += f->keyframes;
  t->landmarks += f->landmarks;
  if (!t->root.valid()) t->root = f->root;
  if (current_ == from) current_ = into;
  maps_.erase(maps_.begin() + (f - maps_.data()));
  return {};
}

Status MapStore::erase_map(MapId map) {
  const MapInfo* m = info(map);
  if (!m || map == current_) {
    return invalid_argument("map: erase of map " + std::to_string(map.value) + ": " +
                            (m ? "the current map" : "a map the store does not hold"));
  }
  erase_scratch_.clear();
  keyframes_.for_each([&](KeyframeId id, const Keyframe& k) {
    if (k.map_id == map) erase_scratch_.push_back(id);
  });
  for (KeyframeId id : erase_scratch_) erase_keyframe(id);
  landmarks_.for_each([&](LandmarkId id, const Landmark& l) {
    if (l.map_id == map) erase_landmark_object(id, l);
  });
  maps_.erase(maps_.begin() + (info(map) - maps_.data()));
  return {};
}

MapStats MapStore::stats() const {
  MapStats s;
  s.keyframes = keyframes_.size();
  s.landmarks = landmarks_.size();
  s.maps = maps_.size();
  if (const MapInfo* m = map_info(current_)) {
    s.map_keyframes = m->keyframes;
    s.map_landmarks = m->landmarks;
  }
  s.keyframe_capacity = keyframes_.capacity();
  s.landmark_capacity = landmarks_.capacity();
  s.keyframes_high_water = keyframes_.high_water();
  s.landmarks_high_water = landmarks_.high_water();
  s.reserved_bytes = keyframes_.capacity() * sizeof(Keyframe) + landmarks_.capacity() * sizeof(Landmark) +
                     feature_arena_.size() * (sizeof(KeyframeFeature) + sizeof(LandmarkId)) +
                     shared_counts_.size() * (sizeof(int) + sizeof(std::uint32_t)) +
                     keyframe_events_.capacity() * sizeof(KeyframeEvent) +
                     landmark_events_.capacity() * sizeof(LandmarkEvent);
  s.refused_observations = refused_observations_;
  s.refused_replacements = refused_replacements_;
  s.dropped_observations = dropped_observations_;
  s.map_id = current_.value;
  return s;
}

void MapStore::rescale(double factor) {
  keyframes_.for_each([&](KeyframeId, Keyframe& k) {
    if (k.map_id == current_) k.T_cw = k.T_cw.scaled(factor);
  });
  landmarks_.for_each([&](LandmarkId, Landmark& l) {
    if (l.map_id != current_) return;
    l.p_w *= factor;
    l.min_distance = static_cast<float>(l.min_distance * factor);
    l.max_distance = static_cast<float>(l.max_distance * factor);
  });
}

void MapStore::move(const geometry::SE3& G) {
  const geometry::SE3 G_inv = G.inverse();
  keyframes_.for_each([&](KeyframeId, Keyframe& k) {
    if (k.map_id == current_) k.T_cw = k.T_cw * G_inv;
  });
  landmarks_.for_each([&](LandmarkId, Landmark& l) {
    if (l.map_id == current_) l.p_w = G * l.p_w;
  });
}

}  // namespace ale::map

namespace ale::map {

Status MapStore::restore_map_id(MapId map) {
  MapInfo& m = *info(current_);
  if (m.keyframes != 0 || m.landmarks != 0) return invalid_argument("map: restore_map_id on a map that is not empty");
  for (const MapInfo& held : maps_) {
    if (held.id != current_ && held.id == map) {
      return invalid_argument("map: map id " + std::to_string(map.value) + " is held already");
    }
  }
  current_ = map;
  m.id = map;
  map_id_ = std::max(map_id_, map.value);
  return {};
}

Status MapStore::restore_parent(KeyframeId kf, KeyframeId parent) {
  Keyframe* k = keyframes_.get(kf);
  if (!k) return invalid_argument("map: restore_parent of a stale keyframe id");
  MapInfo* m = info(k->map_id);
  if (!parent.valid()) {
    set_parent(kf, *k, KeyframeId{});
    m->root = kf;
    return {};
  }
  const Keyframe* p = keyframes_.get(parent);
  if (!p || p->map_id != k->map_id || parent == kf) {
    return invalid_argument("map: a keyframe's parent is stale, itself or in another map");
  }
  // walking up from the parent must not reach kf (a cycle); the walk is bounded by the count
  int steps = 0;
  for (KeyframeId a = parent; a.valid(); a = keyframes_.get(a)->parent) {
    if (a == kf || static_cast<std::size_t>(++steps) > keyframes_.capacity()) return invalid_argument("map: the spanning tree would have a cycle");
  }
  set_parent(kf, *k, parent);
  return {};
}

Status MapStore::restore_covisibility(KeyframeId kf, Span<const Covisible> links) {
  Keyframe* k = keyframes_.get(kf);
  if (!k) return invalid_argument("map: restore_covisibility of a stale keyframe id");
  if (links.size() > kMaxCovisible) return invalid_argument("map: more than kMaxCovisible covisible keyframes");
  for (int i = 0; i < links.size(); ++i) {
    const Covisible& c = links[i];
    const Keyframe* o = keyframes_.get(c.keyframe);
    if (!o || o->map_id != k->map_id || c.keyframe == kf || c.weight <= 0) {
      return invalid_argument("map: a covisible keyframe is stale, itself, in another map or of weight <= 0");
    }
    if (i > 0 && c.weight > links[i - 1].weight) return invalid_argument("map: covisibility not sorted by weight");
    for (int j = 0; j < i; ++j) {
      if (links[j].keyframe == c.keyframe) return invalid_argument("map: a covisible keyframe listed twice");
    }
  }
  std::copy(links.begin(), links.end(), k->covisible.begin());
  k->num_covisible = links.size();
  std::sort(k->covisible.begin(), k->covisible.begin() + k->num_covisible, stronger);
  return {};
}

}  // namespace ale::map
