// The keyframe database: each keyframe's bag of words and feature vector (computed once, when
// it is added) and an inverted index from each word to the keyframes that have it, for place
// recognition (relocalisation now, loop detection later). ORB-SLAM's KeyFrameDatabase, kept in
// memory reserved at construction (one entry per map keyframe slot, a pool of postings), told of
// erased keyframes through the map store's keyframe event log (sync) instead of by the code
// that erases them.
//
// One thread owns it (the SLAM thread that owns the map); queries use scratch held here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/features/brief.h"
#include "core/map/map_store.h"
#include "core/place/vocabulary.h"

namespace ale::place {

// A relocalisation candidate: the best keyframe of a group of covisible keyframes that look like
// the query.
struct PlaceCandidate {
  map::KeyframeId keyframe;
  float score = 0.0f;        // its own BoW score against the query (Vocabulary::score)
  float group_score = 0.0f;  // the summed score of it and its scored covisible neighbours
  int common_words = 0;      // words it shares with the query
};

struct KeyframeDatabaseParams {
  int fv_levels_up = 2;             // the feature vectors' node level, counted up from the leaves
  float min_common_ratio = 0.8f;    // candidates share >= this x the most words any keyframe shares
  float min_group_ratio = 0.75f;    // groups kept with >= this x the best group score
  int covisible_neighbours = 10;    // neighbours whose scores a candidate's group adds
};

class KeyframeDatabase {
 public:
  // Holds up to capacity.max_keyframes keyframes of capacity.max_keypoints_per_keyframe features
  // (the map's capacity). `vocabulary` must outlive the database.
  KeyframeDatabase(const Vocabulary& vocabulary, const map::MapCapacity& capacity,
                   const KeyframeDatabaseParams& params = {});
  KeyframeDatabase(const KeyframeDatabase&) = delete;
  KeyframeDatabase& operator=(const KeyframeDatabase&) = delete;

  // Computes the keyframe's bag of words and feature vector from its n descriptors and indexes
  // it (replacing what the database held for that id or for a stale id of the same slot).
  // kInvalidArgument for an invalid id, a slot beyond the capacity or n out of range.
  // Allocates nothing.
  Status add(map::KeyframeId id, const features::Descriptor* d, int n);
  // Forgets the keyframe (no-op when it is not held).
  void erase(map::KeyframeId id);
  // Reads the map's keyframe events since the last sync: erased keyframes are forgotten, a reset
  // map forgets everything, and added keyframes not yet held are added from the map's features.
  // When events were lost (more than the log holds between two syncs), the database is reconciled
  // with the map instead (every held keyframe checked, every missing one added). Returns how many
  // events were lost.
  std::uint64_t sync(const map::MapStore& map);
  void clear();

  bool contains(map::KeyframeId id) const;
  int size() const { return size_; }
  // nullptr when the keyframe is not held.
  const BowVector* bow(map::KeyframeId id) const;
  const FeatureVector* feature_vector(map::KeyframeId id) const;
  const Vocabulary& vocabulary() const { return vocabulary_; }
  const KeyframeDatabaseParams& params() const { return params_; }

  // ORB-SLAM's DetectRelocalizationCandidates: the keyframes of the map's current map that
  // share words with the query; those sharing >= min_common_ratio x the most shared words are
  // scored; each one's group score adds the scores of its scored covisible neighbours (the
  // strongest covisible_neighbours of them), and each group with >= min_group_ratio x the best
  // group score contributes its best-scoring keyframe. `out` is replaced: group score
  // descending, ties by keyframe id; empty when nothing shares a word. Keyframes the map no
  // longer has (erased but not yet synced) are skipped. Allocates nothing.
  void relocalisation_candidates(const BowVector& query, const map::MapStore& map,
                                 std::vector<PlaceCandidate>& out) const;
  // The same, the keyframe ids only.
  void relocalisation_candidates(const BowVector& query, const map::MapStore& map,
                                 std::vector<map::KeyframeId>& out) const;
  // ORB-SLAM's DetectLoopCandidates: the candidates of the keyframe's own bag of words as above,
  // leaving out the keyframe and its covisible neighbours (the place it is already joined to) and
  // every keyframe scoring below min_score (the caller's: the keyframe's lowest score against its
  // neighbours). Unlike relocalisation, the candidates come from every map the store holds: a
  // place of an older map is a merge (core/slam/loop_closer.h). Empty when the keyframe is not
  // held. Allocates nothing.
  void loop_candidates(map::KeyframeId kf, const map::MapStore& map, float min_score,
                       std::vector<PlaceCandidate>& out) const;

  // Memory reserved at construction (the entries, the postings pool, the query scratch).
  std::size_t reserved_bytes() const;

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  struct Entry {
    map::KeyframeId id;  // invalid: the slot is free
    BowVector bow;
    FeatureVector fv;
  };
  struct Posting {
    std::uint32_t slot = 0;
    std::uint32_t next = kNone;
  };
  struct QueryState {
    std::uint32_t stamp = 0;  // the query that last touched the slot
    int common = 0;
    bool scored = false;
    float score = 0.0f;
    std::uint32_t added_stamp = 0;
    std::uint32_t excluded_stamp = 0;
  };
  void erase_slot(std::uint32_t slot);
  // The query of both candidate lists: keyframes whose slot has excluded_stamp == stamp_ (set by
  // the caller after begin_query) are left out, and so are scores below min_score.
  void begin_query() const;
  void candidates(const BowVector& query, const map::MapStore& map, float min_score, bool any_map,
                  std::vector<PlaceCandidate>& out) const;
  void reconcile(const map::MapStore& map);
  Status add_from_map(const map::MapStore& map, map::KeyframeId id);

  const Vocabulary& vocabulary_;
  KeyframeDatabaseParams params_;
  int max_features_ = 0;
  int size_ = 0;
  std::vector<Entry> entries_;           // by keyframe slot
  std::vector<std::uint32_t> word_head_;  // first posting of each word
  std::vector<Posting> postings_;
  std::uint32_t free_posting_ = kNone;
  map::EventCursor cursor_;
  std::vector<features::Descriptor> descriptors_;  // add_from_map's gathered descriptors

  // query scratch
  mutable std::vector<QueryState> query_;
  mutable std::vector<std::uint32_t> touched_;
  mutable std::vector<std::uint32_t> scored_;
  mutable std::vector<PlaceCandidate> groups_;
  mutable std::vector<PlaceCandidate> candidates_;  // the id-only query's
  mutable std::uint32_t stamp_ = 0;
};

}  // namespace ale::place
