#include "core/place/keyframe_database.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/host/core/place/place_fixtures.h"

namespace ale::place {
namespace {

using fixtures::World;

constexpr int kPerPlace = 40;

// A map whose keyframes each see one place of the world.
class KeyframeDatabaseTest : public ::testing::Test {
 protected:
  World world{8, kPerPlace, 21};
  Vocabulary vocab = fixtures::small_vocabulary(world);
  map::MapCapacity capacity{8, 400, kPerPlace};
  map::MapStore map{capacity};
  KeyframeDatabase db{vocab, capacity};

  map::KeyframeId add_keyframe(int place, std::uint64_t seed) {
    const std::vector<features::Descriptor> d = world.image(place, 6, seed);
    std::vector<map::KeyframeFeature> f(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) f[i].descriptor = d[i];
    Result<map::KeyframeId> id = map.add_keyframe(static_cast<double>(seed), seed, geometry::SE3(), f.data(), kPerPlace);
    EXPECT_TRUE(id.ok()) << id.status().to_string();
    return *id;
  }
  BowVector query(int place, std::uint64_t seed) {
    const std::vector<features::Descriptor> d = world.image(place, 6, seed);
    BowVector bow;
    FeatureVector fv;
    vocab.transform(d.data(), kPerPlace, bow, fv, db.params().fv_levels_up);
    return bow;
  }
  // Makes a and b covisible (n shared landmarks).
  void link(map::KeyframeId a, map::KeyframeId b, int n) {
    for (int i = 0; i < n; ++i) {
      const map::LandmarkId lm = *map.add_landmark(geometry::Vec3(0, 0, 1), features::Descriptor{}, a);
      ASSERT_TRUE(map.add_observation(lm, a, i).ok());
      ASSERT_TRUE(map.add_observation(lm, b, i).ok());
    }
    map.update_connections(a, 1);
    map.update_connections(b, 1);
  }
};

TEST_F(KeyframeDatabaseTest, SyncAddsTheMapsKeyframesOnceAndFindsThePlace) {
  std::vector<map::KeyframeId> kf;
  for (int p = 0; p < 5; ++p) kf.push_back(add_keyframe(p, 100u + static_cast<unsigned>(p)));
  EXPECT_EQ(db.sync(map), 0u);
  EXPECT_EQ(db.size(), 5);
  const BowVector* stored = db.bow(kf[3]);
  ASSERT_NE(stored, nullptr);
  ASSERT_NE(db.feature_vector(kf[3]), nullptr);
  EXPECT_EQ(db.feature_vector(kf[3])->size(), static_cast<std::size_t>(kPerPlace));
  // computed once: a second sync leaves the stored vectors where they are
  EXPECT_EQ(db.sync(map), 0u);
  EXPECT_EQ(db.bow(kf[3]), stored);

  std::vector<PlaceCandidate> c;
  db.relocalisation_candidates(query(3, 555), map, c);
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.front().keyframe, kf[3]);
  EXPECT_GT(c.front().score, 0.4f);
  std::vector<map::KeyframeId> ids;
  db.relocalisation_candidates(query(3, 555), map, ids);
  ASSERT_EQ(ids.size(), c.size());
  EXPECT_EQ(ids.front(), kf[3]);
  // a place no keyframe sees shares (almost) no words: nothing, or weak candidates
  db.relocalisation_candidates(query(7, 556), map, c);
  for (const PlaceCandidate& x : c) EXPECT_LT(x.score, 0.2f);
}

TEST_F(KeyframeDatabaseTest, ErasedKeyframesAreForgottenThroughTheEventLog) {
  const map::KeyframeId a = add_keyframe(1, 200), b = add_keyframe(2, 201);
  (void)db.sync(map);
  map.erase_keyframe(b);
  std::vector<map::KeyframeId> ids;
  // not synced yet: the database still holds b, but the query skips what the map lost
  EXPECT_TRUE(db.contains(b));
  db.relocalisation_candidates(query(2, 600), map, ids);
  for (map::KeyframeId id : ids) EXPECT_NE(id, b);
  EXPECT_EQ(db.sync(map), 0u);
  EXPECT_FALSE(db.contains(b));
  EXPECT_EQ(db.bow(b), nullptr);
  EXPECT_EQ(db.size(), 1);
  // the slot is reused by a new keyframe, which the database takes as new
  const map::KeyframeId c = add_keyframe(2, 202);
  EXPECT_EQ(c.slot(), b.slot());
  (void)db.sync(map);
  db.relocalisation_candidates(query(2, 601), map, ids);
  ASSERT_FALSE(ids.empty());
  EXPECT_EQ(ids.front(), c);
  EXPECT_TRUE(db.contains(a));
  map.reset();
  (void)db.sync(map);
  EXPECT_EQ(db.size(), 0);
  db.relocalisation_candidates(query(2, 602), map, ids);
  EXPECT_TRUE(ids.empty());
}

TEST_F(KeyframeDatabaseTest, LostEventsAreReconciledWithTheMap) {
  const map::KeyframeId keep = add_keyframe(0, 300);
  (void)db.sync(map);
  // far more events than the log holds (2 x 8 + 16)
  for (int i = 0; i < 30; ++i) map.erase_keyframe(add_keyframe(1 + i % 6, 400u + static_cast<unsigned>(i)));
  const map::KeyframeId last = add_keyframe(4, 500);
  EXPECT_GT(db.sync(map), 0u);
  EXPECT_EQ(db.size(), 2);
  EXPECT_TRUE(db.contains(keep));
  EXPECT_TRUE(db.contains(last));
}

TEST_F(KeyframeDatabaseTest, CovisibleGroupsAddUpAndTheBestOfEachIsReturnedOnce) {
  // two keyframes of place 2 seen together, one of place 2 alone, others elsewhere
  const map::KeyframeId g1 = add_keyframe(2, 700), g2 = add_keyframe(2, 701);
  const map::KeyframeId alone = add_keyframe(2, 702);
  (void)add_keyframe(5, 703);
  link(g1, g2, 20);
  (void)db.sync(map);
  std::vector<PlaceCandidate> c;
  db.relocalisation_candidates(query(2, 800), map, c);
  ASSERT_FALSE(c.empty());
  // the pair's group outscores the lone keyframe: its best comes first, with both scores summed
  EXPECT_TRUE(c[0].keyframe == g1 || c[0].keyframe == g2);
  const float s1 = static_cast<float>(Vocabulary::score(query(2, 800), *db.bow(g1)));
  const float s2 = static_cast<float>(Vocabulary::score(query(2, 800), *db.bow(g2)));
  EXPECT_NEAR(c[0].group_score, s1 + s2, 1e-5f);
  EXPECT_NEAR(c[0].score, std::max(s1, s2), 1e-6f);
  // the group's best appears once though both g1 and g2 lead a group
  int pair_entries = 0;
  for (const PlaceCandidate& x : c) pair_entries += x.keyframe == g1 || x.keyframe == g2;
  EXPECT_EQ(pair_entries, 1);
  // the lone keyframe scores about half the pair's group: below 0.75 of it, so it is left out
  const float sa = static_cast<float>(Vocabulary::score(query(2, 800), *db.bow(alone)));
  ASSERT_LT(sa, 0.75f * c[0].group_score);
  for (const PlaceCandidate& x : c) EXPECT_NE(x.keyframe, alone);
  // deterministic: the same query gives the same list
  std::vector<PlaceCandidate> again;
  db.relocalisation_candidates(query(2, 800), map, again);
  ASSERT_EQ(again.size(), c.size());
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(again[i].keyframe, c[i].keyframe);
}

TEST_F(KeyframeDatabaseTest, LoopCandidatesLeaveOutTheKeyframesNeighboursAndThoseBelowTheScore) {
  // place 3 seen three times: now (kf), by a covisible neighbour of kf, and long ago (old)
  const map::KeyframeId old = add_keyframe(3, 900);
  (void)add_keyframe(6, 901);
  const map::KeyframeId neighbour = add_keyframe(3, 902);
  const map::KeyframeId kf = add_keyframe(3, 903);
  link(kf, neighbour, 20);
  (void)db.sync(map);
  std::vector<PlaceCandidate> c;
  db.loop_candidates(kf, map, 0.0f, c);
  // the old sighting is the loop; the neighbour (joined already) and kf itself are not offered
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].keyframe, old);
  // the relocalisation query of the same words leads with kf's own group
  std::vector<PlaceCandidate> all;
  db.relocalisation_candidates(*db.bow(kf), map, all);
  ASSERT_FALSE(all.empty());
  EXPECT_TRUE(all[0].keyframe == kf || all[0].keyframe == neighbour);
  // a candidate scoring below the bound is dropped
  const float s = static_cast<float>(Vocabulary::score(*db.bow(kf), *db.bow(old)));
  db.loop_candidates(kf, map, s + 1e-3f, c);
  EXPECT_TRUE(c.empty());
  db.loop_candidates(kf, map, s - 1e-3f, c);
  EXPECT_EQ(c.size(), 1u);
  // a keyframe the database does not hold has no candidates
  db.erase(kf);
  db.loop_candidates(kf, map, 0.0f, c);
  EXPECT_TRUE(c.empty());
}

TEST_F(KeyframeDatabaseTest, RefusesWhatItCannotHold) {
  const std::vector<features::Descriptor> d = world.image(0, 2, 1);
  EXPECT_EQ(db.add(map::KeyframeId{}, d.data(), kPerPlace).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(db.add(map::KeyframeId::make(8, 0), d.data(), kPerPlace).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(db.add(map::KeyframeId::make(0, 0), d.data(), kPerPlace + 1).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(db.add(map::KeyframeId::make(0, 0), d.data(), kPerPlace).ok());
  EXPECT_GT(db.reserved_bytes(), static_cast<std::size_t>(8 * kPerPlace * (sizeof(BowEntry) + sizeof(NodeFeature))));
  std::printf("[ figures  ] keyframe database for 8 keyframes x %d features: %zu bytes reserved\n", kPerPlace,
              db.reserved_bytes());
}

}  // namespace
}  // namespace ale::place
