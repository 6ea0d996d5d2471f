#include "core/features/brief.h"

#include <cmath>
#include <cstring>

namespace ale::features {

namespace {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// round(N(0,1) * sigma) with sigma = 31/5, from 12 uniforms in Q16.
int gaussian_coordinate(std::uint64_t& state) {
  std::int64_t sum = 0;
  for (int i = 0; i < 12; ++i) sum += static_cast<std::int64_t>(splitmix64(state) >> 48);
  const std::int64_t z_q16 = sum - 6 * 65536;  // N(0, 1) * 2^16, approximately
  const std::int64_t scaled = z_q16 * 31;       // * sigma * 5 * 2^16
  const std::int64_t denom = 5 * 65536;
  const std::int64_t half = denom / 2;
  return static_cast<int>(scaled >= 0 ? (scaled + half) / denom : -((-scaled + half) / denom));
}

}  // namespace

int hamming_distance(const Descriptor& a, const Descriptor& b) {
  int d = 0;
  for (std::size_t i = 0; i < a.bytes.size(); i += 8) {
    std::uint64_t x = 0;
    std::uint64_t y = 0;
    std::memcpy(&x, a.bytes.data() + i, 8);
    std::memcpy(&y, b.bytes.data() + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

BriefPattern make_brief_pattern(std::uint64_t seed) {
  BriefPattern p;
  std::uint64_t state = seed;
  const auto draw_point = [&](int& x, int& y) {
    do {
      x = gaussian_coordinate(state);
      y = gaussian_coordinate(state);
    } while (x * x + y * y > kPatchRadius * kPatchRadius);
  };
  for (int i = 0; i < kDescriptorBits; ++i) {
    int x0, y0, x1, y1;
    do {
      draw_point(x0, y0);
      draw_point(x1, y1);
    } while (x0 == x1 && y0 == y1);
    const std::size_t k = static_cast<std::size_t>(i) * 4u;
    p.xy[k] = static_cast<std::int8_t>(x0);
    p.xy[k + 1] = static_cast<std::int8_t>(y0);
    p.xy[k + 2] = static_cast<std::int8_t>(x1);
    p.xy[k + 3] = static_cast<std::int8_t>(y1);
  }
  return p;
}

void RotatedPattern::build(const BriefPattern& pattern, int stride) {
  stride_ = stride;
  table_.resize(static_cast<std::size_t>(kAngleBins) * 2u * kDescriptorBits);
  for (int bin = 0; bin < kAngleBins; ++bin) {
    const double a = 2.0 * M_PI * bin / kAngleBins;
    const double c = std::cos(a);
    const double s = std::sin(a);
    const auto offset = [&](int point) {
      const double x = pattern.xy[static_cast<std::size_t>(2 * point)];
      const double y = pattern.xy[static_cast<std::size_t>(2 * point + 1)];
      const int rx = static_cast<int>(std::lround(x * c - y * s));
      const int ry = static_cast<int>(std::lround(x * s + y * c));
      return ry * stride + rx;
    };
    std::int32_t* out = table_.data() + static_cast<std::size_t>(bin) * 2u * kDescriptorBits;
    for (int word = 0; word < kDescriptorBits / 32; ++word) {
      for (int k = 31; k >= 0; --k) {
        const int pair = 32 * word + k;
        *out++ = offset(2 * pair);
        *out++ = offset(2 * pair + 1);
      }
    }
  }
}

// ic_angle_deg(): orientation_ref.cpp.

int angle_bin(float angle_deg) {
  int bin = static_cast<int>(std::lround(static_cast<double>(angle_deg) * kAngleBins / 360.0));
  bin %= kAngleBins;
  return bin < 0 ? bin + kAngleBins : bin;
}

namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "descriptor words are stored little-endian");
static_assert(kDescriptorBits % 32 == 0, "whole 32-bit words");

#if defined(__thumb2__)
// Four bits: per pair two byte loads at (centre + offset), cmp (carry = first >= second) and
// adc acc, acc, acc (acc = 2 acc + carry): 5 instructions per bit, where the C loop below costs
// about 10 (GCC shifts, compares and adds the carry under an IT block). Two pairs are loaded ahead
// of their compares so the in-order Cortex-A7 does not wait on each byte load.
#define ALE_BRIEF_TWO_BITS                          \
  "ldrd %[a0], %[b0], [%[p]], #8\n\t"              \
  "ldrd %[a1], %[b1], [%[p]], #8\n\t"              \
  "ldrb %[a0], [%[c], %[a0]]\n\t"                  \
  "ldrb %[b0], [%[c], %[b0]]\n\t"                  \
  "ldrb %[a1], [%[c], %[a1]]\n\t"                  \
  "ldrb %[b1], [%[c], %[b1]]\n\t"                  \
  "cmp %[a0], %[b0]\n\t"                           \
  "adc %[acc], %[acc], %[acc]\n\t"                 \
  "cmp %[a1], %[b1]\n\t"                           \
  "adc %[acc], %[acc], %[acc]\n\t"

inline std::uint32_t not_less_word(const std::uint8_t* centre, const std::int32_t*& p) {
  std::uint32_t acc = 0;
  for (int k = 0; k < 4; ++k) {
    std::uint32_t a0, b0, a1, b1;
    asm(ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS
        : [acc] "+r"(acc), [p] "+r"(p), [a0] "=&r"(a0), [b0] "=&r"(b0), [a1] "=&r"(a1), [b1] "=&r"(b1)
        : [c] "r"(centre)
        : "cc", "memory");
  }
  return acc;
}
#undef ALE_BRIEF_TWO_BITS
#else
inline std::uint32_t not_less_word(const std::uint8_t* centre, const std::int32_t*& p) {
  std::uint32_t acc = 0;
  for (int k = 0; k < 32; ++k, p += 2) acc = acc + acc + static_cast<std::uint32_t>(centre[p[0]] >= centre[p[1]]);
  return acc;
}
#endif

}  // namespace

void describe(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out) {
  const std::uint8_t* centre = smoothed.row(y) + x;
  const std::int32_t* p = rotated.offsets(bin);
  for (int w = 0; w < kDescriptorBits / 32; ++w) {
    // The table lists a word's pairs last first, so pair 32 w + k lands on bit k; the carry is
    // "not less", hence the complement.
    const std::uint32_t bits = ~not_less_word(centre, p);
    std::memcpy(out.bytes.data() + 4 * w, &bits, 4);
  }
}

}  // namespace ale::features
