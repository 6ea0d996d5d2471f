// Seeded random numbers that give the same stream on every machine and standard library:
// splitmix64, with bounded integers and uniforms built from it by integer arithmetic only
// (the output of std::uniform_int_distribution and friends is implementation-defined).
#pragma once

#include <cstdint>

namespace ale {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

  // Uniform in [0, 1) with 24 bits.
  float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }

  // Uniform in [0, 1) with 53 bits.
  double uniform_double() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }

  // Uniform integer in [0, n) for n >= 1, without modulo bias (rejects the short top range).
  std::uint32_t below(std::uint32_t n) {
    const std::uint64_t limit = (UINT64_C(1) << 32) - ((UINT64_C(1) << 32) % n);
    std::uint64_t r;
    do {
      r = next() >> 32;
    } while (r >= limit);
    return static_cast<std::uint32_t>(r % n);
  }

  // Approximately standard normal: the Irwin-Hall sum of four 16-bit uniforms from one draw,
  // centred and scaled to unit variance. Tails stop at +-3.46 sigma, which is fine for sensor
  // noise and costs one draw per sample.
  float gaussian() {
    const std::uint64_t r = next();
    const std::uint32_t sum = static_cast<std::uint32_t>(r & 0xFFFFu) + static_cast<std::uint32_t>((r >> 16) & 0xFFFFu) +
                              static_cast<std::uint32_t>((r >> 32) & 0xFFFFu) + static_cast<std::uint32_t>(r >> 48);
    // sum / 65536 has mean 2 - 2/65536 and variance ~1/3.
    constexpr float kScale = 1.7320508f / 65536.0f;
    return (static_cast<float>(sum) - 131070.0f) * kScale;
  }

 private:
  std::uint64_t state_;
};

// A well-mixed 64-bit value from two inputs (e.g. a sequence seed and a frame index), so that
// streams for neighbouring indices are unrelated.
inline std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b) {
  SplitMix64 g(a ^ (b * 0xD1B54A32D192ED03ULL));
  g.next();
  return g.next();
}

}  // namespace ale
