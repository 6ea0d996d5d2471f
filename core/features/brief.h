// Orientation by intensity centroid and 256-bit rotated BRIEF (spec section 6).
//
// The sampling pattern is ours, generated at start-up by a documented, seeded procedure with
// integer arithmetic only (so host and ARM builds get the same pattern bit for bit):
// - 256 pairs of points (x1, y1), (x2, y2), every coordinate drawn independently from an isotropic
//   Gaussian with sigma = S / 5 for the patch size S = 31 (sigma^2 = S^2 / 25, the distribution the
//   BRIEF paper found best), rounded to the nearest integer;
// - a point outside the disk of radius kPatchRadius is redrawn, and so is a pair of two equal points;
// - the Gaussian comes from the sum of 12 uniform 16-bit numbers (Irwin-Hall, mean 6, variance 1),
//   the uniforms from splitmix64 seeded with kPatternSeed.
// Rotation: the pattern is pre-rotated for kAngleBins orientations (rounded to whole pixels) into
// offsets for one row stride, so a descriptor costs 512 byte loads and 256 compares: the
// reference in C (brief_ref.cpp), the armhf kernel in Thumb-2 assembly (brief_neon.cpp: per bit
// half an ldrd of the pair's offsets, two byte loads, cmp, and adc shifting the carry in).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/base/image.h"
#include "core/base/kernel_path.h"

namespace ale::features {

constexpr int kPatchRadius = 15;  // orientation patch and sampling disk (ORB's HALF_PATCH_SIZE)
constexpr int kDescriptorBits = 256;
constexpr int kAngleBins = 64;    // 5.625 degrees per bin
constexpr std::uint64_t kPatternSeed = 0x414C452D4252494Full;  // "ALE-BRIEF"

struct Descriptor {
  std::array<std::uint8_t, kDescriptorBits / 8> bytes{};  // bit j of byte i: pair 8 i + j
};

// The number of bits in which a and b differ. Kernels (the matcher calls this per candidate): the
// reference counts each 32-bit word's bits by SWAR additions (hamming_ref.cpp; on ARMv7
// __builtin_popcountll is a call to libgcc's __popcountdi2 per 64-bit word), NEON by vcnt on the
// two 16-byte halves and pairwise sums (hamming_neon.cpp).
int hamming_distance(const Descriptor& a, const Descriptor& b, KernelPath path = KernelPath::kAuto);
// The kernel hamming_distance(a, b, path) calls, for a search that takes it once and calls it per
// candidate (one indirect call instead of a call and an indirect call: the dispatching call costs
// about 14 ARM instructions a distance).
using HammingKernel = int (*)(const Descriptor& a, const Descriptor& b);
HammingKernel hamming_kernel(KernelPath path = KernelPath::kAuto);

struct BriefPattern {
  // 2 * kDescriptorBits points: pair i is points 2 i and 2 i + 1.
  std::array<std::int8_t, 4 * kDescriptorBits> xy{};  // x0, y0, x1, y1, ...
};

// The pattern described above.
BriefPattern make_brief_pattern(std::uint64_t seed = kPatternSeed);

// Pre-rotated sample offsets for one row stride.
class RotatedPattern {
 public:
  void build(const BriefPattern& pattern, int stride);
  int stride() const { return stride_; }
  // Offsets (row * stride + column) of the 2 * kDescriptorBits samples for angle bin `bin`, in
  // describe()'s order: per 32-bit word w of the descriptor, the pairs 32 w + 31 down to 32 w, each
  // as (first point, second point).
  const std::int32_t* offsets(int bin) const {
    return table_.data() + static_cast<std::size_t>(bin) * 2u * kDescriptorBits;
  }

 private:
  int stride_ = 0;
  std::vector<std::int32_t> table_;
};

// Intensity-centroid angle in degrees [0, 360) of the disk of radius kPatchRadius around (x, y);
// the disk must lie inside the image.
float ic_angle_deg(GrayView image, int x, int y);

// The angle bin of an angle in degrees.
int angle_bin(float angle_deg);

// BRIEF bits of the (smoothed) image around (x, y), pattern rotated by bin `bin`; the rotated
// pattern must lie inside the image (kPatchRadius + 2 pixels from every border is enough).
void describe(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out,
              KernelPath path = KernelPath::kAuto);

namespace internal {
// hamming_distance()'s kernels.
int hamming_ref(const Descriptor& a, const Descriptor& b);
int hamming_neon(const Descriptor& a, const Descriptor& b);

// describe()'s kernels.
void describe_ref(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out);
void describe_neon(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out);

// The descriptor from a kernel's word: not_less_word(centre, p) returns the "first >= second" bits
// of the next 32 pairs at p (the first pair in the most significant bit) and advances p past them.
template <typename NotLessWord>
inline void describe_words(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out,
                           NotLessWord not_less_word) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "descriptor words are stored little-endian");
  static_assert(kDescriptorBits % 32 == 0, "whole 32-bit words");
  const std::uint8_t* centre = smoothed.row(y) + x;
  const std::int32_t* p = rotated.offsets(bin);
  for (int w = 0; w < kDescriptorBits / 32; ++w) {
    // The table lists a word's pairs last first, so pair 32 w + k lands on bit k; the bits are
    // "not less", hence the complement.
    const std::uint32_t bits = ~not_less_word(centre, p);
    std::memcpy(out.bytes.data() + 4 * w, &bits, 4);
  }
}
}  // namespace internal

}  // namespace ale::features
