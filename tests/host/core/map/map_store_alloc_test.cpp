// The map store's per-frame operations allocate nothing once the store is built: heap calls are
// counted (tests/host/core/optim/alloc_counter.h).
#include <gtest/gtest.h>

#include <vector>

#include "core/map/dense_index.h"
#include "core/map/map_store.h"
#include "tests/host/core/map/map_fixtures.h"
#include "tests/host/core/optim/alloc_counter.h"

namespace ale::map {
namespace {

using namespace ale::map::fixtures;  // NOLINT: the fixtures of this folder

TEST(MapStoreAllocations, EditingTheMapAllocatesNothing) {
  MapStore m(MapCapacity{16, 400, 40});
  const std::vector<KeyframeFeature> f = features_of(40, 0);
  std::vector<KeyframeId> kfs(6);
  std::vector<LandmarkId> lms(40);
  EventCursor reader;
  std::vector<KeyframeId> children;
  children.reserve(16);
  DenseIndex index(m);
  long allocations = 0;
  int erased_events = 0;
  for (int round = 0; round < 3; ++round) {  // no warm-up: every round counts
    test::AllocationCounter counter;
    for (std::size_t k = 0; k < kfs.size(); ++k) {
      kfs[k] = *m.add_keyframe(static_cast<double>(k), k, pose_at(0.1 * static_cast<double>(k)), f.data(), 40);
    }
    // each landmark is seen by two consecutive keyframes
    for (std::size_t i = 0; i < lms.size(); ++i) {
      lms[i] = *m.add_landmark(geometry::Vec3(0.0, 0.0, 2.0), features::Descriptor{}, kfs[0]);
      for (std::size_t k = i % 5; k < i % 5 + 2; ++k) (void)m.add_observation(lms[i], kfs[k], static_cast<int>(i));
    }
    for (KeyframeId k : kfs) m.update_connections(k, 5);
    (void)m.add_loop_edge(kfs[0], kfs[5]);
    (void)m.replace_landmark(lms[1], lms[0]);
    m.erase_landmark(lms[2]);
    m.erase_observation(kfs[3], 3);
    for (KeyframeId k : kfs) m.children_of(k, children);
    EXPECT_GE(children.size(), 3u);  // a tree to re-parent
    children.clear();
    index.build(m, m.current_map());
    for (KeyframeId k : kfs) m.erase_keyframe(k);  // the root first: its children are re-parented
    m.keyframe_events().read(reader, [&](const KeyframeEvent& e) {
      erased_events += e.kind == MapEventKind::kKeyframeErased;
    });
    allocations += counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(erased_events, 18);
  EXPECT_EQ(reader.lost, 0u);
}

}  // namespace
}  // namespace ale::map
