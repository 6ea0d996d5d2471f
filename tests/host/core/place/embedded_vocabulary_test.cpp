// The vocabulary built into the binaries (data/vocabulary/ale-orb.vocab, docs/place.md) parses,
// and how long that takes on this machine; what a frame's transform costs and what a keyframe
// database for the default map capacity reserves (figures, not timed assertions).
#include "core/place/embedded/embedded_vocabulary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "core/base/rng.h"
#include "core/map/map_store.h"
#include "core/place/keyframe_database.h"

namespace ale::place {
namespace {

TEST(EmbeddedVocabulary, ParsesAndReportsItsLoadTime) {
  const Span<const std::uint8_t> bytes = embedded_vocabulary_bytes();
  ASSERT_GT(bytes.size(), static_cast<int>(kVocabularyHeaderBytes));
  EXPECT_LE(bytes.size(), 4 * 1024 * 1024);  // the limit for the file
  std::vector<double> ms;
  for (int i = 0; i < 11; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const Result<Vocabulary> v = load_embedded_vocabulary();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    ASSERT_TRUE(v.ok()) << v.status().to_string();
    EXPECT_GE(v->num_words(), 1000);
    EXPECT_EQ(v->checksum(), vocabulary_file_checksum(bytes.data(), static_cast<std::size_t>(bytes.size())));
  }
  std::sort(ms.begin(), ms.end());
  std::printf("[ figures  ] embedded vocabulary: %d bytes, parse median %.2f ms (min %.2f, max %.2f; target < 50 ms)\n",
              bytes.size(), ms[5], ms.front(), ms.back());
}

TEST(EmbeddedVocabulary, TransformCostAndDatabaseMemoryFigures) {
  const Result<Vocabulary> v = load_embedded_vocabulary();
  ASSERT_TRUE(v.ok()) << v.status().to_string();
  SplitMix64 rng(5);
  std::vector<features::Descriptor> d(1000);
  for (features::Descriptor& x : d)
    for (std::uint8_t& b : x.bytes) b = static_cast<std::uint8_t>(rng.next() >> 56);
  BowVector bow;
  FeatureVector fv;
  std::vector<double> ms;
  for (int i = 0; i < 11; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    v->transform(d.data(), 1000, bow, fv, 2);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  EXPECT_EQ(fv.size(), 1000u);
  const map::MapCapacity capacity;  // the map's defaults
  KeyframeDatabase db(*v, capacity);
  std::printf("[ figures  ] transform of 1000 descriptors: median %.3f ms; keyframe database for %d keyframes x %d "
              "features: %.2f MB reserved\n",
              ms[5], capacity.max_keyframes, capacity.max_keypoints_per_keyframe,
              static_cast<double>(db.reserved_bytes()) / (1024.0 * 1024.0));
}

}  // namespace
}  // namespace ale::place
