// The feature tests' synthetic image: blobs and steps ((x/5 + y/4) mod 3 levels 90 apart), uniform
// noise of +-noise_amp and one pixel in ten saturated (0 or 255), the same for a seed on every
// machine. Written into a view, so each test keeps its own buffer, stride and padding.
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>

#include "core/base/image.h"

namespace ale::test {

inline void fill_blobs(MutableGrayView view, std::uint32_t seed, int noise_amp) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-noise_amp, noise_amp);
  std::uniform_int_distribution<int> spot(0, 9);
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      int v = ((x / 5 + y / 4) % 3) * 90 + noise(rng);
      const int r = spot(rng);
      if (r == 0) v = 0;
      if (r == 1) v = 255;
      view.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  }
}

}  // namespace ale::test
