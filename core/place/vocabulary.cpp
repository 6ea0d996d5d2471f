#include "core/place/vocabulary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/base/checksum.h"
#include "core/base/rng.h"

namespace ale::place {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the file is little-endian and read with memcpy");
static_assert(sizeof(features::Descriptor) == 32, "32-byte descriptors");

namespace {

constexpr std::size_t kDescriptorBytes = sizeof(features::Descriptor);

// Field offsets of the header.
constexpr std::size_t kOffVersion = 8, kOffHeaderBytes = 12, kOffK = 16, kOffLevels = 20, kOffNodes = 24,
                      kOffWords = 28, kOffDescriptorBytes = 32, kOffWeighting = 36, kOffPayloadBytes = 40,
                      kOffChecksum = 48, kOffReserved = 56;

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
void store(std::uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

Status corrupt(const std::string& why) { return corrupt_data("vocabulary: " + why); }

std::string hex64(std::uint64_t v) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::uint64_t payload_bytes(std::uint64_t nodes, std::uint64_t words) {
  return nodes * kVocabularyNodeBytes + words * kVocabularyWordBytes;
}

}  // namespace

std::uint64_t vocabulary_file_checksum(const std::uint8_t* file, std::size_t size) {
  if (size < kVocabularyHeaderBytes) return 0;
  Fnv1a64 h;
  h.update(file, kOffChecksum);
  h.update(file + kVocabularyHeaderBytes, size - kVocabularyHeaderBytes);
  return h.value();
}

// ---------------------------------------------------------------------------------------------
// Training: the tree is grown breadth first, so a node's children are consecutive and after it.

class VocabularyTrainer {
 public:
  VocabularyTrainer(const std::vector<features::Descriptor>& all, const VocabularyTrainParams& p)
      : all_(all), p_(p), rng_(p.seed) {}

  void build(Vocabulary& v) {
    v.k_ = p_.k;
    v.levels_ = p_.levels;
    order_.resize(all_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<std::uint32_t>(i);
    v.nodes_.assign(1, Vocabulary::Node{});
    // pending nodes: (node, first index into order_, end, depth)
    struct Pending {
      std::uint32_t node, begin, end;
      int depth;
    };
    std::vector<Pending> queue{{0, 0, static_cast<std::uint32_t>(order_.size()), 0}};
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Pending cur = queue[q];
      const std::uint32_t m = cur.end - cur.begin;
      cluster(cur.begin, m);
      const std::uint32_t first = static_cast<std::uint32_t>(v.nodes_.size());
      std::uint32_t start = cur.begin;
      for (std::size_t c = 0; c < centres_.size(); ++c) {
        const std::uint32_t size = sizes_[c];
        if (size == 0) continue;
        Vocabulary::Node child;
        child.descriptor = centres_[c];
        const std::uint32_t id = static_cast<std::uint32_t>(v.nodes_.size());
        v.nodes_.push_back(child);
        if (size > 1 && cur.depth + 1 < p_.levels) queue.push_back({id, start, start + size, cur.depth + 1});
        start += size;
      }
      v.nodes_[cur.node].first_child = first;
      v.nodes_[cur.node].count_or_word = static_cast<std::uint32_t>(v.nodes_.size()) - first;
    }
    // Words: the leaves in node order.
    for (std::uint32_t i = 1; i < v.nodes_.size(); ++i) {
      Vocabulary::Node& n = v.nodes_[i];
      if (n.first_child != 0) continue;
      n.count_or_word = static_cast<std::uint32_t>(v.words_.size());
      v.words_.push_back({i, 0.0f});
    }
  }

 private:
  // Clusters order_[begin, begin + m) into centres_ (k-majority, k-means++ seeding) and reorders
  // that range by cluster (sizes_ per centre). m <= k: each descriptor is a centre of its own.
  void cluster(std::uint32_t begin, std::uint32_t m) {
    std::uint32_t* idx = order_.data() + begin;
    centres_.clear();
    sizes_.clear();
    if (m <= static_cast<std::uint32_t>(p_.k)) {
      for (std::uint32_t i = 0; i < m; ++i) {
        centres_.push_back(all_[idx[i]]);
        sizes_.push_back(1);
      }
      return;
    }
    // k-means++: each next centre drawn with probability proportional to the squared distance
    // to the nearest centre so far.
    dist2_.assign(m, 0);
    centres_.push_back(all_[idx[rng_.below(m)]]);
    for (std::uint32_t i = 0; i < m; ++i) {
      const std::uint64_t d = static_cast<std::uint64_t>(features::hamming_distance(all_[idx[i]], centres_[0]));
      dist2_[i] = d * d;
    }
    while (centres_.size() < static_cast<std::size_t>(p_.k)) {
      std::uint64_t total = 0;
      for (std::uint64_t d : dist2_) total += d;
      if (total == 0) break;  // every descriptor sits on a centre already
      const std::uint64_t r = rng_.next() % total;
      std::uint64_t acc = 0;
      std::uint32_t pick = m - 1;
      for (std::uint32_t i = 0; i < m; ++i) {
        acc += dist2_[i];
        if (acc > r) {
          pick = i;
          break;
        }
      }
      centres_.push_back(all_[idx[pick]]);
      for (std::uint32_t i = 0; i < m; ++i) {
        const std::uint64_t d = static_cast<std::uint64_t>(features::hamming_distance(all_[idx[i]], centres_.back()));
        dist2_[i] = std::min(dist2_[i], d * d);
      }
    }
    const std::size_t k = centres_.size();
    assign_.assign(m, 0xFFFFFFFFu);
    for (int it = 0; it < p_.max_iterations; ++it) {
      bool changed = false;
      for (std::uint32_t i = 0; i < m; ++i) {
        std::uint32_t best = 0;
        int best_d = 1 << 30;
        for (std::size_t c = 0; c < k; ++c) {
          const int d = features::hamming_distance(all_[idx[i]], centres_[c]);
          if (d < best_d) {
            best_d = d;
            best = static_cast<std::uint32_t>(c);
          }
        }
        if (assign_[i] != best) changed = true;
        assign_[i] = best;
      }
      if (!changed) break;
      // Each centre becomes the bitwise majority of its members (a bit is set when more than
      // half of them have it); a centre without members keeps its place.
      counts_.assign(k * features::kDescriptorBits, 0);
      sizes_.assign(k, 0);
      for (std::uint32_t i = 0; i < m; ++i) {
        std::uint32_t* cnt = counts_.data() + assign_[i] * features::kDescriptorBits;
        const features::Descriptor& d = all_[idx[i]];
        for (int b = 0; b < features::kDescriptorBits; ++b) cnt[b] += (d.bytes[static_cast<std::size_t>(b >> 3)] >> (b & 7)) & 1u;
        ++sizes_[assign_[i]];
      }
      for (std::size_t c = 0; c < k; ++c) {
        if (sizes_[c] == 0) continue;
        features::Descriptor& out = centres_[c];
        out.bytes.fill(0);
        const std::uint32_t* cnt = counts_.data() + c * features::kDescriptorBits;
        for (int b = 0; b < features::kDescriptorBits; ++b) {
          if (2 * cnt[b] > sizes_[c]) out.bytes[static_cast<std::size_t>(b >> 3)] |= static_cast<std::uint8_t>(1u << (b & 7));
        }
      }
    }
    // Group the range by cluster (stable: members keep their order).
    sizes_.assign(k, 0);
    for (std::uint32_t i = 0; i < m; ++i) ++sizes_[assign_[i]];
    std::vector<std::uint32_t> start(k, 0);
    for (std::size_t c = 1; c < k; ++c) start[c] = start[c - 1] + sizes_[c - 1];
    tmp_.resize(m);
    for (std::uint32_t i = 0; i < m; ++i) tmp_[start[assign_[i]]++] = idx[i];
    std::copy(tmp_.begin(), tmp_.end(), idx);
  }

  const std::vector<features::Descriptor>& all_;
  VocabularyTrainParams p_;
  SplitMix64 rng_;
  std::vector<std::uint32_t> order_;
  std::vector<features::Descriptor> centres_;
  std::vector<std::uint32_t> sizes_;
  std::vector<std::uint64_t> dist2_;
  std::vector<std::uint32_t> assign_;
  std::vector<std::uint32_t> counts_;
  std::vector<std::uint32_t> tmp_;
};

Result<Vocabulary> Vocabulary::train(const std::vector<std::vector<features::Descriptor>>& images,
                                     const VocabularyTrainParams& params) {
  if (params.k < 2 || params.k > kMaxBranching)
    return invalid_argument("vocabulary: k = " + std::to_string(params.k) + " out of range 2.." + std::to_string(kMaxBranching));
  if (params.levels < 1 || params.levels > kMaxVocabularyLevels)
    return invalid_argument("vocabulary: levels = " + std::to_string(params.levels) + " out of range 1.." +
                            std::to_string(kMaxVocabularyLevels));
  if (params.max_iterations < 1) return invalid_argument("vocabulary: max_iterations must be at least 1");
  std::vector<features::Descriptor> all;
  for (const auto& im : images) all.insert(all.end(), im.begin(), im.end());
  if (all.empty()) return invalid_argument("vocabulary: no descriptors to train on");
  if (all.size() > 0xFFFFFFF0u) return invalid_argument("vocabulary: too many descriptors");

  Vocabulary v;
  VocabularyTrainer(all, params).build(v);
  if (v.nodes_.size() > kMaxVocabularyNodes)
    return invalid_argument("vocabulary: " + std::to_string(v.nodes_.size()) + " nodes exceed the limit of " +
                            std::to_string(kMaxVocabularyNodes) + ": lower k or levels");
  // IDF: the images whose descriptors reach each word (through the same descent transform uses).
  std::vector<std::uint32_t> images_with(v.words_.size(), 0);
  std::vector<std::uint32_t> last_image(v.words_.size(), 0xFFFFFFFFu);
  for (std::size_t i = 0; i < images.size(); ++i) {
    for (const features::Descriptor& d : images[i]) {
      const WordId w = v.word_of(d);
      if (last_image[w] != i) {
        last_image[w] = static_cast<std::uint32_t>(i);
        ++images_with[w];
      }
    }
  }
  const double n_images = static_cast<double>(images.size());
  for (std::size_t w = 0; w < v.words_.size(); ++w) {
    // A word no training descriptor reaches (its cluster moved) is as rare as can be.
    const double n = std::max<double>(1.0, images_with[w]);
    v.words_[w].weight = static_cast<float>(std::log(n_images / n));
  }
  v.finish();
  return v;
}

// ---------------------------------------------------------------------------------------------
// The file.

std::vector<std::uint8_t> Vocabulary::serialize() const {
  const std::size_t payload = static_cast<std::size_t>(payload_bytes(nodes_.size(), words_.size()));
  std::vector<std::uint8_t> out(kVocabularyHeaderBytes + payload, 0);
  std::memcpy(out.data(), kVocabularyMagic, sizeof kVocabularyMagic);
  std::uint8_t* h = out.data();
  store<std::uint32_t>(h + kOffVersion, kVocabularyFormatVersion);
  store<std::uint32_t>(h + kOffHeaderBytes, static_cast<std::uint32_t>(kVocabularyHeaderBytes));
  store<std::uint32_t>(h + kOffK, static_cast<std::uint32_t>(k_));
  store<std::uint32_t>(h + kOffLevels, static_cast<std::uint32_t>(levels_));
  store<std::uint32_t>(h + kOffNodes, static_cast<std::uint32_t>(nodes_.size()));
  store<std::uint32_t>(h + kOffWords, static_cast<std::uint32_t>(words_.size()));
  store<std::uint32_t>(h + kOffDescriptorBytes, static_cast<std::uint32_t>(kDescriptorBytes));
  store<std::uint32_t>(h + kOffWeighting, kWeightingTfIdf);
  store<std::uint64_t>(h + kOffPayloadBytes, payload);
  std::uint8_t* p = out.data() + kVocabularyHeaderBytes;
  for (const Node& n : nodes_) {
    std::memcpy(p, n.descriptor.bytes.data(), kDescriptorBytes);
    store<std::uint32_t>(p + 32, n.first_child);
    store<std::uint32_t>(p + 36, n.count_or_word);
    p += kVocabularyNodeBytes;
  }
  for (const Word& w : words_) {
    store<std::uint32_t>(p, w.node);
    store<float>(p + 4, w.weight);
    p += kVocabularyWordBytes;
  }
  store<std::uint64_t>(h + kOffChecksum, vocabulary_file_checksum(out.data(), out.size()));
  return out;
}

void Vocabulary::finish() {
  const std::vector<std::uint8_t> file = serialize();
  checksum_ = load<std::uint64_t>(file.data() + kOffChecksum);
}

Result<Vocabulary> Vocabulary::parse(const std::uint8_t* data, std::size_t size) {
  if (data == nullptr || size < kVocabularyHeaderBytes)
    return corrupt("truncated: " + std::to_string(size) + " bytes, the header alone is " +
                   std::to_string(kVocabularyHeaderBytes));
  if (std::memcmp(data, kVocabularyMagic, sizeof kVocabularyMagic) != 0)
    return corrupt("not a vocabulary file (the first 8 bytes are not \"ALEVOCAB\")");
  const std::uint32_t version = load<std::uint32_t>(data + kOffVersion);
  if (version != kVocabularyFormatVersion)
    return unsupported("vocabulary: format version " + std::to_string(version) + ", this build reads version " +
                       std::to_string(kVocabularyFormatVersion));
  const std::uint32_t header_bytes = load<std::uint32_t>(data + kOffHeaderBytes);
  if (header_bytes != kVocabularyHeaderBytes)
    return corrupt("header size " + std::to_string(header_bytes) + ", version 1 has " + std::to_string(kVocabularyHeaderBytes));
  const std::uint32_t k = load<std::uint32_t>(data + kOffK);
  const std::uint32_t levels = load<std::uint32_t>(data + kOffLevels);
  const std::uint32_t nodes = load<std::uint32_t>(data + kOffNodes);
  const std::uint32_t words = load<std::uint32_t>(data + kOffWords);
  const std::uint32_t descriptor_bytes = load<std::uint32_t>(data + kOffDescriptorBytes);
  const std::uint32_t weighting = load<std::uint32_t>(data + kOffWeighting);
  const std::uint64_t payload = load<std::uint64_t>(data + kOffPayloadBytes);
  const std::uint64_t checksum = load<std::uint64_t>(data + kOffChecksum);
  if (k < 2 || k > static_cast<std::uint32_t>(kMaxBranching))
    return corrupt("branching k = " + std::to_string(k) + " out of range 2.." + std::to_string(kMaxBranching));
  if (levels < 1 || levels > static_cast<std::uint32_t>(kMaxVocabularyLevels))
    return corrupt("levels = " + std::to_string(levels) + " out of range 1.." + std::to_string(kMaxVocabularyLevels));
  if (descriptor_bytes != kDescriptorBytes)
    return corrupt("descriptors of " + std::to_string(descriptor_bytes) + " bytes, ours have " + std::to_string(kDescriptorBytes));
  if (weighting != kWeightingTfIdf)
    return corrupt("weighting " + std::to_string(weighting) + " unknown (1: TF-IDF)");
  if (load<std::uint64_t>(data + kOffReserved) != 0) return corrupt("reserved header field is not 0");
  if (nodes < 2 || nodes > kMaxVocabularyNodes)
    return corrupt(std::to_string(nodes) + " nodes, out of range 2.." + std::to_string(kMaxVocabularyNodes));
  if (words < 1 || words >= nodes)
    return corrupt(std::to_string(words) + " words for " + std::to_string(nodes) + " nodes (1..nodes - 1)");
  if (payload != payload_bytes(nodes, words))
    return corrupt("payload length " + std::to_string(payload) + " bytes does not match " + std::to_string(nodes) +
                   " nodes and " + std::to_string(words) + " words (" + std::to_string(payload_bytes(nodes, words)) + ")");
  const std::size_t have = size - kVocabularyHeaderBytes;
  if (have < payload)
    return corrupt("truncated: the payload is " + std::to_string(payload) + " bytes, the buffer holds " + std::to_string(have));
  if (have > payload)
    return corrupt(std::to_string(have - payload) + " bytes after the payload (not a file this version wrote)");
  const std::uint8_t* p = data + kVocabularyHeaderBytes;
  const std::uint64_t actual = vocabulary_file_checksum(data, size);
  if (actual != checksum)
    return corrupt("checksum mismatch: the header says " + hex64(checksum) + ", the file has " + hex64(actual) +
                   " (the file is damaged)");

  // The counts are sane and the payload intact: now allocate and check the tree.
  Vocabulary v;
  v.k_ = static_cast<int>(k);
  v.levels_ = static_cast<int>(levels);
  v.checksum_ = checksum;
  v.nodes_.resize(nodes);
  v.words_.resize(words);
  for (Node& n : v.nodes_) {
    std::memcpy(n.descriptor.bytes.data(), p, kDescriptorBytes);
    n.first_child = load<std::uint32_t>(p + 32);
    n.count_or_word = load<std::uint32_t>(p + 36);
    p += kVocabularyNodeBytes;
  }
  for (Word& w : v.words_) {
    w.node = load<std::uint32_t>(p);
    w.weight = load<float>(p + 4);
    p += kVocabularyWordBytes;
  }
  // depth of each node (0xFF: not reached yet); every node but the root has exactly one parent.
  std::vector<std::uint8_t> depth(nodes, 0xFF);
  depth[0] = 0;
  if (v.nodes_[0].first_child == 0) return corrupt("the root has no children");
  for (std::uint32_t i = 0; i < nodes; ++i) {
    const Node& n = v.nodes_[i];
    if (depth[i] == 0xFF) return corrupt("node " + std::to_string(i) + " has no parent before it");
    if (n.first_child == 0) {
      if (i == 0) continue;
      if (n.count_or_word >= words) return corrupt("leaf " + std::to_string(i) + " names word " + std::to_string(n.count_or_word) + " of " + std::to_string(words));
      if (v.words_[n.count_or_word].node != i)
        return corrupt("word " + std::to_string(n.count_or_word) + " does not point back to its leaf " + std::to_string(i));
      continue;
    }
    const std::uint64_t end = static_cast<std::uint64_t>(n.first_child) + n.count_or_word;
    if (n.count_or_word < 1 || n.count_or_word > k || n.first_child <= i || end > nodes)
      return corrupt("node " + std::to_string(i) + " has children " + std::to_string(n.first_child) + " + " +
                     std::to_string(n.count_or_word) + ", outside " + std::to_string(i + 1) + ".." + std::to_string(nodes));
    if (depth[i] + 1u > levels) return corrupt("node " + std::to_string(i) + " is deeper than " + std::to_string(levels) + " levels");
    for (std::uint32_t c = n.first_child; c < end; ++c) {
      if (depth[c] != 0xFF) return corrupt("node " + std::to_string(c) + " has two parents");
      depth[c] = static_cast<std::uint8_t>(depth[i] + 1);
    }
  }
  for (std::uint32_t w = 0; w < words; ++w) {
    const Word& word = v.words_[w];
    if (word.node >= nodes || word.node == 0 || v.nodes_[word.node].first_child != 0 || v.nodes_[word.node].count_or_word != w)
      return corrupt("word " + std::to_string(w) + " points to node " + std::to_string(word.node) + ", not its leaf");
    if (!std::isfinite(word.weight) || word.weight < 0.0f)
      return corrupt("word " + std::to_string(w) + " has weight " + std::to_string(word.weight) + " (finite, >= 0)");
  }
  return v;
}

std::size_t Vocabulary::memory_bytes() const {
  return nodes_.capacity() * sizeof(Node) + words_.capacity() * sizeof(Word);
}

// ---------------------------------------------------------------------------------------------
// Use.

int Vocabulary::descend(const features::Descriptor& d, NodeId* path) const {
  NodeId cur = 0;
  int depth = 0;
  path[0] = 0;
  const features::HammingKernel hamming = features::hamming_kernel();
  while (nodes_[cur].first_child != 0) {
    const Node& n = nodes_[cur];
    NodeId best = n.first_child;
    int best_d = 1 << 30;
    for (NodeId c = n.first_child; c < n.first_child + n.count_or_word; ++c) {
      const int dist = hamming(d, nodes_[c].descriptor);
      if (dist < best_d) {
        best_d = dist;
        best = c;
      }
    }
    cur = best;
    path[++depth] = cur;
  }
  return depth;
}

WordId Vocabulary::word_of(const features::Descriptor& d, int fv_levels_up, NodeId* node_out) const {
  std::array<NodeId, kMaxVocabularyLevels + 1> path;
  const int depth = descend(d, path.data());
  if (node_out != nullptr) {
    const int up = std::max(0, levels_ - std::max(0, fv_levels_up));
    *node_out = path[static_cast<std::size_t>(std::min(depth, up))];
  }
  return nodes_[path[static_cast<std::size_t>(depth)]].count_or_word;
}

void Vocabulary::transform(const features::Descriptor* d, int n, BowVector& bow, FeatureVector& fv,
                           int fv_levels_up) const {
  bow.clear();
  fv.clear();
  if (nodes_.empty() || d == nullptr) return;
  for (int i = 0; i < n; ++i) {
    NodeId node = 0;
    const WordId w = word_of(d[i], fv_levels_up, &node);
    fv.push_back({node, static_cast<std::uint32_t>(i)});
    const float weight = words_[w].weight;
    if (weight > 0.0f) bow.push_back({w, weight});  // a word in every training image says nothing
  }
  std::sort(bow.begin(), bow.end(), [](const BowEntry& a, const BowEntry& b) { return a.word < b.word; });
  std::size_t out = 0;
  double total = 0.0;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    total += bow[i].weight;
    if (out > 0 && bow[out - 1].word == bow[i].word) {
      bow[out - 1].weight += bow[i].weight;
    } else {
      bow[out++] = bow[i];
    }
  }
  bow.resize(out);
  if (total > 0.0) {
    const float inv = static_cast<float>(1.0 / total);
    for (BowEntry& e : bow) e.weight *= inv;
  }
  std::sort(fv.begin(), fv.end(), [](const NodeFeature& a, const NodeFeature& b) {
    return a.node != b.node ? a.node < b.node : a.feature < b.feature;
  });
}

double Vocabulary::score(const BowVector& a, const BowVector& b) {
  // With both L1-normalised, 1 - |a - b|_1 / 2 is the sum over shared words of the smaller weight.
  double s = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i].word < b[j].word) {
      ++i;
    } else if (b[j].word < a[i].word) {
      ++j;
    } else {
      s += std::min(a[i].weight, b[j].weight);
      ++i;
      ++j;
    }
  }
  return std::min(1.0, s);
}

}  // namespace ale::place
