// A vocabulary of binary visual words (bag of words, DBoW2's idea in FBoW's flat layout): a tree
// of branching k and depth L whose nodes are 256-bit descriptors (the bitwise majority of the
// training descriptors under them). A descriptor's word is the leaf reached by going down from
// the root to the nearest child (Hamming distance, ties to the lower child) at every level; each
// word weighs its inverse document frequency, log(N / n_w) over the N training images of which
// n_w had a descriptor there (TF-IDF). Trained by train() (k-majority with k-means++ seeding from
// our seeded RNG, so the same descriptors and seed give the same file on every machine).
//
// The file (all integers little-endian) is one 64-byte header and a flat payload:
//   header  magic "ALEVOCAB", u32 format version (1), u32 header bytes (64), u32 k, u32 levels L,
//           u32 nodes, u32 words, u32 descriptor bytes (32), u32 weighting (1: TF-IDF),
//           u64 payload bytes, u64 checksum, u64 reserved (0); the checksum is FNV-1a 64 over
//           the header's first 48 bytes (up to the checksum) and then the payload, so a changed
//           parameter is caught as surely as a changed node
//   payload nodes x 40 bytes: the descriptor (32 bytes), u32 first child (0 for a leaf; node 0 is
//           the root and nobody's child), u32 child count (a leaf: its word id); the children of
//           a node are consecutive and come after it
//           words x 8 bytes: u32 leaf node, f32 IDF weight
// parse() checks every length against the buffer and the limits before it allocates anything,
// then the checksum, then the tree (children in range and after their parent, depth <= L, every
// word's leaf names it back), so a corrupt file is refused with the reason instead of being used.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/span.h"
#include "core/base/status.h"
#include "core/features/brief.h"

namespace ale::place {

using WordId = std::uint32_t;
using NodeId = std::uint32_t;

// One word of an image's bag of words and its weight.
struct BowEntry {
  WordId word = 0;
  float weight = 0.0f;
};
// Sorted by word, weights L1-normalised (sum 1), each word once.
using BowVector = std::vector<BowEntry>;

// A feature of an image under a node of the tree (FeatureVector).
struct NodeFeature {
  NodeId node = 0;
  std::uint32_t feature = 0;  // index into the image's descriptors
};
// Features grouped by the node `fv_levels_up` levels above their leaf: sorted by node, then
// feature. Guided matching compares only features that share a node (search_by_bow).
using FeatureVector = std::vector<NodeFeature>;

constexpr char kVocabularyMagic[8] = {'A', 'L', 'E', 'V', 'O', 'C', 'A', 'B'};
constexpr std::uint32_t kVocabularyFormatVersion = 1;
constexpr std::size_t kVocabularyHeaderBytes = 64;
constexpr std::size_t kVocabularyNodeBytes = 40;
constexpr std::size_t kVocabularyWordBytes = 8;
constexpr std::uint32_t kWeightingTfIdf = 1;
// Limits parse() enforces (a larger file is refused before anything is allocated).
constexpr int kMaxBranching = 64;
constexpr int kMaxVocabularyLevels = 8;
constexpr std::uint32_t kMaxVocabularyNodes = 1u << 22;  // 160 MB of nodes: far beyond any useful vocabulary

struct VocabularyTrainParams {
  int k = 10;                  // branching, 2..kMaxBranching
  int levels = 4;              // depth L, 1..kMaxVocabularyLevels
  std::uint64_t seed = 1;      // k-means++ seeding
  int max_iterations = 10;     // k-majority iterations per node (stops earlier once stable)
};

// The checksum a file of `size` bytes should carry (0 when shorter than the header).
std::uint64_t vocabulary_file_checksum(const std::uint8_t* file, std::size_t size);

class Vocabulary {
 public:
  Vocabulary() = default;

  // Trains on the descriptors of `images` (images[i] lists image i's descriptors).
  // kInvalidArgument for parameters out of range or no descriptors at all.
  static Result<Vocabulary> train(const std::vector<std::vector<features::Descriptor>>& images,
                                  const VocabularyTrainParams& params);
  // Reads a file's bytes (the format above); kCorruptData or kUnsupported saying what is wrong.
  static Result<Vocabulary> parse(const std::uint8_t* data, std::size_t size);
  // The file's bytes.
  std::vector<std::uint8_t> serialize() const;

  // The bag of words of n descriptors and their feature vector (features grouped by the node
  // fv_levels_up levels above their leaf; 0: the leaves, >= L: the root, a leaf shallower than
  // that counts as its own node). Both outputs are replaced; with their capacity kept, nothing
  // is allocated once they have held n entries. An empty vocabulary gives empty outputs.
  void transform(const features::Descriptor* d, int n, BowVector& bow, FeatureVector& fv, int fv_levels_up) const;
  // The word of one descriptor and, when node_out is given, its node fv_levels_up levels up.
  WordId word_of(const features::Descriptor& d, int fv_levels_up = 0, NodeId* node_out = nullptr) const;

  // DBoW2's L1 score of two bags of words: 1 - |a - b|_1 / 2, in [0, 1] (1: the same words in
  // the same proportions; 0: no word in common).
  static double score(const BowVector& a, const BowVector& b);

  bool empty() const { return nodes_.empty(); }
  int branching() const { return k_; }
  int levels() const { return levels_; }
  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_words() const { return static_cast<int>(words_.size()); }
  float word_weight(WordId w) const { return words_[w].weight; }
  // The file's checksum (a map file records it to name the vocabulary it was built with).
  std::uint64_t checksum() const { return checksum_; }
  // Bytes the vocabulary holds in memory.
  std::size_t memory_bytes() const;

 private:
  struct Node {
    features::Descriptor descriptor;
    std::uint32_t first_child = 0;  // 0: a leaf
    std::uint32_t count_or_word = 0;
  };
  struct Word {
    NodeId node = 0;
    float weight = 0.0f;
  };
  // The leaf of d and the path to it: path[0] is the root, path[depth] the leaf.
  int descend(const features::Descriptor& d, NodeId* path) const;
  void finish();  // computes checksum_ (the file's)

  int k_ = 0;
  int levels_ = 0;
  std::vector<Node> nodes_;
  std::vector<Word> words_;
  std::uint64_t checksum_ = 0;

  friend class VocabularyTrainer;
};

}  // namespace ale::place
