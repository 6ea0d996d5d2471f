// Synthetic descriptors for the place-recognition tests: "places" are sets of prototype
// descriptors, and an image of a place draws its descriptors from the prototypes with a few
// bits flipped (the noise of seeing the same corner again).
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "core/base/rng.h"
#include "core/features/brief.h"
#include "core/place/vocabulary.h"

namespace ale::place::fixtures {

inline features::Descriptor random_descriptor(SplitMix64& rng) {
  features::Descriptor d;
  for (std::uint8_t& b : d.bytes) b = static_cast<std::uint8_t>(rng.next() >> 56);
  return d;
}

// d with `bits` distinct random bits flipped.
inline features::Descriptor flipped(const features::Descriptor& d, int bits, SplitMix64& rng) {
  features::Descriptor out = d;
  for (int k = 0; k < bits; ++k) {
    const std::uint32_t bit = rng.below(features::kDescriptorBits);
    out.bytes[bit >> 3] = static_cast<std::uint8_t>(out.bytes[bit >> 3] ^ (1u << (bit & 7)));
  }
  return out;
}

// `places` places of `per_place` prototypes each.
struct World {
  std::vector<std::vector<features::Descriptor>> prototypes;
  World(int places, int per_place, std::uint64_t seed) {
    SplitMix64 rng(seed);
    prototypes.resize(static_cast<std::size_t>(places));
    for (auto& p : prototypes)
      for (int i = 0; i < per_place; ++i) p.push_back(random_descriptor(rng));
  }
  // An image of place p: every prototype once, each with `noise_bits` bits flipped.
  std::vector<features::Descriptor> image(int p, int noise_bits, std::uint64_t seed) const {
    SplitMix64 rng(seed);
    std::vector<features::Descriptor> out;
    for (const features::Descriptor& d : prototypes[static_cast<std::size_t>(p)]) out.push_back(flipped(d, noise_bits, rng));
    return out;
  }
  // Two images of every place: the training set.
  std::vector<std::vector<features::Descriptor>> training(int noise_bits) const {
    std::vector<std::vector<features::Descriptor>> out;
    for (int p = 0; p < static_cast<int>(prototypes.size()); ++p) {
      for (int k = 0; k < 2; ++k) out.push_back(image(p, noise_bits, 1000u + 2u * static_cast<unsigned>(p) + static_cast<unsigned>(k)));
    }
    return out;
  }
};

// A vocabulary of k = 6, L = 3 trained on a world of 8 places x 40 prototypes.
inline Vocabulary small_vocabulary(const World& w, std::uint64_t seed = 3) {
  VocabularyTrainParams p;
  p.k = 6;
  p.levels = 3;
  p.seed = seed;
  Result<Vocabulary> v = Vocabulary::train(w.training(6), p);
  EXPECT_TRUE(v.ok()) << v.status().to_string();
  return v.ok() ? std::move(*v) : Vocabulary{};
}

}  // namespace ale::place::fixtures
