// Place recognition on the frame path allocates nothing once warm: the vocabulary's transform
// into reused vectors, the database's add, sync and query (heap calls counted,
// tests/host/core/optim/alloc_counter.h).
#include <gtest/gtest.h>

#include <vector>

#include "core/place/keyframe_database.h"
#include "tests/host/core/optim/alloc_counter.h"
#include "tests/host/core/place/place_fixtures.h"

namespace ale::place {
namespace {

TEST(PlaceAllocations, TransformAddSyncAndQueryAllocateNothingOnceWarm) {
  const fixtures::World world(8, 40, 31);
  const Vocabulary vocab = fixtures::small_vocabulary(world);
  const map::MapCapacity capacity{6, 200, 40};
  map::MapStore map(capacity);
  KeyframeDatabase db(vocab, capacity);
  std::vector<std::vector<map::KeyframeFeature>> kf_features;
  std::vector<std::vector<features::Descriptor>> queries;
  for (int p = 0; p < 8; ++p) {
    const auto d = world.image(p, 6, 40u + static_cast<unsigned>(p));
    kf_features.emplace_back(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) kf_features.back()[i].descriptor = d[i];
    queries.push_back(world.image(p, 6, 80u + static_cast<unsigned>(p)));
  }
  BowVector bow;
  FeatureVector fv;
  bow.reserve(40);
  fv.reserve(40);
  std::vector<map::KeyframeId> out;
  out.reserve(6);
  std::vector<PlaceCandidate> candidates;
  candidates.reserve(6);
  long allocations = 0;
  int found = 0;
  for (int round = 0; round < 4; ++round) {  // round 0 warms up; rounds 1-3 count
    test::AllocationCounter counter;
    map::KeyframeId ids[6];
    for (int k = 0; k < 6; ++k) {
      const auto& f = kf_features[static_cast<std::size_t>((k + round) % 8)];
      ids[k] = *map.add_keyframe(0.0, 0, geometry::SE3(), f.data(), 40);
    }
    (void)db.sync(map);
    for (int p = 0; p < 8; ++p) {
      vocab.transform(queries[static_cast<std::size_t>(p)].data(), 40, bow, fv, 2);
      db.relocalisation_candidates(bow, map, candidates);
      db.relocalisation_candidates(bow, map, out);
      found += !out.empty();
    }
    for (map::KeyframeId id : ids) map.erase_keyframe(id);
    (void)db.sync(map);
    if (round > 0) allocations += counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(found, 4 * 6 - 1);
  EXPECT_EQ(db.size(), 0);
}

}  // namespace
}  // namespace ale::place
