#include "core/map/map_store.h"

#include <gtest/gtest.h>

#include <vector>

namespace ale::map {
namespace {

std::vector<KeyframeFeature> features_of(int n, int seed) {
  std::vector<KeyframeFeature> f(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    f[static_cast<std::size_t>(i)].u = static_cast<float>(i);
    f[static_cast<std::size_t>(i)].v = static_cast<float>(seed);
    f[static_cast<std::size_t>(i)].level = static_cast<std::int16_t>(i % 3);
    f[static_cast<std::size_t>(i)].descriptor.bytes[0] = static_cast<std::uint8_t>(i + seed);
  }
  return f;
}

geometry::SE3 pose_at(double x) { return geometry::SE3(geometry::SO3(), geometry::Vec3(-x, 0.0, 0.0)); }

KeyframeId add_kf(MapStore& m, int n, int seed, double x = 0.0) {
  const auto f = features_of(n, seed);
  Result<KeyframeId> id = m.add_keyframe(seed * 0.1, static_cast<std::uint64_t>(seed), pose_at(x), f.data(), n);
  EXPECT_TRUE(id.ok()) << id.status().to_string();
  return *id;
}

LandmarkId add_lm(MapStore& m, KeyframeId first) {
  Result<LandmarkId> id = m.add_landmark(geometry::Vec3(0.0, 0.0, 2.0), features::Descriptor{}, first);
  EXPECT_TRUE(id.ok());
  return *id;
}

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

// Three keyframes: k0 and k1 share 20 landmarks, k1 and k2 share 16, k0 and k2 share 3.
struct Chain {
  MapStore m{MapCapacity{8, 100, 64}};
  KeyframeId k0, k1, k2;
  Chain() {
    k0 = add_kf(m, 40, 0, 0.0);
    k1 = add_kf(m, 40, 1, 0.1);
    k2 = add_kf(m, 40, 2, 0.2);
    for (int i = 0; i < 20; ++i) link({k0, k1}, i);
    for (int i = 20; i < 36; ++i) link({k1, k2}, i);
    for (int i = 36; i < 39; ++i) link({k0, k2}, i);
    m.update_connections(k0);
    m.update_connections(k1);
    m.update_connections(k2);
  }
  void link(std::vector<KeyframeId> kfs, int kp) {
    const LandmarkId l = add_lm(m, kfs[0]);
    for (KeyframeId k : kfs) ASSERT_TRUE(m.add_observation(l, k, kp).ok());
  }
  int weight(KeyframeId a, KeyframeId b) const {
    const Keyframe* k = m.keyframe(a);
    for (int i = 0; i < k->num_covisible; ++i) {
      if (k->covisible[static_cast<std::size_t>(i)].keyframe == b) return k->covisible[static_cast<std::size_t>(i)].weight;
    }
    return 0;
  }
};

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
  m.replace_landmark(a, b);
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

}  // namespace
}  // namespace ale::map
