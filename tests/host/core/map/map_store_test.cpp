#include "core/map/map_store.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tests/host/core/map/map_fixtures.h"

namespace ale::map {
namespace {

using namespace ale::map::fixtures;  // NOLINT: the fixtures of this folder

TEST(SlotMap, StaleIdsAreRecognisedAndSlotsReusedLastFreedFirst) {
  SlotMap<int, KeyframeId> s("test", 3);
  const KeyframeId a = *s.insert(1);
  const KeyframeId b = *s.insert(2);
  EXPECT_EQ(*s.get(a), 1);
  EXPECT_TRUE(s.erase(a));
  EXPECT_FALSE(s.erase(a));
  EXPECT_EQ(s.get(a), nullptr);
  const KeyframeId c = *s.insert(3);
  EXPECT_EQ(c.slot(), a.slot());  // reused
  EXPECT_NE(c, a);                // but a new generation
  EXPECT_EQ(s.get(a), nullptr);
  EXPECT_EQ(*s.get(c), 3);
  EXPECT_EQ(*s.get(b), 2);
  (void)*s.insert(4);
  Result<KeyframeId> full = s.insert(5);
  ASSERT_FALSE(full.ok());
  EXPECT_EQ(full.status().code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(s.failures(), 1u);
  EXPECT_EQ(s.high_water(), 3u);
  EXPECT_EQ(s.get(KeyframeId{}), nullptr);
}

TEST(MapStore, ObservationsAreKeptBothWays) {
  MapStore m(MapCapacity{4, 10, 8});
  const KeyframeId k0 = add_kf(m, 5, 0);
  const KeyframeId k1 = add_kf(m, 5, 1);
  const LandmarkId l = add_lm(m, k0);
  ASSERT_TRUE(m.add_observation(l, k0, 2).ok());
  ASSERT_TRUE(m.add_observation(l, k1, 4).ok());
  EXPECT_EQ(m.keypoint_landmarks(k0)[2], l);
  EXPECT_EQ(m.keypoint_landmarks(k1)[4], l);
  EXPECT_EQ(m.landmark(l)->num_observations, 2);
  // a keypoint with a landmark, a second observation from one keyframe, a bad keypoint
  const LandmarkId l2 = add_lm(m, k0);
  EXPECT_EQ(m.add_observation(l2, k0, 2).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.add_observation(l, k0, 3).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.add_observation(l2, k0, 5).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.add_observation(l2, k0, -1).code(), StatusCode::kInvalidArgument);
  m.erase_observation(k1, 4);
  EXPECT_FALSE(m.keypoint_landmarks(k1)[4].valid());
  EXPECT_EQ(m.landmark(l)->num_observations, 1);
  m.erase_landmark(l);
  EXPECT_FALSE(m.keypoint_landmarks(k0)[2].valid());
  EXPECT_EQ(m.landmark(l), nullptr);
}

TEST(MapStore, FullMapRefusesWithOutOfMemory) {
  MapStore m(MapCapacity{2, 1, 4});
  add_kf(m, 4, 0);
  add_kf(m, 4, 1);
  const auto f = features_of(4, 2);
  EXPECT_EQ(m.add_keyframe(0.0, 0, pose_at(0), f.data(), 4).status().code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(m.add_keyframe(0.0, 0, pose_at(0), f.data(), 5).status().code(), StatusCode::kInvalidArgument);
  (void)add_lm(m, KeyframeId{});
  EXPECT_EQ(m.add_landmark(geometry::Vec3::Zero(), {}, {}).status().code(), StatusCode::kOutOfMemory);
}

TEST(MapStore, LandmarkObservationsAreCapped) {
  MapStore m(MapCapacity{kMaxObservations + 1, 2, 2});
  std::vector<KeyframeId> kfs;
  for (int i = 0; i <= kMaxObservations; ++i) kfs.push_back(add_kf(m, 2, i));
  const LandmarkId l = add_lm(m, kfs[0]);
  for (int i = 0; i < kMaxObservations; ++i) ASSERT_TRUE(m.add_observation(l, kfs[static_cast<std::size_t>(i)], 0).ok());
  EXPECT_EQ(m.add_observation(l, kfs.back(), 0).code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(m.stats().refused_observations, 1u);
  EXPECT_FALSE(m.keypoint_landmarks(kfs.back())[0].valid());
}

TEST(MapStore, CovisibilityAndSpanningTree) {
  Chain c;
  EXPECT_EQ(c.weight(c.k0, c.k1), 20);
  EXPECT_EQ(c.weight(c.k1, c.k0), 20);
  EXPECT_EQ(c.weight(c.k1, c.k2), 16);
  EXPECT_EQ(c.weight(c.k0, c.k2), 0);  // below 15
  EXPECT_EQ(c.m.keyframe(c.k1)->covisible[0].keyframe, c.k0);  // strongest first
  EXPECT_EQ(c.m.root(), c.k0);
  EXPECT_FALSE(c.m.keyframe(c.k0)->parent.valid());
  EXPECT_EQ(c.m.keyframe(c.k1)->parent, c.k0);
  EXPECT_EQ(c.m.keyframe(c.k2)->parent, c.k1);
}

TEST(MapStore, ErasingAKeyframeReattachesChildrenAndUnlinks) {
  Chain c;
  c.m.erase_keyframe(c.k1);
  EXPECT_EQ(c.m.keyframe(c.k1), nullptr);
  EXPECT_EQ(c.m.keyframe(c.k2)->parent, c.k0);
  EXPECT_EQ(c.weight(c.k0, c.k1), 0);
  // k0 and k2 now share only 3: linked anyway as each other's strongest
  EXPECT_EQ(c.weight(c.k2, c.k0), 3);
  // the landmarks k1 saw lost that observation
  std::vector<LandmarkId> lms;
  c.m.landmarks_of(c.k2, lms);
  for (LandmarkId l : lms) {
    for (int i = 0; i < c.m.landmark(l)->num_observations; ++i) {
      EXPECT_NE(c.m.landmark(l)->observations[static_cast<std::size_t>(i)].keyframe, c.k1);
    }
  }
  c.m.erase_keyframe(c.k0);  // the root goes: its child becomes the root
  EXPECT_EQ(c.m.root(), c.k2);
  EXPECT_FALSE(c.m.keyframe(c.k2)->parent.valid());
  // both erasures are reported with the keyframe that took over and the pose relative to it
  std::vector<ErasedKeyframe> erased;
  c.m.take_erased(erased);
  ASSERT_EQ(erased.size(), 2u);
  EXPECT_EQ(erased[0].id, c.k1);
  EXPECT_EQ(erased[0].parent, c.k0);
  EXPECT_NEAR(erased[0].T_cp.translation().x(), -0.1, 1e-12);  // pose_at(0.1) * pose_at(0)^-1
  EXPECT_EQ(erased[1].id, c.k0);
  EXPECT_EQ(erased[1].parent, c.k2);
  EXPECT_NEAR(erased[1].T_cp.translation().x(), 0.2, 1e-12);
  c.m.take_erased(erased);
  EXPECT_TRUE(erased.empty());
}

TEST(MapStore, ReplaceLandmarkMovesObservations) {
  MapStore m(MapCapacity{4, 10, 8});
  const KeyframeId k0 = add_kf(m, 4, 0), k1 = add_kf(m, 4, 1), k2 = add_kf(m, 4, 2);
  const LandmarkId a = add_lm(m, k0), b = add_lm(m, k1);
  ASSERT_TRUE(m.add_observation(a, k0, 0).ok());
  ASSERT_TRUE(m.add_observation(a, k1, 1).ok());
  ASSERT_TRUE(m.add_observation(b, k1, 2).ok());
  ASSERT_TRUE(m.add_observation(b, k2, 3).ok());
  Result<LandmarkReplacement> r = m.replace_landmark(a, b);
  ASSERT_TRUE(r.ok()) << r.status().to_string();
  EXPECT_EQ(r->moved, 1);   // k0's
  EXPECT_EQ(r->merged, 1);  // k1 saw both
  EXPECT_EQ(m.landmark(a), nullptr);
  EXPECT_EQ(m.landmark(b)->num_observations, 3);  // k1 keeps its observation of b
  EXPECT_EQ(m.keypoint_landmarks(k0)[0], b);
  EXPECT_FALSE(m.keypoint_landmarks(k1)[1].valid());
  EXPECT_EQ(m.keypoint_landmarks(k1)[2], b);
}

TEST(MapStore, DescriptorIsTheMostCentralObservation) {
  MapStore m(MapCapacity{5, 4, 2});
  std::vector<KeyframeId> kfs;
  // median distances to the others (self included): 2, 1, 1, 2, 6; the first of the two 1s wins
  const std::uint8_t first_bytes[5] = {0x00, 0x01, 0x03, 0x07, 0xFF};
  for (int i = 0; i < 5; ++i) {
    KeyframeFeature f;
    f.descriptor.bytes[0] = first_bytes[i];
    kfs.push_back(*m.add_keyframe(0.0, 0, pose_at(0), &f, 1));
  }
  const LandmarkId l = add_lm(m, kfs[0]);
  for (KeyframeId k : kfs) ASSERT_TRUE(m.add_observation(l, k, 0).ok());
  m.update_descriptor(l);
  EXPECT_EQ(m.landmark(l)->descriptor.bytes[0], 0x01);
}

TEST(MapStore, NormalAndDistanceRange) {
  MapStore m(MapCapacity{4, 4, 2});
  KeyframeFeature f;
  f.level = 2;
  const KeyframeId k = *m.add_keyframe(0.0, 0, pose_at(0.0), &f, 1);
  const LandmarkId l = *m.add_landmark(geometry::Vec3(0.0, 0.0, 3.0), {}, k);
  ASSERT_TRUE(m.add_observation(l, k, 0).ok());
  const float scales[4] = {1.0f, 1.2f, 1.44f, 1.728f};
  m.update_normal_and_depth(l, scales, 4);
  EXPECT_NEAR(m.landmark(l)->normal.z(), 1.0, 1e-12);
  EXPECT_NEAR(m.landmark(l)->max_distance, 3.0 * 1.44, 1e-5);
  EXPECT_NEAR(m.landmark(l)->min_distance, 3.0 * 1.44 / 1.728, 1e-5);
}

TEST(MapStore, ResetEmptiesAndBumpsTheMapId) {
  Chain c;
  const std::uint32_t id = c.m.stats().map_id;
  c.m.reset();
  const MapStats s = c.m.stats();
  EXPECT_EQ(s.keyframes, 0u);
  EXPECT_EQ(s.landmarks, 0u);
  EXPECT_EQ(s.map_id, id + 1);
  EXPECT_EQ(s.keyframes_high_water, 3u);
  EXPECT_GT(s.reserved_bytes, 0u);
  EXPECT_EQ(c.m.keyframe(c.k0), nullptr);
}

TEST(MapStore, SpansViewWhatAKeyframeAndALandmarkHold) {
  Chain c;
  const Span<const KeyframeFeature> f = c.m.features_of(c.k1);
  ASSERT_EQ(f.size(), 40);
  EXPECT_EQ(f.data(), c.m.features(c.k1));
  EXPECT_EQ(f[7].u, 7.0f);
  const Span<const LandmarkId> lms = c.m.keypoint_landmarks_of(c.k1);
  ASSERT_EQ(lms.size(), 40);
  const Span<const Observation> obs = c.m.observations_of(lms[0]);
  ASSERT_EQ(obs.size(), 2);
  EXPECT_EQ(obs[0].keyframe, c.k0);
  EXPECT_EQ(obs[1].keyframe, c.k1);
  EXPECT_EQ(obs[1].keypoint, 0u);
  const Span<const Covisible> cov = c.m.covisible_of(c.k1);
  ASSERT_EQ(cov.size(), 2);
  EXPECT_EQ(cov[0].keyframe, c.k0);
  EXPECT_EQ(cov[1].weight, 16);
  // stale ids give empty views
  const LandmarkId l0 = lms[0];
  c.m.erase_landmark(l0);
  c.m.erase_keyframe(c.k2);
  EXPECT_TRUE(c.m.observations_of(l0).empty());
  EXPECT_TRUE(c.m.features_of(c.k2).empty());
  EXPECT_TRUE(c.m.keypoint_landmarks_of(c.k2).empty());
  EXPECT_TRUE(c.m.covisible_of(c.k2).empty());
  EXPECT_TRUE(c.m.loop_edges(c.k2).empty());
}

std::vector<KeyframeId> children(const MapStore& m, KeyframeId kf) {
  std::vector<KeyframeId> out;
  m.children_of(kf, out);
  return out;
}

// Children kept on the keyframes are what a scan of every keyframe's parent finds, in slot
// order (the order erase_keyframe's choice of a new root depends on).
std::vector<KeyframeId> children_by_scan(const MapStore& m, KeyframeId kf) {
  std::vector<KeyframeId> out;
  m.for_each_keyframe([&](KeyframeId id, const Keyframe& k) {
    if (k.parent == kf) out.push_back(id);
  });
  return out;
}

TEST(MapStore, ChildrenAreInSlotOrderAndTheRootGoesToTheFirstStrongest) {
  MapStore m(MapCapacity{6, 100, 40});
  const KeyframeId k0 = add_kf(m, 40, 0);
  const KeyframeId gap = add_kf(m, 40, 1);
  const KeyframeId k1 = add_kf(m, 40, 2);
  m.erase_keyframe(gap);
  const KeyframeId k2 = add_kf(m, 40, 3);  // takes the freed slot, below k1's
  ASSERT_LT(k2.slot(), k1.slot());
  for (int i = 0; i < 20; ++i) {
    for (KeyframeId k : {k1, k2}) {
      const LandmarkId l = add_lm(m, k0);
      ASSERT_TRUE(m.add_observation(l, k0, k == k1 ? i : 20 + i).ok());
      ASSERT_TRUE(m.add_observation(l, k, i).ok());
    }
  }
  m.update_connections(k1);  // k1 is linked first
  m.update_connections(k2);
  EXPECT_EQ(children(m, k0), (std::vector<KeyframeId>{k2, k1}));
  EXPECT_EQ(children(m, k0), children_by_scan(m, k0));
  m.erase_keyframe(k0);  // both children share 20 with it: the first in slot order becomes the root
  EXPECT_EQ(m.root(), k2);
  EXPECT_FALSE(m.keyframe(k2)->parent.valid());
  EXPECT_EQ(m.keyframe(k1)->parent, k2);
  EXPECT_EQ(children(m, k2), (std::vector<KeyframeId>{k1}));
}

TEST(MapStore, ChildrenMatchTheParentsThroughRandomEdits) {
  MapStore m(MapCapacity{12, 2000, 30});
  std::mt19937 rng(7);
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
  std::vector<KeyframeId> kfs;
  std::vector<LandmarkId> lms;
  int seed = 0, erased = 0;
  for (int step = 0; step < 3000; ++step) {
    const int op = pick(10);
    if (op < 2 && kfs.size() < 12) {
      kfs.push_back(add_kf(m, 30, seed++));
    } else if (op < 6 && kfs.size() >= 2) {
      // a landmark seen by two or three keyframes at free keypoints
      const LandmarkId l = add_lm(m, kfs[0]);
      for (int n = 0; n < 2 + pick(2); ++n) {
        const KeyframeId k = kfs[static_cast<std::size_t>(pick(static_cast<int>(kfs.size())))];
        (void)m.add_observation(l, k, pick(30));  // refused for a taken keypoint or a repeat
      }
      lms.push_back(l);
    } else if (op < 8 && !kfs.empty()) {
      m.update_connections(kfs[static_cast<std::size_t>(pick(static_cast<int>(kfs.size())))], 1 + pick(4));
    } else if (op < 9 && kfs.size() > 1) {
      const std::size_t i = static_cast<std::size_t>(pick(static_cast<int>(kfs.size())));
      m.erase_keyframe(kfs[i]);
      kfs.erase(kfs.begin() + static_cast<std::ptrdiff_t>(i));
      ++erased;
    } else if (!lms.empty()) {
      const std::size_t i = static_cast<std::size_t>(pick(static_cast<int>(lms.size())));
      m.erase_landmark(lms[i]);
      lms.erase(lms.begin() + static_cast<std::ptrdiff_t>(i));
    }
    for (KeyframeId k : kfs) ASSERT_EQ(children(m, k), children_by_scan(m, k)) << "step " << step;
  }
  EXPECT_GT(erased, 100);  // the edits did re-parent
}

TEST(MapStore, LoopEdgesAreKeptBothWaysAndDropWithTheKeyframe) {
  MapStore m(MapCapacity{kMaxLoopEdges + 3, 4, 2});
  std::vector<KeyframeId> kfs;
  for (int i = 0; i < kMaxLoopEdges + 3; ++i) kfs.push_back(add_kf(m, 2, i));
  const KeyframeId a = kfs[0], b = kfs[1], c = kfs[2];
  ASSERT_TRUE(m.add_loop_edge(a, b).ok());
  ASSERT_TRUE(m.add_loop_edge(c, a).ok());
  ASSERT_TRUE(m.add_loop_edge(b, a).ok());  // exists: no-op
  EXPECT_EQ(std::vector<KeyframeId>(m.loop_edges(a).begin(), m.loop_edges(a).end()), (std::vector<KeyframeId>{b, c}));
  EXPECT_EQ(std::vector<KeyframeId>(m.loop_edges(b).begin(), m.loop_edges(b).end()), (std::vector<KeyframeId>{a}));
  EXPECT_EQ(m.add_loop_edge(a, a).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.add_loop_edge(a, KeyframeId{}).code(), StatusCode::kInvalidArgument);
  for (int i = 3; i < kMaxLoopEdges + 1; ++i) ASSERT_TRUE(m.add_loop_edge(a, kfs[static_cast<std::size_t>(i)]).ok());
  EXPECT_EQ(m.loop_edges(a).size(), kMaxLoopEdges);
  // a is full: refused, and the other side is left unchanged
  EXPECT_EQ(m.add_loop_edge(kfs.back(), a).code(), StatusCode::kOutOfMemory);
  EXPECT_TRUE(m.loop_edges(kfs.back()).empty());
  m.erase_keyframe(a);
  EXPECT_TRUE(m.loop_edges(b).empty());
  EXPECT_TRUE(m.loop_edges(c).empty());
  EXPECT_EQ(m.add_loop_edge(a, b).code(), StatusCode::kInvalidArgument);  // stale
}

// kMaxObservations + 2 keyframes; `into` is seen at keypoint 0 of the first `into_seen_by`,
// `from` at keypoint 1 of those listed.
struct Crowd {
  MapStore m{MapCapacity{kMaxObservations + 2, 4, 2}};
  std::vector<KeyframeId> kfs;
  LandmarkId into, from;
  Crowd(int into_seen_by, const std::vector<int>& from_seen_by) {
    for (int i = 0; i < kMaxObservations + 2; ++i) kfs.push_back(add_kf(m, 2, i));
    into = add_lm(m, kfs[0]);
    from = add_lm(m, kfs[0]);
    for (int i = 0; i < into_seen_by; ++i) EXPECT_TRUE(m.add_observation(into, kfs[static_cast<std::size_t>(i)], 0).ok());
    for (int i : from_seen_by) EXPECT_TRUE(m.add_observation(from, kfs[static_cast<std::size_t>(i)], 1).ok());
  }
};

TEST(MapStore, ReplaceLandmarkRefusesRatherThanDropAnObservation) {
  // into is full; from is seen by the last two keyframes and one of into's
  Crowd c(kMaxObservations, {kMaxObservations, kMaxObservations + 1, 0});
  MapStore& m = c.m;
  const std::vector<KeyframeId>& kfs = c.kfs;
  const LandmarkId into = c.into, from = c.from;
  Result<LandmarkReplacement> r = m.replace_landmark(from, into);
  EXPECT_EQ(r.status().code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(m.stats().refused_replacements, 1u);
  // nothing changed
  EXPECT_EQ(m.observations_of(from).size(), 3);
  EXPECT_EQ(m.observations_of(into).size(), kMaxObservations);
  EXPECT_EQ(m.keypoint_landmarks_of(kfs[0])[1], from);
  EXPECT_EQ(m.keypoint_landmarks_of(kfs.back())[1], from);
  // the other way round fits: from takes into's observations, kfs[0] saw both
  m.erase_observation(kfs[1], 0);
  m.erase_observation(kfs[2], 0);
  m.erase_observation(kfs[3], 0);
  r = m.replace_landmark(into, from);
  ASSERT_TRUE(r.ok()) << r.status().to_string();
  EXPECT_EQ(r->moved, kMaxObservations - 4);
  EXPECT_EQ(r->merged, 1);
  EXPECT_EQ(m.observations_of(from).size(), kMaxObservations - 1);
  EXPECT_FALSE(m.keypoint_landmarks_of(kfs[0])[0].valid());  // freed: kfs[0] keeps its keypoint 1
  EXPECT_EQ(m.keypoint_landmarks_of(kfs[0])[1], from);
  EXPECT_EQ(m.keypoint_landmarks_of(kfs[4])[0], from);
  EXPECT_EQ(m.replace_landmark(into, from).status().code(), StatusCode::kInvalidArgument);  // stale
  EXPECT_EQ(m.replace_landmark(from, from).status().code(), StatusCode::kInvalidArgument);
}

TEST(MapStore, ReplaceLandmarkDropsWhatDoesNotFitOnlyWhenAsked) {
  Crowd c(kMaxObservations - 1, {0, kMaxObservations - 1, kMaxObservations, kMaxObservations + 1});
  MapStore& m = c.m;
  const std::vector<KeyframeId>& kfs = c.kfs;
  const LandmarkId into = c.into, from = c.from;
  Result<LandmarkReplacement> r = m.replace_landmark(from, into, WhenFull::kDropOverflow);
  ASSERT_TRUE(r.ok()) << r.status().to_string();
  EXPECT_EQ(r->merged, 1);   // kfs[0]
  EXPECT_EQ(r->moved, 1);    // the first that fits
  EXPECT_EQ(r->dropped, 2);  // the two after it
  EXPECT_EQ(m.stats().dropped_observations, 2u);
  EXPECT_EQ(m.stats().refused_replacements, 0u);
  EXPECT_EQ(m.landmark(from), nullptr);
  EXPECT_EQ(m.observations_of(into).size(), kMaxObservations);
  EXPECT_EQ(m.keypoint_landmarks_of(kfs[kMaxObservations - 1])[1], into);
  EXPECT_FALSE(m.keypoint_landmarks_of(kfs[kMaxObservations])[1].valid());
  EXPECT_FALSE(m.keypoint_landmarks_of(kfs[kMaxObservations + 1])[1].valid());
  EXPECT_FALSE(m.keypoint_landmarks_of(kfs[0])[1].valid());
  EXPECT_EQ(m.keypoint_landmarks_of(kfs[0])[0], into);
}

TEST(MapStore, ObjectsCarryTheMapTheyBelongTo) {
  MapStore m(MapCapacity{4, 4, 2});
  const KeyframeId k = add_kf(m, 2, 0);
  const LandmarkId l = add_lm(m, k);
  EXPECT_EQ(m.keyframe(k)->map_id, m.current_map());
  EXPECT_EQ(m.landmark(l)->map_id, m.current_map());
  EXPECT_EQ(m.current_map().value, m.stats().map_id);
  const MapId first = m.current_map();
  m.reset();
  const KeyframeId k2 = add_kf(m, 2, 1);
  const LandmarkId l2 = add_lm(m, k2);
  EXPECT_NE(m.current_map(), first);
  EXPECT_EQ(m.current_map().value, m.stats().map_id);
  EXPECT_EQ(m.keyframe(k2)->map_id, m.current_map());
  EXPECT_EQ(m.landmark(l2)->map_id, m.current_map());
}

// Two keyframes sharing 20 landmarks in the store's current map, the second a child of the first.
struct Pair {
  KeyframeId a, b;
  Pair(MapStore& m, int seed) {
    a = add_kf(m, 30, seed, 0.0);
    b = add_kf(m, 30, seed + 1, 0.5);
    for (int i = 0; i < 20; ++i) {
      const LandmarkId l = add_lm(m, a);
      EXPECT_TRUE(m.add_observation(l, a, i).ok());
      EXPECT_TRUE(m.add_observation(l, b, i).ok());
    }
    m.update_connections(a);
    m.update_connections(b);
  }
};

TEST(MapStore, StartMapKeepsTheOldMapWithItsOwnRootAndCounts) {
  MapStore m(MapCapacity{8, 100, 32});
  const Pair first(m, 0);
  const MapId old = m.current_map();
  m.start_map();
  const MapId now = m.current_map();
  EXPECT_NE(now, old);
  EXPECT_EQ(now.value, m.stats().map_id);
  ASSERT_NE(m.keyframe(first.a), nullptr);  // nothing erased
  EXPECT_EQ(m.stats().map_keyframes, 0u);
  EXPECT_EQ(m.stats().keyframes, 2u);
  EXPECT_FALSE(m.root().valid());
  const Pair second(m, 10);
  // each map has its own spanning tree: the new map's first keyframe is its root
  EXPECT_EQ(m.root(), second.a);
  EXPECT_EQ(m.root_of(old), first.a);
  EXPECT_FALSE(m.keyframe(second.a)->parent.valid());
  EXPECT_EQ(m.keyframe(second.b)->parent, second.a);
  EXPECT_EQ(m.keyframe(second.a)->map_id, now);
  const MapStats s = m.stats();
  EXPECT_EQ(s.maps, 2u);
  EXPECT_EQ(s.keyframes, 4u);
  EXPECT_EQ(s.landmarks, 40u);
  EXPECT_EQ(s.map_keyframes, 2u);
  EXPECT_EQ(s.map_landmarks, 20u);
  ASSERT_NE(m.map_info(old), nullptr);
  EXPECT_EQ(m.map_info(old)->keyframes, 2u);
  EXPECT_EQ(m.map_info(old)->landmarks, 20u);
  // erasing an old map's root hands its tree to the child, inside that map
  m.erase_keyframe(first.a);
  EXPECT_EQ(m.root_of(old), first.b);
  EXPECT_EQ(m.root(), second.a);
  EXPECT_EQ(m.map_info(old)->keyframes, 1u);
}

TEST(MapStore, RescaleScalesOnlyTheCurrentMap) {
  MapStore m(MapCapacity{8, 100, 32});
  const Pair first(m, 0);
  const geometry::Vec3 p_old = m.landmark(m.keypoint_landmarks(first.a)[0])->p_w;
  const geometry::SE3 T_old = m.keyframe(first.b)->T_cw;
  m.start_map();
  const Pair second(m, 10);
  m.rescale(2.0);
  EXPECT_EQ(m.landmark(m.keypoint_landmarks(first.a)[0])->p_w, p_old);
  EXPECT_EQ(m.keyframe(first.b)->T_cw.translation(), T_old.translation());
  EXPECT_DOUBLE_EQ(m.keyframe(second.b)->T_cw.translation().x(), 2.0 * T_old.translation().x());
}

// A rigid move of the current map: each landmark stays where its keyframes see it (T_cw p_w
// unchanged), the landmark goes to G p, the camera centre to G c; the other map stays.
TEST(MapStore, MoveTakesOnlyTheCurrentMapRigidly) {
  MapStore m(MapCapacity{8, 100, 32});
  const Pair first(m, 0);
  const LandmarkId l_old = m.keypoint_landmarks(first.a)[0];
  const geometry::Vec3 p_old = m.landmark(l_old)->p_w;
  const geometry::SE3 T_old = m.keyframe(first.b)->T_cw;
  m.start_map();
  const Pair second(m, 10);
  const LandmarkId l = m.keypoint_landmarks(second.b)[2];
  const geometry::Vec3 p = m.landmark(l)->p_w;
  const geometry::SE3 T = m.keyframe(second.b)->T_cw;
  const geometry::SE3 G(geometry::SO3::exp(geometry::Vec3(0.1, -0.4, 0.7)), geometry::Vec3(1.0, -2.0, 0.5));
  m.move(G);
  EXPECT_LT((m.landmark(l)->p_w - G * p).norm(), 1e-12);
  EXPECT_LT((m.keyframe(second.b)->T_cw * m.landmark(l)->p_w - T * p).norm(), 1e-12);
  EXPECT_LT((geometry::camera_centre(m.keyframe(second.b)->T_cw) - G * geometry::camera_centre(T)).norm(), 1e-12);
  EXPECT_EQ(m.landmark(l_old)->p_w, p_old);
  EXPECT_EQ(m.keyframe(first.b)->T_cw.translation(), T_old.translation());
}

TEST(MapStore, MergeMapMovesEverythingIntoTheOlderMapUnderTheAttachingKeyframe) {
  MapStore m(MapCapacity{8, 100, 32});
  const Pair first(m, 0);
  const MapId old = m.current_map();
  m.start_map();
  const MapId newer = m.current_map();
  const Pair second(m, 10);
  ASSERT_TRUE(m.merge_map(newer, old, first.b).ok());
  EXPECT_EQ(m.current_map(), old);
  EXPECT_EQ(m.stats().map_id, old.value);
  EXPECT_EQ(m.map_info(newer), nullptr);
  EXPECT_EQ(m.keyframe(second.a)->map_id, old);
  EXPECT_EQ(m.landmark(m.keypoint_landmarks(second.b)[3])->map_id, old);
  EXPECT_EQ(m.keyframe(second.a)->parent, first.b);  // the newer map's tree hangs under it
  EXPECT_EQ(m.root(), first.a);
  const MapStats s = m.stats();
  EXPECT_EQ(s.maps, 1u);
  EXPECT_EQ(s.map_keyframes, 4u);
  EXPECT_EQ(s.map_landmarks, 40u);
  // what is added now belongs to the merged map; a new map still gets a new id
  EXPECT_EQ(m.keyframe(add_kf(m, 2, 30))->map_id, old);
  m.start_map();
  EXPECT_GT(m.current_map().value, newer.value);
  // bad requests change nothing
  EXPECT_EQ(m.merge_map(old, old, first.a).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.merge_map(newer, old, first.a).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.stats().keyframes, 5u);
}

TEST(MapStore, EraseMapDropsOneMapWithEventsAndRefusesTheCurrentOne) {
  MapStore m(MapCapacity{8, 100, 32});
  const Pair first(m, 0);
  const MapId old = m.current_map();
  m.start_map();
  const Pair second(m, 10);
  EventCursor cursor;
  m.keyframe_events().read(cursor, [](const KeyframeEvent&) {});
  EXPECT_EQ(m.erase_map(m.current_map()).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(m.erase_map(old).ok());
  EXPECT_EQ(m.keyframe(first.a), nullptr);
  EXPECT_EQ(m.keyframe(first.b), nullptr);
  EXPECT_NE(m.keyframe(second.a), nullptr);
  EXPECT_EQ(m.map_info(old), nullptr);
  const MapStats s = m.stats();
  EXPECT_EQ(s.maps, 1u);
  EXPECT_EQ(s.keyframes, 2u);
  EXPECT_EQ(s.landmarks, 20u);  // the old map's landmarks went with it
  int erased = 0;
  m.keyframe_events().read(cursor, [&](const KeyframeEvent& e) {
    if (e.kind == MapEventKind::kKeyframeErased && e.map == old) ++erased;
  });
  EXPECT_EQ(erased, 2);
  EXPECT_EQ(m.erase_map(old).code(), StatusCode::kInvalidArgument);
  // reset drops every map
  m.reset();
  EXPECT_EQ(m.stats().maps, 1u);
  EXPECT_EQ(m.stats().keyframes, 0u);
}

TEST(MapStore, EventLogsTellEachConsumerWhatChanged) {
  MapStore m(MapCapacity{8, 100, 64});
  EventCursor trajectory = m.keyframe_events().cursor();
  const KeyframeId k0 = add_kf(m, 40, 0, 0.0);
  const KeyframeId k1 = add_kf(m, 40, 1, 0.1);
  for (int i = 0; i < 20; ++i) {
    const LandmarkId l = add_lm(m, k0);
    ASSERT_TRUE(m.add_observation(l, k0, i).ok());
    ASSERT_TRUE(m.add_observation(l, k1, i).ok());
  }
  m.update_connections(k1);
  // a second consumer that joins now sees only what happens from now on
  EventCursor database = m.keyframe_events().cursor();
  EventCursor landmarks;  // from the start
  m.erase_keyframe(k1);
  std::vector<KeyframeEvent> seen;
  EXPECT_EQ(m.keyframe_events().read(trajectory, [&](const KeyframeEvent& e) { seen.push_back(e); }), 0u);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].kind, MapEventKind::kKeyframeAdded);
  EXPECT_EQ(seen[0].keyframe.id, k0);
  EXPECT_EQ(seen[1].keyframe.id, k1);
  EXPECT_EQ(seen[2].kind, MapEventKind::kKeyframeErased);
  EXPECT_EQ(seen[2].keyframe.id, k1);
  EXPECT_EQ(seen[2].keyframe.parent, k0);
  EXPECT_NEAR(seen[2].keyframe.T_cp.translation().x(), -0.1, 1e-12);
  EXPECT_EQ(seen[2].map, m.current_map());
  seen.clear();
  m.keyframe_events().read(database, [&](const KeyframeEvent& e) { seen.push_back(e); });
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].keyframe.id, k1);
  // reading again gives nothing new
  EXPECT_EQ(m.keyframe_events().pending(trajectory), 0u);
  // landmarks: 20 added, one replaced into another, one erased, then the map reset
  std::vector<LandmarkId> lms;
  m.landmarks_of(k0, lms);
  ASSERT_TRUE(m.replace_landmark(lms[0], lms[1]).ok());
  m.erase_landmark(lms[2]);
  const MapId before = m.current_map();
  m.reset();
  std::vector<LandmarkEvent> lev;
  m.landmark_events().read(landmarks, [&](const LandmarkEvent& e) { lev.push_back(e); });
  ASSERT_EQ(lev.size(), 23u);
  EXPECT_EQ(lev[0].kind, MapEventKind::kLandmarkAdded);
  EXPECT_EQ(lev[19].kind, MapEventKind::kLandmarkAdded);
  EXPECT_EQ(lev[20].kind, MapEventKind::kLandmarkErased);
  EXPECT_EQ(lev[20].id, lms[0]);
  EXPECT_EQ(lev[21].id, lms[2]);
  EXPECT_EQ(lev[22].kind, MapEventKind::kMapReset);
  EXPECT_EQ(lev[22].map, before);
  seen.clear();
  m.keyframe_events().read(trajectory, [&](const KeyframeEvent& e) { seen.push_back(e); });
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].kind, MapEventKind::kMapReset);
}

TEST(MapStore, TakeErasedDropsWhatAResetEnded) {
  Chain c;
  c.m.erase_keyframe(c.k2);
  c.m.reset();
  const KeyframeId k = add_kf(c.m, 4, 9);
  add_kf(c.m, 4, 10);
  c.m.erase_keyframe(k);
  std::vector<ErasedKeyframe> erased;
  c.m.take_erased(erased);
  ASSERT_EQ(erased.size(), 1u);
  EXPECT_EQ(erased[0].id, k);
}

TEST(MapStore, TheKeyframeLogHoldsEveryKeyframeAddedAndErasedOnce) {
  // a consumer that reads once after filling and emptying the whole map loses nothing
  MapStore m(MapCapacity{16, 4, 2});
  EventCursor c;
  for (int round = 0; round < 2; ++round) {
    std::vector<KeyframeId> kfs;
    for (int i = 0; i < 16; ++i) kfs.push_back(add_kf(m, 2, i));
    for (KeyframeId k : kfs) m.erase_keyframe(k);
  }
  int n = 0;
  EXPECT_EQ(m.keyframe_events().read(c, [&](const KeyframeEvent&) { ++n; }), 64u - m.keyframe_events().capacity());
  EXPECT_EQ(m.keyframe_events().capacity(), 2u * 16u + 16u);
  EXPECT_EQ(n, 48);
  EventCursor d = m.keyframe_events().cursor();
  std::vector<KeyframeId> kfs;
  for (int i = 0; i < 16; ++i) kfs.push_back(add_kf(m, 2, i));
  for (KeyframeId k : kfs) m.erase_keyframe(k);
  EXPECT_EQ(m.keyframe_events().read(d, [](const KeyframeEvent&) {}), 0u);
  EXPECT_EQ(d.lost, 0u);
}

// What a map file gives back: the tree, covisibility and the map's id, each checked.
TEST(MapStore, RestoringTheTreeRefusesCyclesAndOtherMaps) {
  Chain c;
  EXPECT_EQ(c.m.root(), c.k0);
  ASSERT_EQ(c.m.keyframe(c.k2)->parent, c.k1);
  EXPECT_FALSE(c.m.restore_parent(c.k0, c.k2).ok()) << "k0 under k2, which is under k1 under k0: a cycle";
  // the tree turned over: k2 the root, k1 under it, k0 under k1
  ASSERT_TRUE(c.m.restore_parent(c.k2, KeyframeId{}).ok());
  ASSERT_TRUE(c.m.restore_parent(c.k1, c.k2).ok());
  ASSERT_TRUE(c.m.restore_parent(c.k0, c.k1).ok());
  EXPECT_EQ(c.m.root(), c.k2);
  EXPECT_EQ(c.m.keyframe(c.k0)->parent, c.k1);
  EXPECT_FALSE(c.m.restore_parent(c.k2, c.k0).ok()) << "a cycle again";
  EXPECT_FALSE(c.m.restore_parent(c.k1, c.k1).ok());
  c.m.start_map();
  const KeyframeId other = add_kf(c.m, 4, 9);
  EXPECT_FALSE(c.m.restore_parent(other, c.k0).ok()) << "a parent in another map";
}

TEST(MapStore, RestoringCovisibilityChecksTheListAndSortsTies) {
  Chain c;
  const std::vector<Covisible> good{{c.k2, 5}, {c.k1, 5}};
  ASSERT_TRUE(c.m.restore_covisibility(c.k0, Span<const Covisible>(good.data(), 2)).ok());
  ASSERT_EQ(c.m.covisible_of(c.k0).size(), 2);
  EXPECT_EQ(c.m.covisible_of(c.k0)[0].keyframe, c.k1);  // ties by id, as update_connections keeps them
  const std::vector<Covisible> unsorted{{c.k1, 2}, {c.k2, 5}};
  EXPECT_FALSE(c.m.restore_covisibility(c.k0, Span<const Covisible>(unsorted.data(), 2)).ok());
  const std::vector<Covisible> itself{{c.k0, 5}};
  EXPECT_FALSE(c.m.restore_covisibility(c.k0, Span<const Covisible>(itself.data(), 1)).ok());
  const std::vector<Covisible> twice{{c.k1, 5}, {c.k1, 4}};
  EXPECT_FALSE(c.m.restore_covisibility(c.k0, Span<const Covisible>(twice.data(), 2)).ok());
  const std::vector<Covisible> zero{{c.k1, 0}};
  EXPECT_FALSE(c.m.restore_covisibility(c.k0, Span<const Covisible>(zero.data(), 1)).ok());
}

TEST(MapStore, RestoringAMapIdNeedsAnEmptyCurrentMapAndAFreeId) {
  MapStore m(MapCapacity{8, 16, 8});
  ASSERT_TRUE(m.restore_map_id(MapId{7}).ok());
  EXPECT_EQ(m.current_map(), MapId{7});
  add_kf(m, 2, 0);
  EXPECT_FALSE(m.restore_map_id(MapId{9}).ok()) << "the current map is not empty";
  m.start_map();
  EXPECT_EQ(m.current_map(), MapId{8});
  EXPECT_FALSE(m.restore_map_id(MapId{7}).ok()) << "held by the first map";
  ASSERT_TRUE(m.restore_map_id(MapId{3}).ok());
  m.start_map();
  EXPECT_EQ(m.current_map(), MapId{9}) << "new ids stay above every id held";
}

}  // namespace
}  // namespace ale::map
