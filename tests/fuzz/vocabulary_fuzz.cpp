// Vocabulary::parse() on arbitrary bytes (core/place/vocabulary.h). The input's first byte is a
// switch: bit 0 set, the file's checksum field (bytes 48..55 of the header) is replaced with the
// right one, so the fuzzer gets past the checksum to the tree checks; clear, the bytes are parsed
// as they are (the checksum check itself). A vocabulary that parses must then be usable: every
// descriptor finds a word and a node, the bag of words holds words of the vocabulary, and its own
// file parses back to the same checksum.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/place/vocabulary.h"

namespace {

constexpr std::size_t kChecksumOffset = 48;

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ale;
  if (size < 1) return 0;
  const bool fix_checksum = (data[0] & 1) != 0;
  std::vector<std::uint8_t> file(data + 1, data + size);
  if (fix_checksum && file.size() >= place::kVocabularyHeaderBytes) {
    const std::uint64_t sum = place::vocabulary_file_checksum(file.data(), file.size());
    std::memcpy(file.data() + kChecksumOffset, &sum, sizeof sum);  // little-endian host
  }
  Result<place::Vocabulary> parsed = place::Vocabulary::parse(file.data(), file.size());
  if (!parsed.ok()) return 0;
  const place::Vocabulary& v = *parsed;

  // Descriptors: all zeros, all ones, and slices of the file itself (they reach its nodes).
  std::vector<features::Descriptor> descriptors(4);
  std::memset(descriptors[1].bytes.data(), 0xff, descriptors[1].bytes.size());
  for (std::size_t i = 2; i < descriptors.size(); ++i)
    for (std::size_t b = 0; b < descriptors[i].bytes.size(); ++b)
      descriptors[i].bytes[b] = file[(i * 97 + b) % file.size()];
  for (int up = 0; up <= v.levels(); ++up) {
    for (const features::Descriptor& d : descriptors) {
      place::NodeId node = 0;
      const place::WordId w = v.word_of(d, up, &node);
      check(static_cast<int>(w) < v.num_words() && static_cast<int>(node) < v.num_nodes());
    }
    place::BowVector bow;
    place::FeatureVector fv;
    v.transform(descriptors.data(), static_cast<int>(descriptors.size()), bow, fv, up);
    for (const place::BowEntry& e : bow) check(static_cast<int>(e.word) < v.num_words());
    check(place::Vocabulary::score(bow, bow) >= 0.0);
  }
  const std::vector<std::uint8_t> again = v.serialize();
  Result<place::Vocabulary> reparsed = place::Vocabulary::parse(again.data(), again.size());
  check(reparsed.ok() && reparsed->checksum() == v.checksum());
  return 0;
}
