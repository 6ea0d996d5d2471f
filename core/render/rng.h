// The renderer's own random numbers: splitmix64 and a Gaussian built from it with integer
// arithmetic only, so a seed gives the same frames with any standard library (the output of
// std::normal_distribution is implementation-defined).
#pragma once

#include <cstdint>

namespace ale::render {

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

  // Approximately standard normal: the Irwin-Hall sum of four 16-bit uniforms from one draw,
  // centred and scaled to unit variance. Tails stop at +-3.46 sigma, which is fine for sensor
  // noise and costs one draw per pixel.
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

// A well-mixed 64-bit value from two inputs (e.g. the sequence seed and a frame index), so that
// streams for neighbouring indices are unrelated.
inline std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b) {
  SplitMix64 g(a ^ (b * 0xD1B54A32D192ED03ULL));
  g.next();
  return g.next();
}

// A 32-bit hash of integer lattice coordinates, for value noise.
inline std::uint32_t hash_2d(std::int32_t x, std::int32_t y, std::uint32_t seed) {
  std::uint32_t h = seed * 0x9E3779B1u;
  h ^= static_cast<std::uint32_t>(x) * 0x85EBCA6Bu;
  h = (h ^ (h >> 15)) * 0xC2B2AE35u;
  h ^= static_cast<std::uint32_t>(y) * 0x27D4EB2Fu;
  h = (h ^ (h >> 13)) * 0x165667B1u;
  return h ^ (h >> 16);
}

}  // namespace ale::render
