// FNV-1a 64: the checksum of the binary files ale-slam writes (the vocabulary, the map file).
// Not cryptographic: it catches truncation, bit rot and edits, not an adversary.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ale {

class Fnv1a64 {
 public:
  static constexpr std::uint64_t kOffsetBasis = 0xCBF29CE484222325ull;
  static constexpr std::uint64_t kPrime = 0x100000001B3ull;

  // Continues the hash over `size` more bytes.
  void update(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    std::uint64_t h = h_;
    for (std::size_t i = 0; i < size; ++i) {
      h ^= p[i];
      h *= kPrime;
    }
    h_ = h;
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = kOffsetBasis;
};

// FNV-1a 64 of `size` bytes.
inline std::uint64_t fnv1a64(const void* data, std::size_t size) {
  Fnv1a64 h;
  h.update(data, size);
  return h.value();
}

}  // namespace ale
