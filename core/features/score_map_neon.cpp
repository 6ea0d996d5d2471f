// NEON FAST-9 score map, bit-exact with score_rect_ref() (see score_map.h), 16 pixels per vector.
//
// The kernel takes a whole cell, so its setup is paid once per cell, not per row. Most vectors
// stop at the compass test: one pointer walks c12, the centre, c4, c0 and c8 with post-incremented
// loads, 10 operations decide, and a rejected vector costs 23 instructions with its zero store
// and loop branch. A row's vectors, its overlapping last one included, share that loop body. A
// vector that passes is handed to score_store (out of line): the same test on the diagonal points
// c2, c6, c10, c14 rejects a quarter of them and settles the polarity of most of the rest (the
// other eight points as two more such tests cost more than they saved), then the vector is scored
// directly, without a separate 9-arc test: a lane is a corner exactly when its score passes the
// threshold, and on ARM the test cost as much as the score (both load and compare all 16 circle
// pixels). The score is the sliding arc extreme of the grey values (arc_extreme: 24
// post-incremented loads and 59 operations, at most 11 Q registers live; ARMv7 has 16, and both
// the earlier doubling and taking neighbouring arcs in pairs made GCC spill). A vector with
// candidates of both polarities but no lane that may be either is scored once, its
// darker-candidate lanes flipped (255 - v); the rest take two passes. The per-frame costs and
// their history are in docs/performance.md ("Kernels").
//
// A row's last vector overlaps the previous one instead of falling back to scalar code (it
// rewrites the same scores; its corners are taken only from the lanes not seen yet); a segment
// narrower than 16 pixels is one vector with its extra lanes masked (moved left at the image's
// right edge), or the reference when the image is narrower than 22 pixels.
#include "core/features/score_map.h"

#include "core/features/fast_neon_common.h"  // any_lane

#if defined(__ARM_NEON)

namespace ale::features::internal {

namespace {

// Which lanes' score a pass computes: kBright the brighter-arc score of every lane, kDark the
// darker one, kFlipped the brighter-arc score of 255 - v in the lanes of `flip` (their darker
// score) and of v elsewhere. Bright scores use the largest arc minimum of the grey values, dark ones
// the smallest arc maximum: a saturating difference with the centre is monotonic, so
// max_arc min_k (v_k - c) = (max_arc min_k v_k) - c and the differences need not be formed per
// circle pixel.
enum class Pass { kBright, kDark, kFlipped };

template <Pass P>
inline uint8x16_t inner(uint8x16_t a, uint8x16_t b) {
  return P == Pass::kDark ? vmaxq_u8(a, b) : vminq_u8(a, b);
}

template <Pass P>
inline uint8x16_t outer(uint8x16_t a, uint8x16_t b) {
  return P == Pass::kDark ? vminq_u8(a, b) : vmaxq_u8(a, b);
}

// The offset from circle pixel c_k to c_(k+1) (mod 16) in an image of row stride s. Only 8 values
// occur (1, s + 1, s, s - 1 and their negatives), which stay in core registers for a whole call.
inline int step(int k, int s) {
  return (kCircleDy[(k + 1) & 15] - kCircleDy[k]) * s + (kCircleDx[(k + 1) & 15] - kCircleDx[k]);
}

// The 16 bytes at p, advancing p by `advance`. On ARMv7 one vld1 with register post-increment: with
// plain intrinsics GCC gives every circle load its own address addition, or hoists all 16 circle
// addresses to the function entry and spills them. The asm's output p also stops GCC from keeping
// loaded circle vectors from one pass to the next (they would spill too).
inline uint8x16_t load_advance(const std::uint8_t*& p, int advance) {
#if defined(__arm__)
  uint8x16_t v;
  asm volatile("vld1.8 {%e0-%f0}, [%1], %2"
               : "=w"(v), "+r"(p)
               : "r"(advance), "m"(*reinterpret_cast<const std::uint8_t(*)[16]>(p)));
  return v;
#else
  const uint8x16_t v = vld1q_u8(p);
  p += advance;
  return v;
#endif
}

// Stores v at p and advances p by 16 (vst1 with post-increment on ARMv7).
inline void store_advance(std::uint8_t*& p, uint8x16_t v) {
#if defined(__arm__)
  asm volatile("vst1.8 {%e2-%f2}, [%0]!" : "+r"(p), "=m"(*reinterpret_cast<std::uint8_t(*)[16]>(p)) : "w"(v));
#else
  vst1q_u8(p, v);
  p += 16;
#endif
}

// The next circle pixel of pass P (see Pass), advancing p by `advance`.
template <Pass P>
inline uint8x16_t circle(const std::uint8_t*& p, int advance, uint8x16_t flip) {
  const uint8x16_t v = load_advance(p, advance);
  return P == Pass::kFlipped ? veorq_u8(v, flip) : v;
}

// The arc extreme (see Pass) over the 16 arcs of 9. An arc from c_k, k < 8, is the suffix c_k..c_7
// of the first half plus the prefix c_8..c_(k+8) of the second; one from c_(k+8) a suffix of the
// second half plus a prefix of the first. The 8 suffix extremes of a half are kept while the
// prefix extreme of the other runs along: 59 operations (the doubling over all 16 arcs took 80),
// at most 11 vectors live, the first half loaded twice. One pointer walks the circle: c_7 down to
// c_0, c_8 up to c_15, c_0 up to c_7.
template <Pass P>
inline uint8x16_t arc_extreme(const std::uint8_t* centre, int s, uint8x16_t flip) {
  const std::uint8_t* p = centre + kCircleDy[7] * s + kCircleDx[7];
  uint8x16_t suffix[8];
  suffix[7] = circle<P>(p, -step(6, s), flip);
  for (int k = 6; k >= 1; --k) suffix[k] = inner<P>(circle<P>(p, -step(k - 1, s), flip), suffix[k + 1]);
  suffix[0] = inner<P>(circle<P>(p, (kCircleDy[8] - kCircleDy[0]) * s, flip), suffix[1]);
  uint8x16_t second[8];
  second[0] = circle<P>(p, step(8, s), flip);
  uint8x16_t prefix = second[0];
  uint8x16_t best = inner<P>(suffix[0], prefix);
  for (int k = 1; k < 8; ++k) {
    second[k] = circle<P>(p, step(8 + k, s), flip);  // the last step leads back to c_0
    prefix = inner<P>(prefix, second[k]);
    best = outer<P>(best, inner<P>(suffix[k], prefix));
  }
  suffix[7] = second[7];
  for (int k = 6; k >= 0; --k) suffix[k] = inner<P>(second[k], suffix[k + 1]);
  prefix = circle<P>(p, step(0, s), flip);  // the first half again, rather than keep (spill) it
  best = outer<P>(best, inner<P>(suffix[0], prefix));
  for (int k = 1; k < 8; ++k) {
    prefix = inner<P>(prefix, circle<P>(p, step(k, s), flip));
    best = outer<P>(best, inner<P>(suffix[k], prefix));
  }
  return best;
}

// max over arcs of the smallest difference (c_k - c for brighter arcs, c - c_k for darker ones).
template <Pass P>
inline uint8x16_t arc_difference(const std::uint8_t* p, int s, uint8x16_t c, uint8x16_t flip) {
  const uint8x16_t e = arc_extreme<P>(p, s, flip);
  if (P == Pass::kDark) return vqsubq_u8(c, e);
  return vqsubq_u8(e, P == Pass::kFlipped ? veorq_u8(c, flip) : c);
}

// The compass test (fast_neon_common.h) split in two: a lane may have a brighter arc when
// bright_min = min(max(c0, c8), max(c4, c12)) > c + t, a darker one when
// dark_max = max(min(c0, c8), min(c4, c12)) < c - t.
struct CompassValues {
  uint8x16_t bright_min, dark_max;
};

inline CompassValues compass_values(uint8x16_t v0, uint8x16_t v4, uint8x16_t v8, uint8x16_t v12) {
  return {vminq_u8(vmaxq_u8(v0, v8), vmaxq_u8(v4, v12)), vmaxq_u8(vminq_u8(v0, v8), vminq_u8(v4, v12))};
}

// The compass test's loads of a vector walk one pointer q (see load_advance): c_12 (centre - 3),
// the centre, c_4, c_0, c_8, and on to the next vector's c_12, 16 pixels right. Five loads and no
// address arithmetic (sliding the centre row, one load and two vext, cost as much plus a copy).
struct CompassWalk {
  int across, up, down, next;
};

inline CompassWalk compass_walk(int s) {
  return {kFastRadius, -kFastRadius * s - kFastRadius, 2 * kFastRadius * s, 16 - kFastRadius - kFastRadius * s};
}

struct Candidates {
  uint8x16_t c;
  CompassValues cv;
};

inline Candidates load_candidates(const std::uint8_t*& q, CompassWalk w) {
#if defined(__arm__)
  // One asm statement: with five, GCC copied q to another register and back in every iteration.
  uint8x16_t v12, c, v4, v0, v8;
  asm volatile(
      "vld1.8 {%e0-%f0}, [%5], %6\n\t"
      "vld1.8 {%e1-%f1}, [%5], %6\n\t"
      "vld1.8 {%e2-%f2}, [%5], %7\n\t"
      "vld1.8 {%e3-%f3}, [%5], %8\n\t"
      "vld1.8 {%e4-%f4}, [%5], %9"
      : "=&w"(v12), "=&w"(c), "=&w"(v4), "=&w"(v0), "=w"(v8), "+r"(q)
      : "r"(w.across), "r"(w.up), "r"(w.down), "r"(w.next), "m"(*reinterpret_cast<const std::uint8_t(*)[16]>(q)));
#else
  const uint8x16_t v12 = load_advance(q, w.across);
  const uint8x16_t c = load_advance(q, w.across);
  const uint8x16_t v4 = load_advance(q, w.up);
  const uint8x16_t v0 = load_advance(q, w.down);
  const uint8x16_t v8 = load_advance(q, w.next);
#endif
  return {c, compass_values(v0, v4, v8, v12)};
}

// Whether some lane passes the compass test of either polarity (saturating differences: no lane
// passes where c + t or c - t saturates).
inline bool compass_any(uint8x16_t c, CompassValues cv, uint8x16_t t) {
  return any_lane(vcgtq_u8(vmaxq_u8(vqsubq_u8(cv.bright_min, c), vqsubq_u8(c, cv.dark_max)), t));
}

// The scores of the 16 candidates at p (0 where below the threshold), given that some lane passed
// the compass test; false (and no score) when no lane passes the diagonal test below. A lane is a
// corner exactly when its score passes the threshold, so there is no separate 9-arc test: on ARM
// it cost as much as the score (both load and compare all 16 circle pixels; measured 5.4 M
// against 4.8 M instructions per frame for test-then-score).
inline bool score_vector(const std::uint8_t* p, int s, uint8x16_t c, uint8x16_t bright_min, uint8x16_t dark_max,
                         uint8x16_t t, uint8x16_t& score) {
  // The same test on the diagonal points c2, c6, c10, c14 (every arc of 9 holds two neighbouring
  // ones as well) rejects about a quarter of these vectors and leaves 60 % fewer with lanes of
  // both polarities (normal frame: 26.3k vectors, 6.7k rejected, two passes 7.4k -> 2.8k) for
  // 4 loads and 8 operations; a lane needs both tests, so the two minima (maxima) merge.
  const std::uint8_t* q = p + kCircleDy[2] * s + kCircleDx[2];
  const uint8x16_t v2 = load_advance(q, (kCircleDy[6] - kCircleDy[2]) * s);
  const uint8x16_t v6 = load_advance(q, kCircleDx[10] - kCircleDx[6]);
  const uint8x16_t v10 = load_advance(q, (kCircleDy[14] - kCircleDy[10]) * s);
  const CompassValues diagonal = compass_values(v2, v6, v10, vld1q_u8(q));
  const uint8x16_t maybe_bright = vcgtq_u8(vminq_u8(bright_min, diagonal.bright_min), vqaddq_u8(c, t));
  const uint8x16_t maybe_dark = vcltq_u8(vmaxq_u8(dark_max, diagonal.dark_max), vqsubq_u8(c, t));
  const uint8x16_t zero = vdupq_n_u8(0);
  // Both any_lane answers in one fold: 4 instructions fewer per vector than one after the other.
  const auto halves = [](uint8x16_t v) { return vreinterpret_u32_u8(vorr_u8(vget_low_u8(v), vget_high_u8(v))); };
  const uint32x2_t folded = vpmax_u32(halves(maybe_bright), halves(maybe_dark));
  const bool any_bright = vget_lane_u32(folded, 0) != 0, any_dark = vget_lane_u32(folded, 1) != 0;
  if (!any_bright && !any_dark) return false;
  uint8x16_t best;
  if (!any_dark) {
    best = arc_difference<Pass::kBright>(p, s, c, zero);
  } else if (!any_bright) {
    best = arc_difference<Pass::kDark>(p, s, c, zero);
  } else if (!any_lane(vandq_u8(maybe_bright, maybe_dark))) {
    // Each lane may be a corner of one polarity only: score the darker candidates flipped.
    best = arc_difference<Pass::kFlipped>(p, s, c, maybe_dark);
  } else {
    // Some lane may be either (a diagonal edge: two neighbouring compass points brighter, the
    // other two darker): score both polarities (a pixel cannot be a corner of both).
    best = vmaxq_u8(arc_difference<Pass::kBright>(p, s, c, zero), arc_difference<Pass::kDark>(p, s, c, zero));
  }
  // score = best - 1 where best > t, else 0.
  score = vandq_u8(vsubq_u8(best, vdupq_n_u8(1)), vcgtq_u8(best, t));
  return true;
}

// Bit i set when lane i is non-zero.
inline unsigned lane_mask(uint8x16_t v) {
  static const std::uint8_t kBits[16] = {1, 2, 4, 8, 16, 32, 64, 128, 1, 2, 4, 8, 16, 32, 64, 128};
  const uint8x16_t b = vandq_u8(vtstq_u8(v, v), vld1q_u8(kBits));
  uint8x8_t m = vpadd_u8(vget_low_u8(b), vget_high_u8(b));
  m = vpadd_u8(m, m);
  m = vpadd_u8(m, m);
  return vget_lane_u16(vreinterpret_u16_u8(m), 0);
}

// Appends the corners of `score`, stored at `lanes` (the vector at (x, y)), whose lanes are in
// `lanes_mask`.
inline void emit(uint8x16_t score, const std::uint8_t* lanes, unsigned lanes_mask, int x, int y,
                 std::vector<FastCorner>& corners) {
  if (!any_lane(score)) return;
  const unsigned mask = lane_mask(score) & lanes_mask;
  if (mask != 0) append_lane_corners(mask, lanes, x, y, corners);
}

// What scoring a vector needs besides its registers.
struct RowJob {
  int s;  // image stride
  int y;
  int x_last;          // the row's last vector, which overlaps the one before
  unsigned last_mask;  // its lanes not emitted yet
  std::vector<FastCorner>* corners;
  // Where the vector's compass walk ended. Not an argument: in r0, GCC copied the walk pointer to
  // another register and back in every iteration of the compass loop.
  const std::uint8_t* walked;
};

// Scores the vector at column x whose compass walk ended at job.walked (see CompassWalk; its centre
// is 13 pixels left), stores the scores at out and appends its corners. Out of line, with its
// vectors in argument registers: the compass loop keeps its own registers.
__attribute__((noinline)) void score_store(uint8x16_t c, uint8x16_t bright_min, uint8x16_t dark_max, uint8x16_t t,
                                           std::uint8_t* out, int x, const RowJob& job) {
  const std::uint8_t* p = job.walked - (16 - kFastRadius);
  uint8x16_t score;
  if (!score_vector(p, job.s, c, bright_min, dark_max, t, score)) {
    vst1q_u8(out, vdupq_n_u8(0));
    return;
  }
  vst1q_u8(out, score);
  emit(score, out, x == job.x_last ? job.last_mask : 0xFFFFu, x, job.y, *job.corners);
}

}  // namespace

void score_rect_neon(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners) {
  const int x_begin = rect.x;
  const int x_end = rect.x + rect.width;
  const int y_end = rect.y + rect.height;
  const int s = image.stride;
  const uint8x16_t t = vdupq_n_u8(static_cast<std::uint8_t>(threshold));
  // The walk's steps as scalars, bundled per use: GCC kept a CompassWalk variable in memory and
  // reloaded it after every store.
  const CompassWalk steps = compass_walk(s);
  const int across = steps.across, up = steps.up, down = steps.down, next = steps.next;
  const auto walk = [=] { return CompassWalk{across, up, down, next}; };
  // A segment narrower than a vector (the last cell of a row) is one vector whose extra lanes are
  // neither stored nor emitted; at the right edge of the image that vector ends at the last pixel
  // with a whole circle, and its lanes before the segment are masked as well.
  if (x_end - x_begin < 16) {
    int x = x_begin;
    if (x_begin + 16 + kFastRadius > image.width) {
      x = image.width - kFastRadius - 16;
      if (x < kFastRadius) {
        score_rect_ref(image, rect, threshold, scores, corners);
        return;
      }
    }
    static const std::uint8_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    const uint8x16_t lane = vld1q_u8(kLane);
    const uint8x16_t keep = vandq_u8(vcgeq_u8(lane, vdupq_n_u8(static_cast<std::uint8_t>(x_begin - x))),
                                     vcltq_u8(lane, vdupq_n_u8(static_cast<std::uint8_t>(x_end - x))));
    const unsigned keep_mask = ((1u << (x_end - x)) - 1u) & ~((1u << (x_begin - x)) - 1u);
    RowJob job{s, rect.y, x, keep_mask, &corners, nullptr};
    for (; job.y < y_end; ++job.y) {
      const std::uint8_t* q = image.row(job.y) + x - kFastRadius;
      const Candidates k = load_candidates(q, walk());
      alignas(16) std::uint8_t score[16] = {};
      if (compass_any(k.c, k.cv, t)) {
        job.walked = q;
        score_store(k.c, k.cv.bright_min, k.cv.dark_max, t, score, x, job);
      }
      std::uint8_t* out = scores.row(job.y) + x;
      vst1q_u8(out, vbslq_u8(keep, vld1q_u8(score), vld1q_u8(out)));
    }
    return;
  }
  const uint8x16_t zero = vdupq_n_u8(0);
  const int x_last = x_end - 16;
  // Lanes of the last vector not emitted by the vector before it.
  const unsigned last_mask = 0xFFFFu & ~0u << ((x_last - x_begin) % 16 == 0 ? 0 : 16 - (x_last - x_begin) % 16);
  RowJob job{s, rect.y, x_last, last_mask, &corners, nullptr};
  for (; job.y < y_end; ++job.y) {
    const std::uint8_t* q = image.row(job.y) + x_begin - kFastRadius;
    const std::uint8_t* const q_last = q + (x_last - x_begin);
    std::uint8_t* const out_row = scores.row(job.y);
    std::uint8_t* out = out_row + x_begin;
    std::uint8_t* const out_last = out_row + x_last;
    // Vectors 16 pixels apart, the last one moved left to end with the segment (it overlaps the one
    // before); one loop body serves them all.
    for (;;) {
      const Candidates k = load_candidates(q, walk());
      // Most vectors stop here; telling GCC so favours this path in register allocation.
      if (!__builtin_expect(compass_any(k.c, k.cv, t), 0)) {
        store_advance(out, zero);
      } else {
        job.walked = q;
        score_store(k.c, k.cv.bright_min, k.cv.dark_max, t, out, static_cast<int>(out - out_row), job);
        out += 16;
      }
      if (out <= out_last) continue;
      if (out == out_last + 16) break;
      // Not q -= out - out_last: that made GCC copy q in every iteration.
      q = q_last;
      out = out_last;
    }
  }
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON
