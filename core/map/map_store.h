// The map store: the one owner of keyframes and landmarks (spec section 7). Everything else
// holds typed ids. Observations are kept both ways (a keyframe's keypoint -> its landmark, a
// landmark -> the keyframes and keypoints that see it); the covisibility graph (keyframes
// weighted by shared landmarks) and the spanning tree (each keyframe's parent) are derived from
// them and updated by update_connections(). Each keyframe also keeps its spanning-tree children
// (an intrusive list through the keyframes, so no allocation and no limit) and its loop edges.
//
// Consumers that keep their own view of the map (the refined trajectory, a keyframe database)
// read what changed from two event logs, each with its own cursor, instead of scanning: one of
// added and erased keyframes, one of added and erased landmarks (event_log.h).
//
// Keyframes and landmarks carry the MapId of the map they belong to. The store can hold several
// maps in the same pools (ORB-SLAM3's Atlas, trimmed): start_map() begins a new current map and
// keeps the others, merge_map() moves one map's objects into another (after the caller put them in
// its frame), erase_map() drops one; reset() drops them all. Each map has its own spanning tree
// (MapInfo::root). Tracking and mapping work in the current map: nothing links objects of two
// maps until they are merged. Ids are a slot and a generation, not stable across runs: DenseIndex
// (dense_index.h) numbers a map's objects 0..n-1 for a file.
//
// Memory is fixed at construction (MapCapacity): keyframes, landmarks and every keyframe's
// keypoints live in arenas reserved once; a full map refuses with kOutOfMemory, and the caller
// culls or resets. No shared_ptr graph, no locks (one thread owns the map), no algorithm
// scratch on map objects: matchers and optimisers keep their own.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/span.h"
#include "core/base/status.h"
#include "core/features/brief.h"
#include "core/geometry/lie.h"
#include "core/map/event_log.h"
#include "core/map/slot_map.h"

namespace ale::map {

using KeyframeId = Id<struct KeyframeTag>;
using LandmarkId = Id<struct LandmarkTag>;

// Which map a keyframe or landmark belongs to; MapStats::map_id is the current one's value.
struct MapId {
  std::uint32_t value = 0;
  friend bool operator==(MapId a, MapId b) { return a.value == b.value; }
  friend bool operator!=(MapId a, MapId b) { return a.value != b.value; }
  friend bool operator<(MapId a, MapId b) { return a.value < b.value; }
};

struct MapCapacity {
  int max_keyframes = 200;
  int max_landmarks = 20000;
  int max_keypoints_per_keyframe = 1000;  // at least the extractor's budget
};

// One keypoint of a keyframe: undistorted pixel position (the pinhole the solvers use), the
// octave and orientation (for search radii and the rotation-consistency check) and its
// descriptor.
struct KeyframeFeature {
  float u = 0.0f;
  float v = 0.0f;
  float angle_deg = 0.0f;
  std::int16_t level = 0;
  features::Descriptor descriptor;
};

struct Observation {
  KeyframeId keyframe;
  std::uint32_t keypoint = 0;
};

struct Covisible {
  KeyframeId keyframe;
  int weight = 0;  // landmarks both keyframes observe
};

// Keyframes keep their strongest covisibility links up to this many (ties by id).
constexpr int kMaxCovisible = 64;
// Landmarks keep up to this many observations; further ones are refused (counted).
constexpr int kMaxObservations = 24;
// Loop edges a keyframe can hold (a place is rarely closed more often); add_loop_edge refuses more.
constexpr int kMaxLoopEdges = 8;

// The spanning-tree and loop fields are the store's to write (callers read them).
struct Keyframe {
  double timestamp_s = 0.0;
  std::uint64_t frame_seq = 0;
  geometry::SE3 T_cw;
  int num_features = 0;
  MapId map_id;
  KeyframeId parent;  // spanning tree; invalid for the root (the map's first keyframe)
  // children of this keyframe in slot order: the first, then each child's next sibling
  KeyframeId first_child;
  KeyframeId next_sibling;
  std::array<Covisible, kMaxCovisible> covisible{};
  int num_covisible = 0;  // sorted by weight, descending
  std::array<KeyframeId, kMaxLoopEdges> loop_edges{};
  int num_loop_edges = 0;  // in the order they were added
  // The base's wheel-odometry pose (x, y metres, theta radians in the MCU's odometry frame) at
  // the keyframe's time, when the SLAM had one; the caller sets it after add_keyframe().
  bool has_odometry = false;
  double odometry_x_m = 0.0, odometry_y_m = 0.0, odometry_theta_rad = 0.0;
};

struct Landmark {
  geometry::Vec3 p_w = geometry::Vec3::Zero();
  features::Descriptor descriptor;     // the most representative of its observations
  geometry::Vec3 normal = geometry::Vec3::UnitZ();  // mean viewing direction (unit)
  float min_distance = 0.0f;  // scale-invariance range of the reference observation
  float max_distance = 0.0f;
  KeyframeId reference;        // keyframe whose observation sets the distances
  KeyframeId first;            // keyframe that created it
  std::array<Observation, kMaxObservations> observations{};
  int num_observations = 0;
  std::uint32_t visible = 1;   // frames in whose view it fell
  std::uint32_t found = 1;     // frames that matched it
  MapId map_id;                // last: it fills what would be padding
};

// A keyframe erase_keyframe() removed, with the spanning-tree parent that took its children and
// its pose relative to that parent then (invalid parent: it was the last keyframe).
struct ErasedKeyframe {
  KeyframeId id;
  KeyframeId parent;
  geometry::SE3 T_cp;
};

enum class MapEventKind : std::uint8_t {
  kKeyframeAdded,
  kKeyframeErased,
  kLandmarkAdded,
  kLandmarkErased,
  kMapReset,  // reset() emptied the map: every object of `map` is gone, without events of its own
};

struct KeyframeEvent {
  MapEventKind kind = MapEventKind::kKeyframeAdded;
  MapId map;
  ErasedKeyframe keyframe;  // the keyframe's id; for kKeyframeErased also its parent and T_cp
};

struct LandmarkEvent {
  MapEventKind kind = MapEventKind::kLandmarkAdded;
  MapId map;
  LandmarkId id;
};

// What replace_landmark() does when the surviving landmark cannot hold every observation that
// would move to it (kMaxObservations).
enum class WhenFull {
  kRefuse,        // change nothing, kOutOfMemory
  kDropOverflow,  // move what fits, in observation order; the rest are dropped (their keypoints
                  // are free again), counted in LandmarkReplacement::dropped and in the stats
};

// What replace_landmark() did with the observations of the landmark it erased.
struct LandmarkReplacement {
  int moved = 0;    // observations now of the surviving landmark
  int merged = 0;   // keyframes that saw both: they keep their observation of the survivor, and
                    // the keypoint that saw the erased one is free again
  int dropped = 0;  // WhenFull::kDropOverflow only: observations that did not fit
};

// A map the store holds: the root of its spanning tree (its first keyframe, or the one that took
// over when that was erased) and its counts. metric: its lengths are metres (the owner says so).
struct MapInfo {
  MapId id;
  KeyframeId root;
  std::size_t keyframes = 0;
  std::size_t landmarks = 0;
  bool metric = false;
};

struct MapStats {
  std::size_t keyframes = 0;   // of every map the store holds
  std::size_t landmarks = 0;
  std::size_t maps = 0;          // maps held (the current one included)
  std::size_t map_keyframes = 0;  // of the current map
  std::size_t map_landmarks = 0;
  std::size_t keyframe_capacity = 0;
  std::size_t landmark_capacity = 0;
  std::size_t keyframes_high_water = 0;
  std::size_t landmarks_high_water = 0;
  std::size_t reserved_bytes = 0;      // memory the store reserved at construction
  std::uint64_t refused_observations = 0;  // landmark full
  std::uint64_t refused_replacements = 0;  // replace_landmark() with too many observers together
  std::uint64_t dropped_observations = 0;  // by replace_landmark(..., WhenFull::kDropOverflow)
  std::uint32_t map_id = 0;  // the current map's: a new one from reset() and start_map()
};

class MapStore {
 public:
  explicit MapStore(const MapCapacity& capacity);
  MapStore(const MapStore&) = delete;
  MapStore& operator=(const MapStore&) = delete;

  // Adds a keyframe with its features (copied into the arena); kInvalidArgument when there
  // are more than max_keypoints_per_keyframe, kOutOfMemory when the map is full.
  Result<KeyframeId> add_keyframe(double timestamp_s, std::uint64_t frame_seq, const geometry::SE3& T_cw,
                                  const KeyframeFeature* features, int count);
  Result<LandmarkId> add_landmark(const geometry::Vec3& p_w, const features::Descriptor& descriptor,
                                  KeyframeId first);

  // Links a landmark and a keyframe's keypoint both ways. kInvalidArgument for a stale id, a
  // keypoint out of range or one that already has a landmark; kOutOfMemory when the landmark
  // has kMaxObservations already.
  Status add_observation(LandmarkId lm, KeyframeId kf, int keypoint);
  // Unlinks a keyframe's keypoint from its landmark (no-op when it has none).
  void erase_observation(KeyframeId kf, int keypoint);
  // Removes a landmark and every observation of it.
  void erase_landmark(LandmarkId lm);
  // Removes a keyframe and its observations and loop edges; its children are re-attached to its
  // parent (or, for the root, to the child with the most shared landmarks, which becomes the
  // root); the covisibility of its neighbours is recomputed. Allocates nothing.
  void erase_keyframe(KeyframeId kf);
  // The keyframes erased since the last call (by erase_keyframe, not reset), oldest first, into
  // `out` (replacing its contents): the keyframe event log read through the store's own cursor,
  // kept for callers written before the log; new consumers keep an EventCursor.
  void take_erased(std::vector<ErasedKeyframe>& out);
  // Landmark fusion: moves every observation of `from` to `into` and erases `from`. A keyframe
  // that sees both keeps its observation of `into` (counted as merged). When `into` cannot hold
  // the observations that would move, `when_full` decides: by default nothing changes and the
  // result is kOutOfMemory (counted in refused_replacements), so no observation is lost unless
  // the caller asks for it. kInvalidArgument for a stale or equal id.
  Result<LandmarkReplacement> replace_landmark(LandmarkId from, LandmarkId into, WhenFull when_full = WhenFull::kRefuse);

  // Records that a and b see the same place (both ways; adding an existing edge is a no-op).
  // kInvalidArgument for a stale id or a == b, kOutOfMemory when either has kMaxLoopEdges.
  Status add_loop_edge(KeyframeId a, KeyframeId b);

  // Recomputes kf's covisibility from its landmarks, updates the lists of the keyframes it
  // shares landmarks with, and gives kf a parent (its strongest neighbour) when it has none and
  // is not the root. Neighbours with fewer than min_weight shared landmarks are not linked
  // (ORB-SLAM uses 15), unless none reaches it, then the strongest one is.
  void update_connections(KeyframeId kf, int min_weight = 15);

  Keyframe* keyframe(KeyframeId id) { return keyframes_.get(id); }
  const Keyframe* keyframe(KeyframeId id) const { return keyframes_.get(id); }
  Landmark* landmark(LandmarkId id) { return landmarks_.get(id); }
  const Landmark* landmark(LandmarkId id) const { return landmarks_.get(id); }

  // Views of what a keyframe or landmark holds; empty for a stale id. They stay valid until the
  // object changes (the next call that adds, erases or relinks).
  // The keyframe's features (num_features of them) and the landmark of each (invalid where none).
  Span<const KeyframeFeature> features_of(KeyframeId kf) const;
  Span<const LandmarkId> keypoint_landmarks_of(KeyframeId kf) const;
  // The keyframes and keypoints that see the landmark, in the order they were added.
  Span<const Observation> observations_of(LandmarkId lm) const;
  // The keyframe's covisible neighbours, strongest first.
  Span<const Covisible> covisible_of(KeyframeId kf) const;
  // The keyframes kf shares a loop with, in the order the edges were added.
  Span<const KeyframeId> loop_edges(KeyframeId kf) const;

  // Pointer forms of features_of and keypoint_landmarks_of (nullptr for a stale id).
  const KeyframeFeature* features(KeyframeId kf) const;
  const LandmarkId* keypoint_landmarks(KeyframeId kf) const;
  // Landmarks the keyframe observes (in keypoint order), appended to out.
  void landmarks_of(KeyframeId kf, std::vector<LandmarkId>& out) const;
  // Children of kf in the spanning tree, in slot order, appended to out.
  void children_of(KeyframeId kf, std::vector<KeyframeId>& out) const;
  // Calls f(child id) for each child of kf in the spanning tree, in slot order.
  template <class F>
  void for_each_child(KeyframeId kf, F&& f) const {
    const Keyframe* k = keyframes_.get(kf);
    for (KeyframeId c = k ? k->first_child : KeyframeId{}; c.valid(); c = keyframes_.get(c)->next_sibling) f(c);
  }
  // The current map's spanning-tree root; root_of(): any map's (invalid for an empty or unknown map).
  KeyframeId root() const { return root_of(current_); }
  KeyframeId root_of(MapId map) const;

  // The landmark's descriptor becomes the observation descriptor with the least median Hamming
  // distance to the others (ORB-SLAM's distinctive descriptor).
  void update_descriptor(LandmarkId lm);
  // Mean viewing direction and the scale-invariance distance range from the reference
  // keyframe's observation: level_scales[l] = scale_factor^l, num_levels entries.
  void update_normal_and_depth(LandmarkId lm, const float* level_scales, int num_levels);

  template <class F>
  void for_each_keyframe(F&& f) const { keyframes_.for_each(f); }
  template <class F>
  void for_each_landmark(F&& f) const { landmarks_.for_each(f); }

  // What changed, for consumers with their own EventCursor. A consumer that reads the keyframe
  // log at least once between two keyframe insertions loses nothing (it holds every keyframe
  // the map can hold being added and erased); the landmark log holds every landmark the map can
  // hold being erased plus two keyframes' worth of new ones.
  const EventLog<KeyframeEvent>& keyframe_events() const { return keyframe_events_; }
  const EventLog<LandmarkEvent>& landmark_events() const { return landmark_events_; }

  // Multiplies every length of the current map by `factor` > 0 (keyframe positions, landmark
  // positions and their scale-invariance distances): the same map in another unit (metres from
  // odometry). The other maps keep theirs.
  void rescale(double factor);
  // Moves the current map rigidly: every keyframe's world and landmark position is taken by G
  // (p -> G p; T_cw -> T_cw G^-1). The other maps stay where they are.
  void move(const geometry::SE3& G);

  // Empties the store (every map) and starts a new map with the next id; one kMapReset event in
  // each log.
  void reset();
  // Starts a new, empty current map with the next id; the maps held so far stay (no event).
  void start_map();
  // Moves every keyframe and landmark of map `from` into map `into` (their poses and positions as
  // they are: the caller has put them in `into`'s frame). from's spanning tree hangs under
  // `attach` (a keyframe of `into`; invalid: its root becomes a root without a map to root).
  // When `from` was the current map, `into` is now. kInvalidArgument for an unknown map or
  // from == into. No events: the keyframes and landmarks stay.
  Status merge_map(MapId from, MapId into, KeyframeId attach);
  // Erases every keyframe and landmark of map `map` (not the current one) with their events, and
  // forgets the map. kInvalidArgument for the current or an unknown map.
  Status erase_map(MapId map);
  // Restoring a saved map (core/io/map_file.h): the caller has added the keyframes, landmarks
  // and observations of one map and gives back what the store derives and keeps.
  // The current map, still empty, takes the id `map` (a file's id), one no other map holds; new
  // maps take ids above every id held so far.
  Status restore_map_id(MapId map);
  // kf's spanning-tree parent (a keyframe of the same map that is not below kf); an invalid
  // parent makes kf its map's root. kInvalidArgument otherwise.
  Status restore_parent(KeyframeId kf, KeyframeId parent);
  // kf's covisibility list as saved: keyframes of the same map other than kf, each once, weights
  // > 0, sorted strongest first (ties by id as update_connections leaves them), at most
  // kMaxCovisible. kInvalidArgument otherwise.
  Status restore_covisibility(KeyframeId kf, Span<const Covisible> links);

  // The map new keyframes and landmarks belong to.
  MapId current_map() const { return current_; }
  // The maps held, oldest first; nullptr for one not held.
  Span<const MapInfo> maps() const { return Span<const MapInfo>(maps_.data(), static_cast<int>(maps_.size())); }
  const MapInfo* map_info(MapId map) const;
  void set_metric(MapId map, bool metric);
  MapStats stats() const;
  const MapCapacity& capacity() const { return capacity_; }

 private:
  std::size_t arena_offset(KeyframeId kf) const {
    return static_cast<std::size_t>(kf.slot()) * static_cast<std::size_t>(capacity_.max_keypoints_per_keyframe);
  }
  void unlink_observation(Landmark& lm, KeyframeId kf, std::uint32_t keypoint);
  // keeps parent's children in slot order
  void set_parent(KeyframeId child, Keyframe& c, KeyframeId parent);
  void remove_loop_edge(Keyframe& kf, KeyframeId other);
  void erase_landmark_object(LandmarkId id, const Landmark& lm);
  void remove_covisible(Keyframe& kf, KeyframeId other);
  void set_covisible(Keyframe& kf, KeyframeId other, int weight);

  MapCapacity capacity_;
  SlotMap<Keyframe, KeyframeId> keyframes_;
  SlotMap<Landmark, LandmarkId> landmarks_;
  std::vector<KeyframeFeature> feature_arena_;   // max_keyframes x max_keypoints_per_keyframe
  std::vector<LandmarkId> keypoint_landmark_arena_;
  MapInfo* info(MapId map);
  std::vector<MapInfo> maps_;  // oldest first; the current map's is among them
  MapId current_;
  std::uint64_t refused_observations_ = 0;
  std::uint64_t refused_replacements_ = 0;
  std::uint64_t dropped_observations_ = 0;
  std::uint32_t map_id_ = 0;  // the newest map's id (ids are never reused)
  EventLog<KeyframeEvent> keyframe_events_;
  EventLog<LandmarkEvent> landmark_events_;
  EventCursor take_erased_cursor_;
  // scratch of update_connections (counts per keyframe slot), sized once
  std::vector<int> shared_counts_;
  std::vector<std::uint32_t> touched_slots_;
  std::vector<KeyframeId> erase_scratch_;  // erase_map()'s keyframes
};

}  // namespace ale::map
