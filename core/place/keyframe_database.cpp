#include "core/place/keyframe_database.h"

#include <algorithm>
#include <string>

namespace ale::place {

KeyframeDatabase::KeyframeDatabase(const Vocabulary& vocabulary, const map::MapCapacity& capacity,
                                   const KeyframeDatabaseParams& params)
    : vocabulary_(vocabulary), params_(params) {
  const std::size_t keyframes = static_cast<std::size_t>(std::max(0, capacity.max_keyframes));
  max_features_ = std::max(0, capacity.max_keypoints_per_keyframe);
  entries_.resize(keyframes);
  for (Entry& e : entries_) {
    e.bow.reserve(static_cast<std::size_t>(max_features_));
    e.fv.reserve(static_cast<std::size_t>(max_features_));
  }
  word_head_.assign(static_cast<std::size_t>(vocabulary.num_words()), kNone);
  // A keyframe has at most one posting per feature (a bag of words holds each word once).
  postings_.resize(keyframes * static_cast<std::size_t>(max_features_));
  for (std::size_t i = 0; i < postings_.size(); ++i)
    postings_[i].next = i + 1 < postings_.size() ? static_cast<std::uint32_t>(i + 1) : kNone;
  free_posting_ = postings_.empty() ? kNone : 0;
  descriptors_.reserve(static_cast<std::size_t>(max_features_));
  query_.resize(keyframes);
  touched_.reserve(keyframes);
  scored_.reserve(keyframes);
  groups_.reserve(keyframes);
  candidates_.reserve(keyframes);
}

Status KeyframeDatabase::add(map::KeyframeId id, const features::Descriptor* d, int n) {
  if (!id.valid() || id.slot() >= entries_.size())
    return invalid_argument("keyframe database: keyframe slot " + std::to_string(id.slot()) + " beyond its capacity of " +
                            std::to_string(entries_.size()));
  if (n < 0 || n > max_features_ || (n > 0 && d == nullptr))
    return invalid_argument("keyframe database: " + std::to_string(n) + " descriptors (0.." + std::to_string(max_features_) + ")");
  if (entries_[id.slot()].id.valid()) erase_slot(id.slot());
  Entry& e = entries_[id.slot()];
  vocabulary_.transform(d, n, e.bow, e.fv, params_.fv_levels_up);
  for (const BowEntry& b : e.bow) {
    // cannot run out: the pool holds max_features_ postings for every slot
    const std::uint32_t p = free_posting_;
    free_posting_ = postings_[p].next;
    postings_[p] = Posting{id.slot(), word_head_[b.word]};
    word_head_[b.word] = p;
  }
  e.id = id;
  ++size_;
  return {};
}

void KeyframeDatabase::erase_slot(std::uint32_t slot) {
  Entry& e = entries_[slot];
  for (const BowEntry& b : e.bow) {
    std::uint32_t* link = &word_head_[b.word];
    while (*link != kNone && postings_[*link].slot != slot) link = &postings_[*link].next;
    if (*link == kNone) continue;  // not reached: every word of the bag has its posting
    const std::uint32_t p = *link;
    *link = postings_[p].next;
    postings_[p].next = free_posting_;
    free_posting_ = p;
  }
  e.bow.clear();
  e.fv.clear();
  e.id = map::KeyframeId{};
  --size_;
}

void KeyframeDatabase::erase(map::KeyframeId id) {
  if (contains(id)) erase_slot(id.slot());
}

void KeyframeDatabase::clear() {
  for (std::uint32_t s = 0; s < entries_.size(); ++s) {
    if (entries_[s].id.valid()) erase_slot(s);
  }
}

bool KeyframeDatabase::contains(map::KeyframeId id) const {
  return id.valid() && id.slot() < entries_.size() && entries_[id.slot()].id == id;
}

const BowVector* KeyframeDatabase::bow(map::KeyframeId id) const {
  return contains(id) ? &entries_[id.slot()].bow : nullptr;
}

const FeatureVector* KeyframeDatabase::feature_vector(map::KeyframeId id) const {
  return contains(id) ? &entries_[id.slot()].fv : nullptr;
}

Status KeyframeDatabase::add_from_map(const map::MapStore& map, map::KeyframeId id) {
  const Span<const map::KeyframeFeature> f = map.features_of(id);
  descriptors_.clear();
  for (const map::KeyframeFeature& k : f) descriptors_.push_back(k.descriptor);
  return add(id, descriptors_.data(), static_cast<int>(descriptors_.size()));
}

std::uint64_t KeyframeDatabase::sync(const map::MapStore& map) {
  const std::uint64_t lost = map.keyframe_events().read(cursor_, [&](const map::KeyframeEvent& e) {
    switch (e.kind) {
      case map::MapEventKind::kKeyframeErased:
        erase(e.keyframe.id);
        break;
      case map::MapEventKind::kMapReset:
        clear();
        break;
      case map::MapEventKind::kKeyframeAdded:
        // the map may have erased it again since (its erase event follows)
        if (!contains(e.keyframe.id) && map.keyframe(e.keyframe.id) != nullptr) (void)add_from_map(map, e.keyframe.id);
        break;
      default:
        break;
    }
  });
  if (lost > 0) reconcile(map);
  return lost;
}

void KeyframeDatabase::reconcile(const map::MapStore& map) {
  for (std::uint32_t s = 0; s < entries_.size(); ++s) {
    const map::Keyframe* kf = entries_[s].id.valid() ? map.keyframe(entries_[s].id) : nullptr;
    if (entries_[s].id.valid() && kf == nullptr) erase_slot(s);
  }
  map.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe&) {
    if (!contains(id)) (void)add_from_map(map, id);
  });
}

void KeyframeDatabase::begin_query() const {
  if (++stamp_ == 0) {  // wrapped: forget every stamp
    for (QueryState& q : query_) q = QueryState{};
    stamp_ = 1;
  }
}

void KeyframeDatabase::relocalisation_candidates(const BowVector& query, const map::MapStore& map,
                                                 std::vector<PlaceCandidate>& out) const {
  begin_query();
  candidates(query, map, 0.0f, false, out);
}

void KeyframeDatabase::loop_candidates(map::KeyframeId kf, const map::MapStore& map, float min_score,
                                       std::vector<PlaceCandidate>& out) const {
  out.clear();
  const BowVector* query = bow(kf);
  if (query == nullptr) return;
  begin_query();
  query_[kf.slot()].excluded_stamp = stamp_;
  for (const map::Covisible& c : map.covisible_of(kf)) {
    if (c.keyframe.slot() < query_.size()) query_[c.keyframe.slot()].excluded_stamp = stamp_;
  }
  candidates(*query, map, min_score, true, out);
}

void KeyframeDatabase::candidates(const BowVector& query, const map::MapStore& map, float min_score, bool any_map,
                                  std::vector<PlaceCandidate>& out) const {
  out.clear();
  touched_.clear();
  for (const BowEntry& b : query) {
    if (b.word >= word_head_.size()) continue;
    for (std::uint32_t p = word_head_[b.word]; p != kNone; p = postings_[p].next) {
      const std::uint32_t s = postings_[p].slot;
      QueryState& q = query_[s];
      if (q.stamp != stamp_) {
        q.stamp = stamp_;
        q.common = 0;
        q.scored = false;
        touched_.push_back(s);
      }
      ++q.common;
    }
  }
  if (touched_.empty()) return;
  int max_common = 0;
  for (std::uint32_t s : touched_) {
    if (query_[s].excluded_stamp != stamp_) max_common = std::max(max_common, query_[s].common);
  }
  const float min_common = params_.min_common_ratio * static_cast<float>(max_common);

  scored_.clear();
  for (std::uint32_t s : touched_) {
    QueryState& q = query_[s];
    if (static_cast<float>(q.common) < min_common || q.excluded_stamp == stamp_) continue;
    const map::Keyframe* kf = map.keyframe(entries_[s].id);
    if (kf == nullptr || (!any_map && kf->map_id != map.current_map())) continue;
    const float score = static_cast<float>(Vocabulary::score(query, entries_[s].bow));
    if (score < min_score) continue;
    q.scored = true;
    q.score = score;
    scored_.push_back(s);
  }

  groups_.clear();
  float best_group = 0.0f;
  for (std::uint32_t s : scored_) {
    const map::KeyframeId id = entries_[s].id;
    PlaceCandidate g{id, query_[s].score, query_[s].score, query_[s].common};
    for (const map::Covisible& c : map.covisible_of(id).first(params_.covisible_neighbours)) {
      const std::uint32_t ns = c.keyframe.slot();
      if (ns >= entries_.size() || entries_[ns].id != c.keyframe) continue;
      const QueryState& nq = query_[ns];
      if (nq.stamp != stamp_ || !nq.scored) continue;
      g.group_score += nq.score;
      if (nq.score > g.score || (nq.score == g.score && c.keyframe < g.keyframe)) {
        g.keyframe = c.keyframe;
        g.score = nq.score;
        g.common_words = nq.common;
      }
    }
    best_group = std::max(best_group, g.group_score);
    groups_.push_back(g);
  }
  std::sort(groups_.begin(), groups_.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.group_score != b.group_score ? a.group_score > b.group_score : a.keyframe < b.keyframe;
  });
  const float min_group = params_.min_group_ratio * best_group;
  for (const PlaceCandidate& g : groups_) {
    if (g.group_score < min_group) break;
    QueryState& q = query_[g.keyframe.slot()];
    if (q.added_stamp == stamp_) continue;  // the best of another group already
    q.added_stamp = stamp_;
    out.push_back(g);
  }
}

void KeyframeDatabase::relocalisation_candidates(const BowVector& query, const map::MapStore& map,
                                                 std::vector<map::KeyframeId>& out) const {
  relocalisation_candidates(query, map, candidates_);
  out.clear();
  for (const PlaceCandidate& c : candidates_) out.push_back(c.keyframe);
}

std::size_t KeyframeDatabase::reserved_bytes() const {
  std::size_t bytes = entries_.capacity() * sizeof(Entry) + word_head_.capacity() * sizeof(std::uint32_t) +
                      postings_.capacity() * sizeof(Posting) + descriptors_.capacity() * sizeof(features::Descriptor) +
                      query_.capacity() * sizeof(QueryState) +
                      (touched_.capacity() + scored_.capacity()) * sizeof(std::uint32_t) +
                      (groups_.capacity() + candidates_.capacity()) * sizeof(PlaceCandidate);
  for (const Entry& e : entries_) bytes += e.bow.capacity() * sizeof(BowEntry) + e.fv.capacity() * sizeof(NodeFeature);
  return bytes;
}

}  // namespace ale::place
