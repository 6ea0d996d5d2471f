#include "core/map/dense_index.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/host/core/map/map_fixtures.h"

namespace ale::map {
namespace {

using namespace ale::map::fixtures;  // NOLINT: the fixtures of this folder

TEST(DenseIndex, NumbersLiveObjectsZeroToNAndBack) {
  MapStore m(MapCapacity{8, 16, 4});
  // keyframes added out of frame order and through reused slots
  const KeyframeId a = add_kf(m, 4, 30);
  const KeyframeId gone = add_kf(m, 4, 10);
  const KeyframeId b = add_kf(m, 4, 20);
  const LandmarkId l0 = add_lm(m, a), l1 = add_lm(m, a), l2 = add_lm(m, b);
  m.erase_keyframe(gone);
  m.erase_landmark(l1);
  const KeyframeId c = add_kf(m, 4, 5);  // gone's slot
  DenseIndex index(m);
  index.build(m, m.current_map());
  ASSERT_EQ(index.num_keyframes(), 3);
  ASSERT_EQ(index.num_landmarks(), 2);
  // by frame sequence: c (5), b (20), a (30)
  EXPECT_EQ(index.keyframe_at(0), c);
  EXPECT_EQ(index.keyframe_at(1), b);
  EXPECT_EQ(index.keyframe_at(2), a);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(index.index_of(index.keyframe_at(i)), i);
  // landmarks in slot order
  EXPECT_EQ(index.landmark_at(0), l0);
  EXPECT_EQ(index.landmark_at(1), l2);
  EXPECT_EQ(index.index_of(l2), 1);
  // erased, stale, invalid and out-of-range
  EXPECT_EQ(index.index_of(gone), -1);
  EXPECT_EQ(index.index_of(l1), -1);
  EXPECT_EQ(index.index_of(KeyframeId{}), -1);
  EXPECT_FALSE(index.keyframe_at(3).valid());
  EXPECT_FALSE(index.landmark_at(-1).valid());
}

TEST(DenseIndex, TheSameMapNumbersTheSameWhateverItsHistory) {
  // one store reached its map through erasures, the other was filled directly in dense order
  // (as loading a file does): the numbering maps one's objects onto the other's
  MapStore worn(MapCapacity{8, 16, 4});
  for (int i = 0; i < 3; ++i) worn.erase_keyframe(add_kf(worn, 4, 100 + i));
  const KeyframeId w2 = add_kf(worn, 4, 2), w1 = add_kf(worn, 4, 1);
  for (int i = 0; i < 4; ++i) worn.erase_landmark(add_lm(worn, w1));
  const LandmarkId wl = add_lm(worn, w2);
  DenseIndex worn_index(worn);
  worn_index.build(worn, worn.current_map());

  MapStore fresh(MapCapacity{8, 16, 4});
  const KeyframeId f1 = add_kf(fresh, 4, 1), f2 = add_kf(fresh, 4, 2);
  const LandmarkId fl = add_lm(fresh, f2);
  DenseIndex fresh_index(fresh);
  fresh_index.build(fresh, fresh.current_map());

  EXPECT_NE(w1, f1);  // the ids differ
  EXPECT_EQ(worn_index.index_of(w1), fresh_index.index_of(f1));
  EXPECT_EQ(worn_index.index_of(w2), fresh_index.index_of(f2));
  EXPECT_EQ(worn_index.index_of(wl), fresh_index.index_of(fl));
}

TEST(DenseIndex, OnlyTheGivenMap) {
  MapStore m(MapCapacity{4, 4, 2});
  const KeyframeId k = add_kf(m, 2, 0);
  DenseIndex index(m);
  index.build(m, MapId{m.current_map().value + 1});
  EXPECT_EQ(index.num_keyframes(), 0);
  EXPECT_EQ(index.index_of(k), -1);
  index.build(m, m.current_map());
  EXPECT_EQ(index.index_of(k), 0);
  // a later object in the same slot is not the numbered one
  m.erase_keyframe(k);
  const KeyframeId again = add_kf(m, 2, 1);
  ASSERT_EQ(again.slot(), k.slot());
  EXPECT_EQ(index.index_of(again), -1);
}

}  // namespace
}  // namespace ale::map
