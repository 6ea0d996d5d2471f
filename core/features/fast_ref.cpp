// Scalar FAST-9: the specification the NEON path is tested against (definitions in fast.h).
#include <algorithm>

#include "core/features/fast.h"

namespace ale::features {

namespace internal {

void fast9_offsets(int stride, int offsets[16]) {
  for (int k = 0; k < 16; ++k) offsets[k] = kCircleDy[k] * stride + kCircleDx[k];
}

namespace {

// True when the 16-bit circular mask has 9 contiguous set bits.
inline bool has_arc9(unsigned mask) {
  unsigned m = mask | (mask << 16);
  unsigned run = m;
  for (int i = 1; i < 9; ++i) run &= m >> i;
  return run != 0;
}

}  // namespace

void fast9_row_ref(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                   std::vector<FastCorner>& corners) {
  int off[16];
  fast9_offsets(image.stride, off);
  const std::uint8_t* row = image.row(y);
  for (int x = x_begin; x < x_end; ++x) {
    const std::uint8_t* p = row + x;
    const int hi = p[0] + threshold;
    const int lo = p[0] - threshold;
    score_row[x] = 0;
    // An arc of 9 holds two neighbouring compass points (0-4, 4-8, 8-12 or 12-0).
    const int c0 = p[off[0]], c4 = p[off[4]], c8 = p[off[8]], c12 = p[off[12]];
    const bool b0 = c0 > hi, b4 = c4 > hi, b8 = c8 > hi, b12 = c12 > hi;
    const bool d0 = c0 < lo, d4 = c4 < lo, d8 = c8 < lo, d12 = c12 < lo;
    const bool maybe_bright = (b0 || b8) && (b4 || b12);
    const bool maybe_dark = (d0 || d8) && (d4 || d12);
    if (!maybe_bright && !maybe_dark) continue;
    unsigned bright = 0;
    unsigned dark = 0;
    for (int k = 0; k < 16; ++k) {
      const int v = p[off[k]];
      bright |= static_cast<unsigned>(v > hi) << k;
      dark |= static_cast<unsigned>(v < lo) << k;
    }
    if (!has_arc9(bright) && !has_arc9(dark)) continue;
    const int s = fast9_score_ref(p, image.stride);
    score_row[x] = static_cast<std::uint8_t>(s);
    corners.push_back({static_cast<std::int16_t>(x), static_cast<std::int16_t>(y), static_cast<std::uint8_t>(s)});
  }
}

int fast9_score_ref(const std::uint8_t* p, int stride) {
  int off[16];
  fast9_offsets(stride, off);
  const int centre = p[0];
  // d over 24 positions (the circle and its first 8 again), then sliding minima of width 9 by
  // doubling: 2, 4, 8, then 8 + 1.
  int d[24];
  for (int k = 0; k < 16; ++k) d[k] = p[off[k]] - centre;
  for (int k = 16; k < 24; ++k) d[k] = d[k - 16];
  int best = -255;
  for (int sign = 0; sign < 2; ++sign) {
    int v[24];
    for (int k = 0; k < 24; ++k) v[k] = sign == 0 ? d[k] : -d[k];
    int m2[23], m4[21], m8[17];
    for (int k = 0; k < 23; ++k) m2[k] = std::min(v[k], v[k + 1]);
    for (int k = 0; k < 21; ++k) m4[k] = std::min(m2[k], m2[k + 2]);
    for (int k = 0; k < 17; ++k) m8[k] = std::min(m4[k], m4[k + 4]);
    for (int k = 0; k < 16; ++k) best = std::max(best, std::min(m8[k], v[k + 8]));
  }
  return std::max(best - 1, 0);
}

}  // namespace internal

void fast9_nonmax(GrayView scores, const std::vector<FastCorner>& in, std::vector<FastCorner>& out) {
  for (const FastCorner& c : in) {
    const std::uint8_t* s = scores.row(c.y) + c.x;
    const std::uint8_t* up = s - scores.stride;
    const std::uint8_t* down = s + scores.stride;
    const int v = c.score;
    if (v > up[-1] && v > up[0] && v > up[1] && v > s[-1] && v > s[1] && v > down[-1] && v > down[0] &&
        v > down[1])
      out.push_back(c);
  }
}

}  // namespace ale::features
