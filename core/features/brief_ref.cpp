// BRIEF bits in C: the specification brief_neon.cpp reproduces (brief.h).
#include "core/features/brief.h"

namespace ale::features::internal {

void describe_ref(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out) {
  describe_words(smoothed, x, y, rotated, bin, out, [](const std::uint8_t* centre, const std::int32_t*& p) {
    std::uint32_t acc = 0;
    for (int k = 0; k < 32; ++k, p += 2) acc = acc + acc + static_cast<std::uint32_t>(centre[p[0]] >= centre[p[1]]);
    return acc;
  });
}

}  // namespace ale::features::internal
