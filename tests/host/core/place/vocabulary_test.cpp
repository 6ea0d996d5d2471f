#include "core/place/vocabulary.h"

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "tests/host/core/place/place_fixtures.h"

namespace ale::place {
namespace {

using fixtures::World;

constexpr int kPlaces = 8;
constexpr int kPerPlace = 40;

class VocabularyTest : public ::testing::Test {
 protected:
  World world{kPlaces, kPerPlace, 11};
  Vocabulary vocab = fixtures::small_vocabulary(world);
};

TEST_F(VocabularyTest, TrainsATreeWithinItsShape) {
  ASSERT_FALSE(vocab.empty());
  EXPECT_EQ(vocab.branching(), 6);
  EXPECT_EQ(vocab.levels(), 3);
  EXPECT_LE(vocab.num_nodes(), 1 + 6 + 36 + 216);
  EXPECT_GT(vocab.num_words(), 100);  // 320 prototypes: most get a word of their own
  EXPECT_LT(vocab.num_words(), vocab.num_nodes());
}

TEST_F(VocabularyTest, TrainingIsDeterministicAndSeeded) {
  const Vocabulary again = fixtures::small_vocabulary(world);
  EXPECT_EQ(vocab.serialize(), again.serialize());
  const Vocabulary other = fixtures::small_vocabulary(world, 4);
  EXPECT_NE(vocab.serialize(), other.serialize());
}

TEST_F(VocabularyTest, RefusesBadTrainingParameters) {
  VocabularyTrainParams p;
  p.k = 1;
  EXPECT_EQ(Vocabulary::train(world.training(2), p).status().code(), StatusCode::kInvalidArgument);
  p.k = 10;
  p.levels = kMaxVocabularyLevels + 1;
  EXPECT_EQ(Vocabulary::train(world.training(2), p).status().code(), StatusCode::kInvalidArgument);
  p.levels = 3;
  const Result<Vocabulary> none = Vocabulary::train({{}, {}}, p);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.status().message().find("no descriptors"), std::string::npos);
}

TEST_F(VocabularyTest, BagOfWordsIsSortedNormalisedAndFeatureVectorCoversEveryFeature) {
  const std::vector<features::Descriptor> d = world.image(2, 6, 77);
  BowVector bow;
  FeatureVector fv;
  vocab.transform(d.data(), static_cast<int>(d.size()), bow, fv, 1);
  ASSERT_FALSE(bow.empty());
  double sum = 0.0;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    if (i > 0) {
      EXPECT_LT(bow[i - 1].word, bow[i].word);
    }
    EXPECT_GT(bow[i].weight, 0.0f);
    sum += bow[i].weight;
  }
  EXPECT_NEAR(sum, 1.0, 1e-5);
  ASSERT_EQ(fv.size(), d.size());
  std::set<std::uint32_t> seen;
  for (std::size_t i = 0; i < fv.size(); ++i) {
    if (i > 0) {
      EXPECT_TRUE(fv[i - 1].node < fv[i].node || (fv[i - 1].node == fv[i].node && fv[i - 1].feature < fv[i].feature));
    }
    seen.insert(fv[i].feature);
    // the node one level up from the feature's leaf
    NodeId node = 0;
    vocab.word_of(d[fv[i].feature], 1, &node);
    EXPECT_EQ(node, fv[i].node);
  }
  EXPECT_EQ(seen.size(), d.size());
  // levels_up >= L: everything under the root
  vocab.transform(d.data(), static_cast<int>(d.size()), bow, fv, 3);
  for (const NodeFeature& f : fv) EXPECT_EQ(f.node, 0u);
}

TEST_F(VocabularyTest, TransformIsDeterministic) {
  const std::vector<features::Descriptor> d = world.image(5, 8, 78);
  BowVector a, b;
  FeatureVector fa, fb;
  vocab.transform(d.data(), static_cast<int>(d.size()), a, fa, 2);
  vocab.transform(d.data(), static_cast<int>(d.size()), b, fb, 2);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].word, b[i].word);
    EXPECT_EQ(a[i].weight, b[i].weight);
  }
  ASSERT_EQ(fa.size(), fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) EXPECT_TRUE(fa[i].node == fb[i].node && fa[i].feature == fb[i].feature);
}

TEST_F(VocabularyTest, ScoreSeparatesPlaces) {
  BowVector a, b, c;
  FeatureVector fv;
  const auto da = world.image(1, 6, 501), db = world.image(1, 6, 502), dc = world.image(4, 6, 503);
  vocab.transform(da.data(), kPerPlace, a, fv, 0);
  vocab.transform(db.data(), kPerPlace, b, fv, 0);
  vocab.transform(dc.data(), kPerPlace, c, fv, 0);
  EXPECT_NEAR(Vocabulary::score(a, a), 1.0, 1e-5);
  EXPECT_DOUBLE_EQ(Vocabulary::score(a, b), Vocabulary::score(b, a));
  EXPECT_GT(Vocabulary::score(a, b), 0.5);  // the same place seen again
  EXPECT_LT(Vocabulary::score(a, c), 0.2);  // another place
  EXPECT_EQ(Vocabulary::score(a, BowVector{}), 0.0);
}

TEST_F(VocabularyTest, RoundTripGivesTheSameVocabulary) {
  const std::vector<std::uint8_t> bytes = vocab.serialize();
  Result<Vocabulary> back = Vocabulary::parse(bytes.data(), bytes.size());
  ASSERT_TRUE(back.ok()) << back.status().to_string();
  EXPECT_EQ(back->serialize(), bytes);
  EXPECT_EQ(back->checksum(), vocab.checksum());
  EXPECT_NE(vocab.checksum(), 0u);
  for (int p = 0; p < kPlaces; ++p) {
    const auto d = world.image(p, 10, 900u + static_cast<unsigned>(p));
    BowVector a, b;
    FeatureVector fa, fb;
    vocab.transform(d.data(), kPerPlace, a, fa, 1);
    back->transform(d.data(), kPerPlace, b, fb, 1);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].word == b[i].word && a[i].weight == b[i].weight);
    ASSERT_EQ(fa.size(), fb.size());
    for (std::size_t i = 0; i < fa.size(); ++i) EXPECT_TRUE(fa[i].node == fb[i].node && fa[i].feature == fb[i].feature);
  }
}

// parse() of bytes must fail with `code` and a message containing `what`.
void expect_refused(const std::vector<std::uint8_t>& bytes, std::size_t size, StatusCode code, const std::string& what) {
  const Result<Vocabulary> r = Vocabulary::parse(bytes.data(), size);
  ASSERT_FALSE(r.ok()) << "accepted " << size << " bytes, expected: " << what;
  EXPECT_EQ(r.status().code(), code) << r.status().to_string();
  EXPECT_NE(r.status().message().find(what), std::string::npos) << r.status().to_string();
  EXPECT_EQ(r.status().message().rfind("vocabulary: ", 0), 0u) << r.status().to_string();
}

template <class T>
void put(std::vector<std::uint8_t>& b, std::size_t offset, T v) {
  std::memcpy(b.data() + offset, &v, sizeof v);
}
// Rewrites the checksum so that only the structure is wrong.
void reseal(std::vector<std::uint8_t>& b) { put<std::uint64_t>(b, 48, vocabulary_file_checksum(b.data(), b.size())); }

TEST_F(VocabularyTest, ParseRefusesTruncatedFilesAtEveryBoundary) {
  const std::vector<std::uint8_t> bytes = vocab.serialize();
  // every header field boundary, then into the nodes and the words, and one byte short
  const std::size_t nodes_end = kVocabularyHeaderBytes + static_cast<std::size_t>(vocab.num_nodes()) * kVocabularyNodeBytes;
  std::vector<std::size_t> cuts{0, 4, 8, 12, 16, 20, 24, 28, 32, 36, 40, 48, 56, 63, 64, 65, 64 + kVocabularyNodeBytes,
                                nodes_end - 1, nodes_end, nodes_end + kVocabularyWordBytes, bytes.size() - 1};
  for (std::size_t cut : cuts) expect_refused(bytes, cut, StatusCode::kCorruptData, "truncated");
  EXPECT_FALSE(Vocabulary::parse(nullptr, 0).ok());
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  expect_refused(longer, longer.size(), StatusCode::kCorruptData, "1 bytes after the payload");
}

TEST_F(VocabularyTest, ParseRefusesWrongMagicAndOtherVersions) {
  std::vector<std::uint8_t> b = vocab.serialize();
  b[0] = 'X';
  expect_refused(b, b.size(), StatusCode::kCorruptData, "not a vocabulary file");
  b = vocab.serialize();
  put<std::uint32_t>(b, 8, 2);
  expect_refused(b, b.size(), StatusCode::kUnsupported, "format version 2, this build reads version 1");
  b = vocab.serialize();
  put<std::uint32_t>(b, 8, 0);
  expect_refused(b, b.size(), StatusCode::kUnsupported, "format version 0");
}

TEST_F(VocabularyTest, ParseRefusesEveryFlippedByte) {
  const std::vector<std::uint8_t> good = vocab.serialize();
  std::vector<std::uint8_t> b = good;
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0x80}}) {
      b[i] = static_cast<std::uint8_t>(good[i] ^ mask);
      ASSERT_FALSE(Vocabulary::parse(b.data(), b.size()).ok()) << "byte " << i << " ^ " << int(mask) << " accepted";
      b[i] = good[i];
    }
  }
  b[200] ^= 0x10;
  expect_refused(b, b.size(), StatusCode::kCorruptData, "checksum mismatch");
}

TEST_F(VocabularyTest, ParseRefusesOutOfRangeHeaderFieldsBeforeAllocating) {
  const std::vector<std::uint8_t> good = vocab.serialize();
  std::vector<std::uint8_t> b = good;
  put<std::uint32_t>(b, 16, 1);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "branching k = 1");
  b = good;
  put<std::uint32_t>(b, 20, 99);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "levels = 99");
  b = good;
  put<std::uint32_t>(b, 24, 0xFFFFFFFFu);  // would be 160 GB of nodes
  expect_refused(b, b.size(), StatusCode::kCorruptData, "4294967295 nodes");
  b = good;
  put<std::uint32_t>(b, 28, static_cast<std::uint32_t>(vocab.num_words() + 1));
  expect_refused(b, b.size(), StatusCode::kCorruptData, "payload length");
  b = good;
  put<std::uint32_t>(b, 32, 64);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "descriptors of 64 bytes");
  b = good;
  put<std::uint32_t>(b, 36, 7);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "weighting 7");
  b = good;
  put<std::uint64_t>(b, 40, 1ull << 60);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "payload length");
  b = good;
  put<std::uint64_t>(b, 56, 1);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "reserved");
}

TEST_F(VocabularyTest, ParseRefusesABrokenTreeWithAValidChecksum) {
  const std::vector<std::uint8_t> good = vocab.serialize();
  const std::size_t root = kVocabularyHeaderBytes;
  std::vector<std::uint8_t> b = good;
  put<std::uint32_t>(b, root + 32, static_cast<std::uint32_t>(vocab.num_nodes()));  // children past the end
  reseal(b);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "node 0 has children");
  b = good;
  put<std::uint32_t>(b, root + 36, 200);  // more children than k
  reseal(b);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "node 0 has children");
  b = good;
  // the first word's weight becomes NaN
  const std::size_t words = root + static_cast<std::size_t>(vocab.num_nodes()) * kVocabularyNodeBytes;
  put<std::uint32_t>(b, words + 4, 0x7FC00000u);
  reseal(b);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "word 0 has weight");
  b = good;
  put<std::uint32_t>(b, words, 0);  // word 0 points at the root
  reseal(b);
  expect_refused(b, b.size(), StatusCode::kCorruptData, "word 0");
}

}  // namespace
}  // namespace ale::place
