// The vocabulary built into the binaries (data/vocabulary/ale-orb.vocab, docs/place.md) parses,
// and how long that takes on this machine (a figure, not a timed assertion).
#include "core/place/embedded/embedded_vocabulary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

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

}  // namespace
}  // namespace ale::place
