// The renderer's random numbers: the project's seeded splitmix64 (core/base/rng.h) and a hash
// of lattice coordinates for value noise.
#pragma once

#include <cstdint>

#include "core/base/rng.h"

namespace ale::render {

using ale::mix_seed;
using ale::SplitMix64;

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
